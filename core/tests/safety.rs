//! Safety distances: zero wrong rays against the `f64` exact traversal, in `f32` and
//! `f64`, directional and isotropic, on synthetic fields; and an independent check of
//! the bake (dense rays inside each claimed safety distance must not leave the solid),
//! which is shown to fail on a bake inflated by one.
#![cfg(feature = "safety")]

mod common;

use common::{
    assert_rows_rebake, breakpoints, check_bakes, class_axis, judge_trace, march_fields,
    rays_with_grazing, rows_field, Field, Probe, RaySpec, Rng, Tally,
};
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, MarchSurface, Options, SafetyMap, Variant, CLASSES};
use hfcast::{dda, Flags, Marcher, Query, Real, Surface};

const TRI: Surface = Surface::Triangles;
const VL: Surface = Surface::ViewLinear;
/// The maps' march on the triangle surface they are baked for.
const TRI_MARCH: MarchSurface = MarchSurface::Triangles;

/// The synthetic fields of the brief.
fn fields() -> Vec<(String, Field)> {
    march_fields(0x5afe, 7, ("checkerboard 24x20", 0.0, 1.0), Vec::new(), 12)
}

fn bake(field: &Field, opts: Options) -> Vec<u8> {
    let hf = field.hf();
    let mut scratch = vec![0f32; safety::scratch_len(field.w, field.h)];
    let mut out = vec![0u8; safety::map_len(field.w, field.h, opts.variant)];
    safety::bake(&hf, &mut scratch, opts, &mut out).unwrap();
    out
}

fn bake_cc(field: &Field, opts: CcOptions) -> Vec<u8> {
    let hf = field.hf();
    let mut scratch = vec![0f32; safety::scratch_len(field.w, field.h)];
    let mut nb = vec![0f32; cc::nbuffer_len(field.w, field.h, opts.cap)];
    let mut out = vec![0u8; cc::map_len(field.w, field.h)];
    cc::bake(&hf, &mut scratch, &mut nb, opts, &mut out).unwrap();
    out
}

/// One field's rays, traced with every map and judged.
struct Rays<'a> {
    name: &'a str,
    field: &'a Field,
    specs: Vec<RaySpec>,
}

impl<'a> Rays<'a> {
    /// `per_kind[0]` rays of every kind and class on fields of more than 200 samples,
    /// `per_kind[1]` on the others, plus twice as many grazing rays down to 1e-4 rad,
    /// starting above the surface ([`rays_with_grazing`]).
    fn new(name: &'a str, field: &'a Field, rng: &mut Rng, per_kind: [usize; 2]) -> Rays<'a> {
        let per_kind = if field.w * field.h > 200 {
            per_kind[0]
        } else {
            per_kind[1]
        };
        Rays {
            name,
            field,
            specs: rays_with_grazing(field, TRI, rng, per_kind),
        }
    }

    /// Traces every ray with `m` in precision `R` and judges it on `surface`: the
    /// tally `name`.
    fn run<R: Real>(&self, name: &str, surface: Surface, m: &Marcher) -> Tally {
        let field = self.field;
        let hf = field.hf();
        let zs = field.z_scale();
        let mut t = Tally::new(name);
        for s in &self.specs {
            let q = s.query::<R>();
            let got = m.trace(&hf, &q);
            assert!(
                !got.flags.contains(Flags::BUDGET_EXHAUSTED),
                "{name}: budget"
            );
            t.tried += 1;
            t.hits += u64::from(got.hit.is_some());
            match judge_trace(field, surface, &got, &q, zs) {
                None => t.ambiguous += 1,
                Some(true) => {}
                Some(false) => t.wrong(|| {
                    let o = dda::trace(&hf, surface, &q.cast::<f64>());
                    format!("{q:?} got {:?} oracle {:?}", got.hit, o.hit)
                }),
            }
        }
        t
    }

    /// [`Rays::run`] in `f32` and in `f64`: the tallies "`name` `what` f32" and
    /// "`name` `what` f64".
    fn both(&self, what: &str, surface: Surface, m: &Marcher) -> [Tally; 2] {
        let name = |p: &str| format!("{} {what} {p}", self.name);
        [
            self.run::<f32>(&name("f32"), surface, m),
            self.run::<f64>(&name("f64"), surface, m),
        ]
    }
}

#[test]
fn zero_wrong_rays() {
    let mut rng = Rng::new(42);
    let mut out = String::new();
    let mut wrong = 0;
    let mut positive_wrong = 0;
    let mut positive_tried = 0;
    for (name, field) in fields() {
        let hf = field.hf();
        let rays = Rays::new(&name, &field, &mut rng, [400, 60]);
        let mut tallies = Vec::new();
        for variant in [Variant::Directional, Variant::Isotropic] {
            let opts = Options {
                variant,
                ..Options::default()
            };
            let data = bake(&field, opts);
            let m = Marcher::Safety(SafetyMap::new(&hf, &data, variant).unwrap(), TRI_MARCH);
            tallies.extend(rays.both(&format!("{variant:?}"), TRI, &m));
        }
        for slope in [Slope::Exact, Slope::NBuffer] {
            let opts = CcOptions {
                slope,
                ..CcOptions::default()
            };
            let data = bake_cc(&field, opts);
            let m = Marcher::Cc(CcMap::new(&hf, &data, opts.cap).unwrap(), TRI_MARCH);
            tallies.extend(rays.both(&format!("CC {slope:?}"), TRI, &m));
        }
        for t in &tallies {
            wrong += t.wrong;
            t.report(&mut out);
        }
        // The strictly positive variant: approximate; its silhouette errors measured.
        let opts = Options {
            positive: true,
            ..Options::default()
        };
        let data = bake(&field, opts);
        let m = Marcher::Safety(SafetyMap::new(&hf, &data, opts.variant).unwrap(), TRI_MARCH);
        let t = rays.run::<f32>(&format!("{name} positive f32 (approximate)"), TRI, &m);
        positive_wrong += t.wrong;
        positive_tried += t.tried;
    }
    println!("{out}");
    println!(
        "strictly positive variant (approximate): {positive_wrong} wrong of {positive_tried} rays"
    );
    assert_eq!(wrong, 0, "wrong rays");
}

/// §7: the maps baked for the triangle surface, marched to the view-linear surface,
/// against the exact `f64` traversal of that surface.
#[test]
fn view_linear_zero_wrong_rays() {
    let mut rng = Rng::new(7);
    let mut out = String::new();
    let (mut wrong, mut tried, mut triangles_wrong) = (0, 0, 0);
    let vl = MarchSurface::ViewLinear;
    for (name, field) in fields() {
        let hf = field.hf();
        let rays = Rays::new(&name, &field, &mut rng, [200, 40]);
        let sd = bake(&field, Options::default());
        let sd = SafetyMap::new(&hf, &sd, Variant::Directional).unwrap();
        let ccd = bake_cc(&field, CcOptions::default());
        let ccm = CcMap::new(&hf, &ccd, CcOptions::default().cap).unwrap();
        let mut tallies = Vec::from(rays.both("SD view-linear", VL, &Marcher::Safety(sd, vl)));
        tallies.extend(rays.both("CC view-linear", VL, &Marcher::Cc(ccm, vl)));
        for t in &tallies {
            wrong += t.wrong;
            tried += t.tried;
            t.report(&mut out);
        }
        // The test tells the surfaces apart: the triangle march fails it.
        let tri = rays.run::<f64>("triangles", VL, &Marcher::Safety(sd, TRI_MARCH));
        triangles_wrong += tri.wrong;
    }
    println!("{out}");
    println!("the triangle march judged on the view-linear surface: {triangles_wrong} wrong");
    assert!(tried > 10_000, "{tried} rays");
    assert!(triangles_wrong > 100, "the surfaces should differ");
    assert_eq!(wrong, 0, "wrong rays on the view-linear surface");
}

/// Surface clearance of the ray at `t`.
fn clearance(field: &Field, q: &Query<f64>, t: f64) -> f64 {
    common::clearance(field, TRI, q, t)
}

/// `true` when the ray leaves the solid (goes from under the surface to above it) on
/// `[0, t_end]`. The clearance is linear between its [`breakpoints`], so its values
/// there decide.
fn leaves_solid(field: &Field, q: &Query<f64>, t_end: f64, tol: f64) -> bool {
    let mut under = false;
    for t in breakpoints(q, 0.0, t_end) {
        let c = clearance(field, q, t);
        if c < -tol {
            under = true;
        } else if under && c > tol {
            return true;
        }
    }
    false
}

/// For random texels and every class, dense rays from the segment above the texel,
/// aimed inside the claimed safety distance (`sd + extra` columns), checked with the
/// exact piecewise-linear clearance; returns (rays, violations).
fn check_bake(field: &Field, data: &[u8], extra: u32, rng: &mut Rng) -> (u64, u64) {
    let probe = Probe::new(field);
    let (w, h) = (field.w, field.h);
    let (mut tried, mut bad) = (0, 0);
    for _ in 0..250 {
        let (i, j) = (rng.below(w as usize) as u32, rng.below(h as usize) as u32);
        for class in CLASSES {
            let at = safety::texel_offset(w, Variant::Directional, class, i, j);
            let sd = u32::from(data[at]);
            let k = sd + extra;
            if k == 0 || sd == 255 {
                continue;
            }
            let (ax, sg) = class_axis(class);
            let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
            let lm = if ax == 0 { w } else { h } as f64;
            let ln = if ax == 0 { h } else { w } as f64;
            // The ray must stay over the field up to the claimed centerline.
            let end_main = m as f64 + sg * k as f64;
            if end_main < 0.0 || end_main > lm - 1.0 {
                continue;
            }
            for r in 0..60 {
                let p = probe.start(rng, ax, [m, n], r);
                // Aim at a point of the quadrant ahead, near the surface.
                let (dist, slope) = Probe::reach(rng, k, r);
                let mut tgt = [0.0; 3];
                tgt[ax] = m as f64 + sg * dist;
                tgt[1 - ax] = p[1 - ax] + slope * dist;
                if tgt[1 - ax] < 0.0 || tgt[1 - ax] > ln - 1.0 {
                    continue;
                }
                let below = rng.range(-0.05, 0.5) * probe.relief;
                tgt[2] = TRI.height_at(&probe.hf, tgt[0], tgt[1]) - below;
                let dir = [tgt[0] - p[0], tgt[1] - p[1], tgt[2] - p[2]];
                let q = Query::from_arrays(p, dir, 0.0, f64::INFINITY).unwrap();
                // Parameter of the claimed centerline, cut where the ray leaves the
                // footprint sideways.
                let mut t_end = k as f64 / dist;
                let dm = dir[1 - ax];
                if dm != 0.0 {
                    let lim = if dm > 0.0 { ln - 1.0 } else { 0.0 };
                    t_end = t_end.min((lim - p[1 - ax]) / dm);
                }
                tried += 1;
                if leaves_solid(field, &q, t_end, 1e-9 * probe.zs) {
                    bad += 1;
                }
            }
        }
    }
    (tried, bad)
}

#[test]
fn bake_checked_independently() {
    check_bakes(9, fields(), |name, field, rng| {
        let data = bake(field, Options::default());
        let (tried, bad) = check_bake(field, &data, 0, rng);
        let (itried, ibad) = check_bake(field, &data, 1, rng);
        println!(
            "{name:<36} bake check: rays {tried:>7} leaving the solid {bad}   \
             (bake + 1: rays {itried:>7} leaving {ibad})"
        );
        assert_eq!(
            bad, 0,
            "{name}: a ray inside its safety distance leaves the solid"
        );
        ibad
    });
}

#[test]
fn row_ranges_match_whole_bake() {
    let field = rows_field(3);
    let hf = field.hf();
    for variant in [Variant::Directional, Variant::Isotropic] {
        let opts = Options {
            variant,
            ..Options::default()
        };
        let whole = bake(&field, opts);
        let mut scratch = vec![0f32; safety::scratch_len(23, 17)];
        safety::prepare(&hf, &mut scratch).unwrap();
        assert_rows_rebake(
            &whole,
            23 * variant.channels(),
            &[0..5, 5..6, 6..17],
            |r, out| safety::bake_rows(&hf, &scratch, r, opts, out).unwrap(),
        );
    }
    // Isotropic = minimum of the directional channels.
    let dir = bake(&field, Options::default());
    let iso = bake(
        &field,
        Options {
            variant: Variant::Isotropic,
            ..Options::default()
        },
    );
    for (t, v) in iso.iter().enumerate() {
        let (i, j) = ((t % 23) as u32, (t / 23) as u32);
        let at = |class| safety::texel_offset(23, Variant::Directional, class, i, j);
        let min = CLASSES.map(|class| dir[at(class)]).into_iter().min();
        assert_eq!(Some(*v), min);
    }
}

/// The packing: for every texel and class, the byte at [`safety::texel_offset`] is
/// the class's distance from `texel_distance` (directional, capped, with and without
/// the positive floor), or the minimum over the classes (isotropic); every byte of the
/// map is written; the directional map's class rows are `(j·4 + class)·W + i`.
#[test]
fn packing_holds_texel_distances() {
    for (name, field) in fields().into_iter().take(4) {
        let hf = field.hf();
        let (w, h) = (field.w, field.h);
        let mut scratch = vec![0f32; safety::scratch_len(w, h)];
        safety::prepare(&hf, &mut scratch).unwrap();
        for (positive, cap) in [(false, u8::MAX), (true, 3)] {
            let dist = |class, i, j| {
                let d = safety::texel_distance(&hf, &scratch, &safety::AllRays, class, i, j, cap);
                d.max(u8::from(positive))
            };
            for variant in [Variant::Directional, Variant::Isotropic] {
                let opts = Options {
                    variant,
                    positive,
                    cap,
                };
                let mut data = vec![0xEEu8; safety::map_len(w, h, variant)];
                safety::bake_rows(&hf, &scratch, 0..h, opts, &mut data).unwrap();
                let map = SafetyMap::new(&hf, &data, variant).unwrap();
                let mut seen = vec![false; data.len()];
                for j in 0..h {
                    for i in 0..w {
                        let want = CLASSES.map(|class| dist(class, i, j));
                        for (c, class) in CLASSES.into_iter().enumerate() {
                            let at = safety::texel_offset(w, variant, class, i, j);
                            let v = match variant {
                                Variant::Directional => {
                                    assert_eq!(at, (j as usize * 4 + c) * w as usize + i as usize);
                                    want[c]
                                }
                                Variant::Isotropic => {
                                    assert_eq!(at, j as usize * w as usize + i as usize);
                                    *want.iter().min().unwrap()
                                }
                            };
                            assert_eq!(data[at], v, "{name} {variant:?} ({i}, {j}) {class:?}");
                            seen[at] = true;
                            assert_eq!(map.distance(class, i, j), v);
                        }
                    }
                }
                assert!(
                    seen.iter().all(|&s| s),
                    "{name} {variant:?}: byte unwritten"
                );
            }
        }
    }
}

/// The cylinder–cone check: for random texels and every class, rays from the segment
/// above the texel (many above the cone's base), rising or falling, marched the step
/// the decoded shape allows (`max(r, floor((p_z − z_c)/(s_c − s_d)))`, the cap when
/// `s_d ≥ s_c`), checked with the exact clearance; the shape is `inflate`d by lowering
/// `z_c` by `inflate.0 ×` the relief and `s_c` by `inflate.1`. Returns (rays, violations).
fn check_cc_bake(
    field: &Field,
    data: &[u8],
    cap: u8,
    inflate: (f64, f64),
    rng: &mut Rng,
) -> (u64, u64) {
    let hf = field.hf();
    let map = CcMap::new(&hf, data, cap).unwrap();
    let (w, h) = (field.w, field.h);
    let zs = field.z_scale();
    let (zlo, zhi) = field.range();
    let relief = (zhi - zlo).max(1e-3);
    let (mut tried, mut bad) = (0, 0);
    for _ in 0..50 {
        let (i, j) = (rng.below(w as usize) as u32, rng.below(h as usize) as u32);
        for class in CLASSES {
            let shape = map.shape(&hf, class, i, j);
            if !shape.zc.is_finite() {
                continue;
            }
            let zc = shape.zc - inflate.0 * relief;
            let sc = shape.sc - inflate.1;
            let (ax, sg) = class_axis(class);
            let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
            let lm = if ax == 0 { w } else { h } as f64;
            let ln = if ax == 0 { h } else { w } as f64;
            for r in 0..40 {
                let y = match r % 5 {
                    0 => n as f64 - 0.5,
                    1 => n as f64 + 0.5,
                    _ => n as f64 + rng.range(-0.5, 0.5),
                }
                .clamp(0.0, ln - 1.0);
                let mut p = [0.0; 3];
                p[ax] = m as f64;
                p[1 - ax] = y;
                let ground = TRI.height_at(&hf, p[0], p[1]);
                p[2] = match r % 4 {
                    0 => ground + rng.range(0.0, 0.05) * relief,
                    _ => ground.max(zc) + rng.range(0.0, 0.6) * relief * rng.unit(),
                };
                let sd = match r % 6 {
                    0 => rng.range(0.0, 1.5),
                    1 => -rng.range(0.0, 0.05),
                    _ => -rng.range(0.0, 3.0) * rng.unit(),
                };
                let slope = match r % 3 {
                    0 => rng.sign(),
                    _ => rng.range(-1.0, 1.0),
                };
                let cone = if p[2] <= zc {
                    0
                } else if sd >= sc {
                    u32::from(cap)
                } else {
                    (((p[2] - zc) / (sc - sd)).floor()).min(f64::from(cap)) as u32
                };
                let k = cone.max(shape.r);
                if k == 0 {
                    continue;
                }
                let mut dir = [0.0, 0.0, sd];
                dir[ax] = sg;
                dir[1 - ax] = slope;
                let q = Query::from_arrays(p, dir, 0.0, f64::INFINITY).unwrap();
                let end_main = m as f64 + sg * k as f64;
                let mut t_end = k as f64;
                if end_main < 0.0 || end_main > lm - 1.0 {
                    t_end = if sg > 0.0 {
                        lm - 1.0 - m as f64
                    } else {
                        m as f64
                    };
                }
                if slope != 0.0 {
                    let lim = if slope > 0.0 { ln - 1.0 } else { 0.0 };
                    t_end = t_end.min((lim - y) / slope);
                }
                if t_end <= 0.0 {
                    continue;
                }
                tried += 1;
                if leaves_solid(field, &q, t_end, 1e-9 * zs) {
                    bad += 1;
                }
            }
        }
    }
    (tried, bad)
}

#[test]
fn cc_bake_checked_independently() {
    let mut rng = Rng::new(19);
    let mut inflated_bad = 0;
    for (name, field) in fields() {
        for slope in [Slope::Exact, Slope::NBuffer] {
            let opts = CcOptions {
                slope,
                ..CcOptions::default()
            };
            let data = bake_cc(&field, opts);
            let (tried, bad) = check_cc_bake(&field, &data, opts.cap, (0.0, 0.0), &mut rng);
            let (itried, ibad) = check_cc_bake(&field, &data, opts.cap, (0.05, 0.3), &mut rng);
            println!(
                "{name:<36} CC {slope:?} bake check: rays {tried:>7} leaving the solid {bad}   \
                 (inflated: rays {itried:>7} leaving {ibad})"
            );
            assert_eq!(
                bad, 0,
                "{name} {slope:?}: a ray inside its shape leaves the solid"
            );
            inflated_bad += ibad;
        }
    }
    assert!(
        inflated_bad > 0,
        "the check never fails, even on an inflated shape"
    );
}

/// The N-buffer slope is the paper's: the largest `(h_max(u) − z_c)/u` over the
/// abscissas `u` (sample columns ahead) of the columns past the cylinder, `h_max(u)`
/// the highest sample of the column at `u` over the band of column `u` (cells
/// `n − u − 2 ..= n + u + 1`). Computed here by brute force for the texels with a
/// cylinder (`r ≥ 1`: column 0, taken exactly, plays no part), between the base
/// height's stored code and the code below it (the map keeps `z_c` rounded up). A
/// bound per cell column (both sample columns over `u = k`, as the bake took until
/// session 7) fails it.
#[test]
fn cc_nbuffer_slope_is_per_abscissa() {
    let (mut checked, mut tight) = (0, 0);
    for (name, field) in fields() {
        let hf = field.hf();
        for cap in [6u8, 255] {
            let data = bake_cc(
                &field,
                CcOptions {
                    slope: Slope::NBuffer,
                    cap,
                },
            );
            for class in CLASSES {
                let (ax, sg) = class_axis(class);
                let (lm, ln) = if ax == 0 {
                    (field.w, field.h)
                } else {
                    (field.h, field.w)
                };
                let at =
                    |m: u32, n: u32| f64::from(if ax == 0 { hf.at(m, n) } else { hf.at(n, m) });
                for j in 0..field.h {
                    for i in 0..field.w {
                        let b = &data[cc::texel_offset(field.w, class, i, j)..][..2];
                        let (m, n) = if ax == 0 { (i, j) } else { (j, i) };
                        let kend = u32::from(cap).min(if sg > 0.0 { lm - 1 - m } else { m });
                        let k0 = u32::from(b[0]).max(1);
                        if b[0] == 0 || b[1] == cc::NO_CONE || k0 >= kend {
                            continue;
                        }
                        // The largest (h_max(u) − zc)/u for a base height zc.
                        let slope = |zc: f64| {
                            (k0..=kend).fold(cc::S_MIN, |s: f64, u| {
                                let col = if sg > 0.0 { m + u } else { m - u };
                                let (y0, y1) = (n.saturating_sub(u + 2), (n + u + 2).min(ln - 1));
                                let top = (y0..=y1).map(|y| at(col, y)).fold(f64::MIN, f64::max);
                                s.max((top - zc) / f64::from(u))
                            })
                        };
                        // The base as the bake takes it, and a hair either side (the
                        // bound's own rounding may differ from the bake's).
                        let zc = cc::base_height(&hf, class, i, j);
                        let eps = 1e-9 * (1.0 + zc.abs());
                        let (hi, lo) = (zc + eps, zc - eps);
                        let got = b[1];
                        let (least, most) =
                            (cc::encode_slope(slope(hi)), cc::encode_slope(slope(lo)));
                        assert!(
                            least <= got && got <= most,
                            "{name} cap {cap} {class:?} texel ({i}, {j}): slope code {got} outside {least}..={most}"
                        );
                        checked += 1;
                        tight += usize::from(least == most);
                    }
                }
            }
        }
    }
    println!("N-buffer slopes checked per abscissa: {checked} ({tight} to the code)");
    assert!(
        checked > 5000 && tight * 2 > checked,
        "{checked} checked, {tight} tight"
    );
}

/// The N-buffers hold what their definition says: per axis, sample column `c`, level
/// `l` and minor index `y`, the maximum of the samples `y ..= min(y + 2^l − 1, last)`
/// of the column; per block `b` the maximum of that over the sample columns
/// `8b ..= min(8b + 8, last)`. The steps only locate the entries; every entry of
/// every step is checked, and every element of the buffer is written by one.
#[test]
fn nbuffers_hold_their_window_maxima() {
    let mut checked = 0usize;
    for (name, field) in fields().into_iter().take(5) {
        let hf = field.hf();
        for cap in [1u8, 6, 255] {
            let len = cc::nbuffer_len(field.w, field.h, cap);
            let mut nb = vec![f32::NAN; len];
            cc::prepare_nbuffer(&hf, cap, &mut nb).unwrap();
            assert!(
                nb.iter().all(|v| !v.is_nan()),
                "{name} cap {cap}: unwritten entries"
            );
            let steps: Vec<cc::NbufferStep> = cc::nbuffer_steps(field.w, field.h, cap).collect();
            let written: usize = steps
                .iter()
                .map(|s| s.rows as usize * s.row_len as usize)
                .sum();
            assert_eq!(
                written, len,
                "{name} cap {cap}: the steps write every entry once"
            );
            for ax in 0..2u32 {
                let at = |m: u32, n: u32| if ax == 0 { hf.at(m, n) } else { hf.at(n, m) };
                let of_axis = steps.iter().filter(|s| s.axis == ax);
                // Level 0 (heights, blocks), then each level above over the sample
                // columns and then the blocks.
                let mut level = 0u32;
                for s in of_axis {
                    if s.kind == cc::NbufferKind::Double {
                        level += 1;
                    }
                    let last = s.row_len - 1;
                    for r in 0..s.rows {
                        let block = match s.kind {
                            cc::NbufferKind::Heights => None,
                            cc::NbufferKind::Blocks => Some(r),
                            cc::NbufferKind::Double => r.checked_sub(s.columns),
                        };
                        let cols = match block {
                            Some(b) => 8 * b..=(8 * b + 8).min(s.columns - 1),
                            None => r..=r,
                        };
                        for y in 0..s.row_len {
                            let window = y..=(y + (1 << level) - 1).min(last);
                            let want = cols
                                .clone()
                                .flat_map(|c| window.clone().map(move |n| (c, n)))
                                .map(|(c, n)| at(c, n))
                                .fold(f32::NEG_INFINITY, f32::max);
                            let got = nb[s.dst + (r * s.row_len + y) as usize];
                            assert_eq!(got, want, "{name} cap {cap} axis {ax} {s:?} row {r} y {y}");
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    println!("N-buffer entries checked against their definition: {checked}");
    assert!(checked > 100_000, "{checked}");
}

#[test]
fn cc_rows_and_packing() {
    let field = rows_field(5);
    let hf = field.hf();
    for slope in [Slope::Exact, Slope::NBuffer] {
        let opts = CcOptions { slope, cap: 20 };
        let whole = bake_cc(&field, opts);
        let mut scratch = vec![0f32; safety::scratch_len(23, 17)];
        let mut nb = vec![0f32; cc::nbuffer_len(23, 17, opts.cap)];
        safety::prepare(&hf, &mut scratch).unwrap();
        cc::prepare_nbuffer(&hf, opts.cap, &mut nb).unwrap();
        assert_rows_rebake(
            &whole,
            23 * cc::BYTES_PER_TEXEL,
            &[0..4, 4..11, 11..17],
            |r, out| cc::bake_rows(&hf, &scratch, &nb, r, opts, out).unwrap(),
        );
        // r equals the SD bake; the N-buffer slope is never below the exact one.
        let sd = bake(&field, Options::default());
        let exact = bake_cc(
            &field,
            CcOptions {
                slope: Slope::Exact,
                cap: 20,
            },
        );
        for t in 0..(23 * 17) as usize {
            for class in CLASSES {
                let (i, j) = ((t % 23) as u32, (t / 23) as u32);
                let at = cc::texel_offset(23, class, i, j);
                let b = &whole[at..][..2];
                let sd_at = safety::texel_offset(23, Variant::Directional, class, i, j);
                assert_eq!(b[0], sd[sd_at]);
                let e = &exact[at..][..2];
                if slope == Slope::NBuffer && e[1] != cc::NO_CONE && b[1] != cc::NO_CONE {
                    assert!(cc::decode_slope(b[1]) >= cc::decode_slope(e[1]));
                }
            }
        }
    }
    // Conservative rounding of the codes: on a sweep, and at every code's value and the
    // floats beside it (where a rounding step lost by the encoder would show).
    let at_codes = (0..cc::NO_CONE).flat_map(|c| {
        let v = cc::decode_slope(c);
        [v.next_down(), v, v.next_up()]
    });
    for s in (0..20_000)
        .map(|k| -9.0 + k as f64 * 0.00089)
        .chain(at_codes)
    {
        let c = cc::encode_slope(s);
        assert!(cc::decode_slope(c) >= s, "slope {s}");
        if c != cc::NO_CONE && c > 0 {
            assert!(cc::decode_slope(c - 1) < s || s < cc::S_MIN);
        }
    }
}
