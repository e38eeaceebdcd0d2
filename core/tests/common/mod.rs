//! Shared helpers of the integration tests: a seeded RNG, owned height fields, the
//! ambiguity rule of docs/DESIGN.md, ray generators and a tally that prints per-case counts.
#![allow(dead_code)] // every test binary uses a different part of this module

use hfcast::bake::{Spec, Texels};
use hfcast::ktx2::{Desc, MapKind};
use hfcast::{brute, dda, judge, Flags, HeightField, Query, RayClass, Real, Surface, Trace};
use std::ops::Range;

/// The tests' seeded generator: SplitMix64 from `seed ^ GOLDEN` ([`Rng::new`]).
pub use hfcast::rng::SplitMix as Rng;

/// An owned height field; row padding (stride > width) is filled with NaN so that a
/// read outside the rows poisons the result.
#[derive(Clone, Debug)]
pub struct Field {
    pub samples: Vec<f32>,
    pub w: u32,
    pub h: u32,
    pub stride: usize,
}

impl Field {
    /// `w × h` samples from `f(i, j)`, rows `stride` apart.
    pub fn from_fn(w: u32, h: u32, stride: usize, mut f: impl FnMut(u32, u32) -> f32) -> Field {
        let mut samples = vec![f32::NAN; stride * (h as usize - 1) + w as usize];
        for j in 0..h {
            for i in 0..w {
                samples[j as usize * stride + i as usize] = f(i, j);
            }
        }
        Field {
            samples,
            w,
            h,
            stride,
        }
    }
    /// The validated view.
    pub fn hf(&self) -> HeightField<'_> {
        HeightField::new(&self.samples, self.w, self.h, self.stride).expect("valid test field")
    }
    /// Sample (i, j).
    pub fn at(&self, i: u32, j: u32) -> f32 {
        self.samples[j as usize * self.stride + i as usize]
    }
    /// The footprint's far corner `(W − 1, H − 1)`.
    pub fn far_corner(&self) -> (f64, f64) {
        ((self.w - 1) as f64, (self.h - 1) as f64)
    }
    /// `(min, max)` height.
    pub fn range(&self) -> (f64, f64) {
        let hf = self.hf();
        (hf.min_height() as f64, hf.max_height() as f64)
    }
    /// Largest |height|, at least 1: the `max(1, |z|)` of the ambiguity rule, taken
    /// over the whole field (conservative: a graze is never below it).
    pub fn z_scale(&self) -> f64 {
        let (lo, hi) = self.range();
        1f64.max(lo.abs()).max(hi.abs())
    }
    /// `max − min` height, at least 1e-3.
    pub fn relief(&self) -> f64 {
        let (lo, hi) = self.range();
        (hi - lo).max(1e-3)
    }
}

/// Random small field: sizes 2×2 … 12×9, random stride, heights that are integers
/// (ties, flat cells), quarter-integers or arbitrary floats, in several ranges.
pub fn small_field(rng: &mut Rng) -> Field {
    let w = rng.int(2, 12) as u32;
    let h = rng.int(2, 9) as u32;
    let stride = w as usize
        + if rng.chance(0.5) {
            0
        } else {
            rng.int(1, 5) as usize
        };
    let mode = rng.below(5);
    let amp = [1.0, 3.0, 0.01, 40.0][rng.below(4)];
    let offset = if rng.chance(0.2) {
        rng.range(-50.0, 50.0)
    } else {
        0.0
    };
    Field::from_fn(w, h, stride, |_, _| match mode {
        0 => rng.int(0, 3) as f32,
        1 => (rng.int(0, 8) as f64 * 0.25 + offset.round()) as f32,
        2 => rng.range(-amp, amp) as f32,
        3 => (rng.range(0.0, amp) + offset) as f32,
        _ => {
            if rng.chance(0.5) {
                rng.int(-2, 2) as f32
            } else {
                rng.range(-2.0, 2.0) as f32
            }
        }
    })
}

/// A smooth fractal-ish field: a sum of sines with random phases and falling
/// amplitudes, plus a little value noise.
pub fn fractal_field(rng: &mut Rng, w: u32, h: u32, stride: usize, amp: f64) -> Field {
    let waves: Vec<[f64; 4]> = (0..8)
        .map(|k| {
            let f = 0.05 * 1.9f64.powi(k);
            let a = rng.range(0.0, std::f64::consts::TAU);
            [
                f * a.cos(),
                f * a.sin(),
                rng.range(0.0, std::f64::consts::TAU),
                amp / 1.8f64.powi(k),
            ]
        })
        .collect();
    let mut noise = Rng::new(rng.next_u64());
    Field::from_fn(w, h, stride, |i, j| {
        let (x, y) = (i as f64, j as f64);
        let s: f64 = waves
            .iter()
            .map(|[fx, fy, ph, a]| a * (fx * x + fy * y + ph).sin())
            .sum();
        (s + noise.range(-0.02, 0.02) * amp) as f32
    })
}

/// The two fractal fields of the march tests: 61×47 (amplitude 8) and the non-square
/// 90×7 with stride 95 (amplitude 3), named `"fractal 61x47"` and `wide`.
pub fn fractal_fields(rng: &mut Rng, wide: &str) -> Vec<(String, Field)> {
    let square = fractal_field(rng, 61, 47, 61, 8.0);
    let narrow = fractal_field(rng, 90, 7, 95, 3.0);
    vec![("fractal 61x47".into(), square), (wide.into(), narrow)]
}

/// 1-texel walls of height 6 on a flat 40×40 floor, along 5 random rows and columns.
pub fn random_walls_field(rng: &mut Rng) -> Field {
    let mut wall_rows = [false; 40];
    let mut wall_cols = [false; 40];
    for _ in 0..5 {
        wall_rows[rng.below(40)] = true;
        wall_cols[rng.below(40)] = true;
    }
    Field::from_fn(40, 40, 40, |i, j| {
        let wall = wall_rows[j as usize] || wall_cols[i as usize];
        if wall {
            6.0
        } else {
            0.0
        }
    })
}

/// Needles (one texel in 25, 5 to 30 high) on gentle noise, 45×38, drawn from their
/// own generator seeded with `seed`.
pub fn needles_field(seed: u64) -> Field {
    let mut r = Rng::new(seed);
    Field::from_fn(45, 38, 45, |_, _| {
        let needle = r.chance(0.04);
        let (lo, hi) = if needle { (5.0, 30.0) } else { (0.0, 0.3) };
        r.range(lo, hi) as f32
    })
}

/// A 24×20 checkerboard: `even` where `i + j` is even, `odd` elsewhere.
pub fn checkerboard_field(even: f32, odd: f32) -> Field {
    Field::from_fn(24, 20, 24, |i, j| if (i + j) % 2 == 0 { even } else { odd })
}

/// The smallest field, 2×2.
pub fn tiny_field() -> Field {
    Field::from_fn(2, 2, 2, |i, j| [0.3, 1.0, 0.7, 0.1][(i + 2 * j) as usize])
}

/// A flat-topped plateau of height 4 on a low ridged floor, 33×29.
pub fn plateau_field() -> Field {
    Field::from_fn(33, 29, 33, |i, j| {
        let top = (8..25).contains(&i) && (6..22).contains(&j);
        if top {
            4.0
        } else {
            (i % 3) as f32 * 0.1
        }
    })
}

/// `n` random small fields ([`small_field`]), named `"small random #k"`.
pub fn small_fields(rng: &mut Rng, n: usize) -> Vec<(String, Field)> {
    (0..n)
        .map(|k| (format!("small random #{k}"), small_field(rng)))
        .collect()
}

/// The synthetic fields of the safety-distance and radius tests, in this order: the two
/// fractals, random walls, needles (from `needles`' own generator), the checkerboard
/// `checker` (name, even and odd height), 2×2, the `extra` fields, the plateau and
/// `n_small` small random fields; every random field but the needles is drawn from
/// one generator seeded with `seed`.
pub fn march_fields(
    seed: u64,
    needles: u64,
    checker: (&str, f32, f32),
    extra: Vec<(String, Field)>,
    n_small: usize,
) -> Vec<(String, Field)> {
    let mut rng = Rng::new(seed);
    let mut v = fractal_fields(&mut rng, "fractal non-square 90x7 stride 95");
    v.push(("walls 40x40".into(), random_walls_field(&mut rng)));
    v.push(("needles 45x38".into(), needles_field(needles)));
    v.push((checker.0.into(), checkerboard_field(checker.1, checker.2)));
    v.push(("2x2".into(), tiny_field()));
    v.extend(extra);
    v.push(("plateau 33x29".into(), plateau_field()));
    v.extend(small_fields(&mut rng, n_small));
    v
}

/// `hf`'s float map `map` (the pyramid, cone, relaxed cone or QDM map), baked whole
/// through the one bake interface (`hfcast::bake::Spec` with the defaults).
pub fn baked_floats(map: MapKind, hf: &HeightField) -> Vec<f32> {
    let spec = Spec::new(Desc::new(map, hf.width(), hf.height()));
    match spec.bake_owned(hf).expect("bake") {
        Texels::F32(v) => v,
        Texels::U8(_) => panic!("{map:?} is not a float map"),
    }
}

/// docs/DESIGN.md's ambiguity threshold `2⁻¹³ · max(1, |z|)`.
pub fn eps_f32(z_scale: f64) -> f64 {
    z_scale / 8192.0
}

/// docs/DESIGN.md's ambiguity rule on an exact trace: its clearance is below `eps`. (For a
/// hit where the traced span begins the clearance is the depth under the surface
/// there, so an origin just under the surface is ambiguous too.)
pub fn is_ambiguous<R: Real>(oracle: &Trace<R>, eps: f64) -> bool {
    oracle.clearance.to_f64() < eps
}

/// Whether the oracle's hit flags are the same on the ray moved by δ along every axis
/// (`hfcast::judge::moved`): only then must an `f32` trace's flags match.
pub fn flags_resolved(
    hf: &HeightField,
    surface: Surface,
    q: &Query<f64>,
    oracle: &Trace<f64>,
) -> bool {
    let flags = |t: &Trace<f64>| t.hit.map(|h| h.flags);
    judge::moved(hf, surface, q)
        .iter()
        .all(|m| m.as_ref().is_some_and(|m| flags(m) == flags(oracle)))
}

/// For the discontinuous surfaces (height planes, corner planes): `true` when the ray
/// passes within `tol` texel (horizontally) of a point where walls meet — quarter
/// corners at half-integer x and y for height planes, grid points for corner planes —
/// below the top of the pieces meeting there. There two walls touch along a vertical
/// edge, and which side of it the ray passes by is decided by rounding: an ambiguous
/// ray that the clearance (a vertical distance) cannot flag. Vertical rays are exempt:
/// their coordinates are exact and the tie rule decides them the same in any precision
/// (and so are rays running exactly along a wall line).
pub fn near_pinch(field: &Field, surface: Surface, q: &Query<f64>, tol: f64) -> bool {
    let off = match surface {
        Surface::HeightPlanes => 0.5,
        Surface::CornerPlanes => 0.0,
        _ => return false,
    };
    let hf = field.hf();
    let (o, d) = (q.origin(), q.dir());
    let lim = [(field.w - 1) as f64, (field.h - 1) as f64];
    for axis in 0..2 {
        if d[axis] == 0.0 {
            continue;
        }
        let other = 1 - axis;
        if d[other] == 0.0 {
            // Running along a line of constant, exact `other` coordinate: the tie rule
            // decides it the same way in every precision.
            continue;
        }
        let mut k = off;
        while k <= lim[axis] {
            let t = (k - o[axis]) / d[axis];
            k += 1.0;
            if t < q.t_min() || t > q.t_max() {
                continue;
            }
            let p = q.at(t);
            let line = (p[other] - off).round() + off;
            if (p[other] - line).abs() >= tol || line < 0.0 || line > lim[other] {
                continue;
            }
            let mut pinch = [0.0; 2];
            pinch[axis] = k - 1.0;
            pinch[other] = line;
            let top = [[-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]]
                .iter()
                .map(|s| surface.height_at(&hf, pinch[0] + 1e-3 * s[0], pinch[1] + 1e-3 * s[1]))
                .fold(f64::NEG_INFINITY, f64::max);
            if p[2] <= top + 1e-6 * field.z_scale() {
                return true;
            }
        }
    }
    false
}

/// A ray query as plain `f64` numbers, before conversion to the precision under test.
#[derive(Clone, Copy, Debug)]
pub struct RaySpec {
    pub o: [f64; 3],
    pub d: [f64; 3],
    pub t_min: f64,
    pub t_max: f64,
}

impl RaySpec {
    /// The ray `o + t·d` over `[0, ∞)`.
    pub fn whole(o: [f64; 3], d: [f64; 3]) -> RaySpec {
        RaySpec {
            o,
            d,
            t_min: 0.0,
            t_max: f64::INFINITY,
        }
    }
    /// The query in precision `R` (values rounded to `R`).
    pub fn query<R: Real>(&self) -> Query<R> {
        let c = |v: [f64; 3]| v.map(R::from_f64);
        let (t_min, t_max) = (R::from_f64(self.t_min), R::from_f64(self.t_max));
        Query::from_arrays(c(self.o), c(self.d), t_min, t_max).expect("valid ray")
    }
    /// The `f64` query.
    pub fn q64(&self) -> Query<f64> {
        self.query()
    }
    /// The `f32` query (values rounded to `f32`).
    pub fn q32(&self) -> Query<f32> {
        self.query()
    }
}

/// The kinds of rays the random tests draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    Down,
    Up,
    Grazing,
    Horizontal,
    AxisX,
    AxisY,
    VerticalInt,
    VerticalHalf,
    Inside,
    CornerOrigin,
    CenterlineOrigin,
    Diagonal,
    Outside,
}

impl RayKind {
    pub const ALL: [RayKind; 13] = [
        RayKind::Down,
        RayKind::Up,
        RayKind::Grazing,
        RayKind::Horizontal,
        RayKind::AxisX,
        RayKind::AxisY,
        RayKind::VerticalInt,
        RayKind::VerticalHalf,
        RayKind::Inside,
        RayKind::CornerOrigin,
        RayKind::CenterlineOrigin,
        RayKind::Diagonal,
        RayKind::Outside,
    ];
}

/// Direction with a random horizontal angle and the given elevation (radians; negative
/// is down), scaled by a random length so that `t` is not always in grid units.
fn dir_from(rng: &mut Rng, elevation: f64) -> [f64; 3] {
    let azimuth = rng.range(0.0, std::f64::consts::TAU);
    let len = if rng.chance(0.3) {
        10f64.powf(rng.range(-1.5, 1.5))
    } else {
        1.0
    };
    [
        len * elevation.cos() * azimuth.cos(),
        len * elevation.cos() * azimuth.sin(),
        len * elevation.sin(),
    ]
}

/// A random ray of `kind` for `field`: the origin is sometimes inside and sometimes
/// outside the box, `t_min`/`t_max` are usually `0`/`∞` but not always.
pub fn random_ray(rng: &mut Rng, field: &Field, surface: Surface, kind: RayKind) -> RaySpec {
    let (xm, ym) = field.far_corner();
    let (zlo, zhi) = field.range();
    let zr = (zhi - zlo).max(1e-3);
    let hf = field.hf();
    let any_xy = |rng: &mut Rng, pad: f64| [rng.range(-pad, xm + pad), rng.range(-pad, ym + pad)];
    let any_z = |rng: &mut Rng| rng.range(zlo - 0.3 * zr, zhi + 0.5 * zr);
    let (o, d) = match kind {
        RayKind::Down | RayKind::Outside => {
            let target = [
                rng.range(-0.2 * xm, 1.2 * xm),
                rng.range(-0.2 * ym, 1.2 * ym),
                rng.range(zlo, zhi),
            ];
            let el = -rng.range(0.02, std::f64::consts::FRAC_PI_2);
            let d = dir_from(rng, el);
            let back = rng.range(0.3, 2.0 * (xm + ym) + zr)
                / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let mut o = [
                target[0] - back * d[0],
                target[1] - back * d[1],
                target[2] - back * d[2],
            ];
            if kind == RayKind::Outside {
                // Push the origin out of the footprint and start below, inside or above it.
                let side = rng.below(4);
                match side {
                    0 => o[0] = -rng.range(0.1, 3.0),
                    1 => o[0] = xm + rng.range(0.1, 3.0),
                    2 => o[1] = -rng.range(0.1, 3.0),
                    _ => o[1] = ym + rng.range(0.1, 3.0),
                }
                o[2] = rng.range(zlo - 3.0 * zr - 2.0, zhi + zr);
                let aim = [
                    rng.range(0.0, xm),
                    rng.range(0.0, ym),
                    rng.range(zlo - zr, zhi + zr),
                ];
                let dd = [aim[0] - o[0], aim[1] - o[1], aim[2] - o[2]];
                return finish(rng, o, dd);
            }
            (o, d)
        }
        RayKind::Up => {
            let [x, y] = any_xy(rng, 1.0);
            let el = rng.range(0.02, std::f64::consts::FRAC_PI_2);
            ([x, y, any_z(rng)], dir_from(rng, el))
        }
        RayKind::Grazing => {
            let [x, y] = any_xy(rng, 0.5);
            let el = rng.sign() * 10f64.powf(rng.range(-4.0, -1.5));
            let z = surface.height_at(&hf, x, y) + rng.range(-0.01, 0.3) * zr;
            ([x, y, z], dir_from(rng, el))
        }
        RayKind::Horizontal => {
            let [x, y] = any_xy(rng, 1.0);
            let z = if rng.chance(0.3) {
                field.at(
                    rng.below(field.w as usize) as u32,
                    rng.below(field.h as usize) as u32,
                ) as f64
            } else {
                any_z(rng)
            };
            let a = rng.range(0.0, std::f64::consts::TAU);
            ([x, y, z], [a.cos(), a.sin(), 0.0])
        }
        RayKind::AxisX | RayKind::AxisY => {
            let axis = usize::from(kind == RayKind::AxisY);
            let lim = [xm, ym];
            let mut o = [0.0; 3];
            o[axis] = rng.range(-1.0, lim[axis] + 1.0);
            // The other coordinate: random, on a centerline, or half-way between.
            let other = 1 - axis;
            o[other] = match rng.below(3) {
                0 => rng.range(0.0, lim[other]),
                1 => rng.int(0, lim[other] as i64) as f64,
                _ => (rng.int(0, lim[other] as i64 - 1) as f64) + 0.5,
            };
            o[2] = any_z(rng);
            let mut d = [0.0; 3];
            d[axis] = rng.sign() * rng.range(0.2, 2.0);
            d[2] = match rng.below(4) {
                0 => 0.0,
                1 => rng.range(0.0, 1.0),
                _ => -rng.range(0.0, 2.0),
            };
            (o, d)
        }
        RayKind::VerticalInt | RayKind::VerticalHalf => {
            let half = if kind == RayKind::VerticalHalf {
                0.5
            } else {
                0.0
            };
            let mut x = rng.int(0, xm as i64) as f64;
            let mut y = rng.int(0, ym as i64) as f64;
            if half > 0.0 {
                // Half-integer in x, y or both (inside the footprint).
                match rng.below(3) {
                    0 => x = (x.min(xm - 1.0)) + 0.5,
                    1 => y = (y.min(ym - 1.0)) + 0.5,
                    _ => {
                        x = (x.min(xm - 1.0)) + 0.5;
                        y = (y.min(ym - 1.0)) + 0.5;
                    }
                }
            }
            let dz = if rng.chance(0.8) { -1.0 } else { 1.0 } * rng.range(0.1, 3.0);
            ([x, y, any_z(rng)], [0.0, 0.0, dz])
        }
        RayKind::Inside => {
            let [x, y] = any_xy(rng, 0.0);
            let z = surface.height_at(&hf, x, y) - rng.range(1e-3, 1.0) * zr;
            let el = rng.range(-1.5, 1.5);
            ([x, y, z], dir_from(rng, el))
        }
        RayKind::CornerOrigin | RayKind::CenterlineOrigin => {
            let i = rng.int(0, xm as i64) as u32;
            let j = rng.int(0, ym as i64) as u32;
            let (mut x, mut y) = (i as f64, j as f64);
            if kind == RayKind::CenterlineOrigin {
                if rng.chance(0.5) {
                    x = rng.range(0.0, xm);
                } else {
                    y = rng.range(0.0, ym);
                }
            }
            let z = match rng.below(5) {
                0 => field.at(i, j) as f64,
                3 => field.at(i, j) as f64 - rng.range(0.01, 1.0) * zr,
                1 => field.at(i, j) as f64 + rng.range(0.01, 1.0) * zr,
                _ => any_z(rng),
            };
            let d = match rng.below(3) {
                0 => [rng.sign(), rng.sign(), rng.range(-1.0, 0.5)],
                1 => {
                    let mut d = [0.0, 0.0, rng.range(-1.0, 0.5)];
                    d[rng.below(2)] = rng.sign();
                    d
                }
                _ => {
                    let el = rng.range(-1.4, 0.6);
                    dir_from(rng, el)
                }
            };
            ([x, y, z], d)
        }
        RayKind::Diagonal => {
            // Through a grid point exactly, along a cell diagonal: o = p − k·d with dyadic d.
            let (i, j) = (rng.int(0, xm as i64) as f64, rng.int(0, ym as i64) as f64);
            let d = [rng.sign(), rng.sign(), -(rng.int(1, 16) as f64) / 8.0];
            let k = rng.int(1, 6) as f64;
            let zc = surface.height_at(&hf, i, j) + rng.range(-0.05, 0.05) * zr;
            ([i - k * d[0], j - k * d[1], zc - k * d[2]], d)
        }
    };
    finish(rng, o, d)
}

/// `n` random rays (for surface `s` of `f`) of each kind of `ks`, kind after kind.
pub fn kind_blocks(rng: &mut Rng, f: &Field, s: Surface, ks: &[RayKind], n: usize) -> Vec<RaySpec> {
    let kinds = ks.iter().flat_map(|&k| vec![k; n]);
    kinds.map(|k| random_ray(rng, f, s, k)).collect()
}

/// `n` rounds of one random ray (for surface `s` of `f`) of each kind of `ks`, in turn.
pub fn of_kinds(rng: &mut Rng, f: &Field, s: Surface, ks: &[RayKind], n: usize) -> Vec<RaySpec> {
    let kinds = (0..n).flat_map(|_| ks.iter().copied());
    kinds.map(|k| random_ray(rng, f, s, k)).collect()
}

/// Rays at exactly `elevation` (radians, up or down) from just above the surface,
/// some along an axis.
pub fn grazing(rng: &mut Rng, field: &Field, surface: Surface, n: usize, el: f64) -> Vec<RaySpec> {
    let hf = field.hf();
    let (xm, ym) = field.far_corner();
    let (lo, hi) = field.range();
    (0..n)
        .map(|_| {
            let el = el * rng.sign();
            let az = rng.range(0.0, std::f64::consts::TAU);
            let (x, y) = (rng.range(-0.5, xm + 0.5), rng.range(-0.5, ym + 0.5));
            let z = surface.height_at(&hf, x, y) + rng.range(-0.001, 0.2) * (hi - lo).max(1e-3);
            let d = if rng.chance(0.25) {
                let mut d = [0.0, 0.0, el.sin()];
                d[rng.below(2)] = rng.sign() * el.cos();
                d
            } else {
                [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()]
            };
            RaySpec::whole([x, y, z], d)
        })
        .collect()
}

/// Picks the parameter range: mostly `[0, ∞)`, sometimes a negative or positive
/// `t_min` and a finite `t_max`.
fn finish(rng: &mut Rng, o: [f64; 3], d: [f64; 3]) -> RaySpec {
    let (t_min, t_max) = match rng.below(8) {
        0 => (rng.range(-1.0, 1.0), f64::INFINITY),
        1 => {
            let a = rng.range(0.0, 2.0);
            (a, a + rng.range(0.0, 20.0))
        }
        _ => (0.0, f64::INFINITY),
    };
    RaySpec { o, d, t_min, t_max }
}

/// Adds the named counters of `$from` to those of `$to` (`$to.tried += $from.tried`, …):
/// the per-case counts of a test summed into its totals.
macro_rules! add_counts {
    ($to:expr, $from:expr, $($counter:ident),+ $(,)?) => {
        $($to.$counter += $from.$counter;)+
    };
}
#[allow(unused_imports)] // the test binaries that sum counts of their own use it
pub(crate) use add_counts;

/// Keeps `what()` among `examples` while they are fewer than `max`: the first few of
/// something are described, the rest only counted.
pub fn keep_example(examples: &mut Vec<String>, max: usize, what: impl FnOnce() -> String) {
    if examples.len() < max {
        examples.push(what());
    }
}

/// Per-case counts, printed as one line: `tried`, `wrong`, `ambiguous` and the largest
/// position error (texels) among the compared rays.
#[derive(Debug, Default)]
pub struct Tally {
    pub name: String,
    pub tried: u64,
    pub wrong: u64,
    pub ambiguous: u64,
    pub hits: u64,
    pub max_err: f64,
    pub sum_err: f64,
    pub compared_hits: u64,
    pub examples: Vec<String>,
}

impl Tally {
    pub fn new(name: impl Into<String>) -> Tally {
        Tally {
            name: name.into(),
            ..Tally::default()
        }
    }
    /// Records one wrong ray (keeps the first few descriptions).
    pub fn wrong(&mut self, what: impl FnOnce() -> String) {
        self.wrong += 1;
        keep_example(&mut self.examples, 5, what);
    }
    /// Counts one traced ray, a hit of its reference (`hits`) and whether it is
    /// `ambiguous`; `true` when it is to be compared (not ambiguous).
    pub fn ray(&mut self, hits: bool, ambiguous: bool) -> bool {
        self.tried += 1;
        self.hits += u64::from(hits);
        self.ambiguous += u64::from(ambiguous);
        !ambiguous
    }
    /// Records the position error of two compared hit points (the reference's `a`,
    /// the trace's `b`) and returns it.
    pub fn err_between(&mut self, a: [f64; 3], b: [f64; 3]) -> f64 {
        let e = dist(a, b);
        self.err(e);
        e
    }
    /// Records the position error of one compared hit.
    pub fn err(&mut self, e: f64) {
        self.compared_hits += 1;
        self.sum_err += e;
        self.max_err = self.max_err.max(e);
    }
    /// Adds another tally's counts.
    pub fn absorb(&mut self, o: &Tally) {
        add_counts!(
            self,
            o,
            tried,
            wrong,
            ambiguous,
            hits,
            sum_err,
            compared_hits
        );
        self.max_err = self.max_err.max(o.max_err);
        for e in &o.examples {
            keep_example(&mut self.examples, 5, || e.clone());
        }
    }
    /// Appends the line the project notes quote (and a few wrong examples).
    pub fn report(&self, out: &mut String) {
        let mean = if self.compared_hits > 0 {
            self.sum_err / self.compared_hits as f64
        } else {
            0.0
        };
        out.push_str(&format!(
            "{:<44} tried {:>7}  wrong {:>5}  ambiguous {:>5}  hits {:>7}  err mean {:.1e} max {:.1e}\n",
            self.name, self.tried, self.wrong, self.ambiguous, self.hits, mean, self.max_err
        ));
        for e in &self.examples {
            out.push_str(&format!("    e.g. {e}\n"));
        }
    }
}

/// Euclidean distance.
pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// A hit point as `[f64; 3]`.
pub fn p64<R: Real>(v: R::V3) -> [f64; 3] {
    R::xyz(v).map(|x| x.to_f64())
}

/// Footprint entry parameter of the ray (≥ `t_min`), `None` when it never enters.
pub fn footprint_entry(q: &Query<f64>, xm: f64, ym: f64) -> Option<f64> {
    let (o, d) = (q.origin(), q.dir());
    let (mut a, mut b) = (q.t_min(), q.t_max());
    for (axis, lim) in [xm, ym].into_iter().enumerate() {
        if d[axis] == 0.0 {
            if o[axis] < 0.0 || o[axis] > lim {
                return None;
            }
        } else {
            let (p, r) = ((0.0 - o[axis]) / d[axis], (lim - o[axis]) / d[axis]);
            a = a.max(p.min(r));
            b = b.min(p.max(r));
        }
    }
    (a <= b).then_some(a)
}

/// Where the tie rule of a discontinuous surface matters, for a ray the DDA and the
/// closed-solid brute force disagree on: the traced span starts exactly on a wall
/// (at `t_min` or where the ray enters the footprint), or the ray passes exactly
/// through a point where walls meet (corner planes: grid points; height planes: quarter
/// corners at half-integer x and y), touching the cells beside its path at one point.
pub fn tie_point(surface: Surface, q: &Query<f64>, xm: f64, ym: f64) -> bool {
    let off = match surface {
        Surface::CornerPlanes => 0.0,
        Surface::HeightPlanes => 0.5,
        _ => return false,
    };
    let on_wall = |x: f64| (x - off - (x - off).round()).abs() < 1e-12;
    let d = q.dir();
    let inside = |p: [f64; 3]| p[0] >= 0.0 && p[0] <= xm && p[1] >= 0.0 && p[1] <= ym;
    let mut starts = vec![q.t_min()];
    if let Some(te) = footprint_entry(q, xm, ym) {
        starts.push(te);
    }
    for t in starts {
        let p = q.at(t);
        if inside(p) && (0..2).any(|a| d[a] != 0.0 && on_wall(p[a])) {
            return true;
        }
    }
    if d[0] == 0.0 || d[1] == 0.0 {
        return false;
    }
    let o = q.origin();
    (0..=xm as i64).any(|k| {
        let t = (k as f64 + off - o[0]) / d[0];
        let y = o[1] + t * d[1];
        t >= q.t_min() && t <= q.t_max() && y >= 0.0 && y <= ym && on_wall(y)
    })
}

/// Relative tolerance of `f64` comparisons (positions, ambiguity).
pub const TOL64: f64 = 1e-9;
/// docs/DESIGN.md's "wrong" distance (texels), used for `f32`.
pub const WRONG: f64 = 1e-3;
/// Horizontal distance (texels) from a wall pinch point under which an `f32` ray on a
/// discontinuous surface is ambiguous (see [`near_pinch`]).
pub const PINCH: f64 = 1e-4;

/// What one ray came to, against brute force.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Same answer; the position error of a hit.
    Right(Option<f64>),
    /// The oracle's clearance is under the threshold (or, in `f32`, the ray passes a
    /// wall pinch point).
    Ambiguous,
    /// The `f64` traversal and brute force disagree on a touch: one of them meets the
    /// surface at zero clearance without going under it (ambiguous by docs/DESIGN.md's rule).
    Touch,
    /// The `f64` traversal and brute force disagree at a wall tie point of a
    /// discontinuous surface (see [`tie_point`]); the DDA's hit was checked to be no
    /// earlier than the closed solid's.
    Tie,
    /// A wrong ray, described.
    Wrong(String),
}

/// Traces `q` (in its own precision) and judges it against `brute::first_hit` on the
/// same ray in `f64`. `f64` traces must match to [`TOL64`] of the scene's length scale
/// and are ambiguous below `TOL64 · max(1, |z|)`; `f32` traces must match to
/// [`WRONG`] and are ambiguous by docs/DESIGN.md's rule (`hfcast::judge::ambiguous` on
/// the `f64` traversal), or near a wall pinch. Returns the outcome and whether brute
/// force hits.
pub fn judge<R: Real>(field: &Field, surface: Surface, q: &Query<R>) -> (Outcome, bool) {
    judge_march(field, surface, q, dda::trace(&field.hf(), surface, q))
}

/// [`judge`] of `tr`, another march's trace of `q` on `surface`.
pub fn judge_march<R: Real>(
    field: &Field,
    surface: Surface,
    q: &Query<R>,
    tr: Trace<R>,
) -> (Outcome, bool) {
    let is64 = R::EPSILON.to_f64() < 1e-10;
    let hf = field.hf();
    let q64 = q.cast::<f64>();
    let (xm, ym) = field.far_corner();
    let (zlo, zhi) = field.range();
    let (o, d) = (q64.origin(), q64.dir());
    let dlen = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let len_scale = 1f64
        .max(xm + ym)
        .max(zhi - zlo)
        .max(o.iter().fold(0f64, |m, v| m.max(v.abs())));
    let tol64 = TOL64 * len_scale;
    let zs = field.z_scale();
    let oracle = dda::trace(&hf, surface, &q64);
    let bf = brute::first_hit(&hf, surface, &q64);
    let brute_hits = bf.is_some();
    let ambiguous = match is64 {
        true => is_ambiguous(&oracle, TOL64 * zs),
        false => {
            judge::ambiguous(&hf, surface, &q64, &oracle) || near_pinch(field, surface, &q64, PINCH)
        }
    };
    if ambiguous {
        return (Outcome::Ambiguous, brute_hits);
    }
    let desc = |what: &str, got: String| {
        let samples = if field.samples.len() <= 150 {
            format!("{:?}", field.samples)
        } else {
            String::from("[..]")
        };
        format!(
            "{what}: {surface:?} field {}x{} stride {} {samples} query {q:?} brute {bf:?} got {got}",
            field.w, field.h, field.stride
        )
    };
    // The oracle against brute force first: touches and wall ties are settled there.
    let agree = match (oracle.hit, bf) {
        (None, None) => true,
        (Some(h), Some((tb, _))) => dist(p64::<f64>(h.point), q64.at(tb)) <= tol64,
        _ => false,
    };
    if !agree {
        let first = match (oracle.hit, bf) {
            (Some(h), Some((tb, _))) => h.t.min(tb),
            (Some(h), None) => h.t,
            (None, Some((tb, _))) => tb,
            (None, None) => unreachable!(),
        };
        let clear = |t: f64| {
            let p = q64.at(t);
            p[2] - surface.height_at(&hf, p[0], p[1])
        };
        let eps = TOL64 * zs;
        if clear(first).abs() <= eps && clear(first + 1e-4 / dlen) >= -eps {
            return (Outcome::Touch, brute_hits);
        }
        if tie_point(surface, &q64, xm, ym) {
            let ok = match (oracle.hit, bf) {
                (Some(h), Some((tb, _))) => tb <= h.t + tol64,
                (Some(_), None) => false,
                _ => true,
            };
            return if ok {
                (Outcome::Tie, brute_hits)
            } else {
                (
                    Outcome::Wrong(desc("tie", format!("{:?}", oracle.hit))),
                    brute_hits,
                )
            };
        }
    }
    let tol = if is64 { tol64 } else { WRONG };
    let (h, tb) = match (tr.hit, bf) {
        (None, None) => return (Outcome::Right(None), false),
        (Some(h), Some((tb, _))) => (h, tb),
        _ => {
            return (
                Outcome::Wrong(desc("hit/miss", format!("{:?}", tr.hit))),
                brute_hits,
            )
        }
    };
    let pd = p64::<R>(h.point);
    let e = dist(pd, q64.at(tb));
    let mut bad = Vec::new();
    if e > tol {
        bad.push("position");
    }
    if dist(pd, q64.at(h.t.to_f64())) > tol {
        bad.push("point != at(t)");
    }
    // The cell holds the point.
    let [ci, cj] = h.cell;
    if ci >= field.w - 1
        || cj >= field.h - 1
        || pd[0] < ci as f64 - tol
        || pd[0] > ci as f64 + 1.0 + tol
        || pd[1] < cj as f64 - tol
        || pd[1] > cj as f64 + 1.0 + tol
    {
        bad.push("cell");
    }
    // A unit normal.
    let n = p64::<R>(h.normal);
    if ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() > 1e-5 {
        bad.push("normal");
    }
    if tr.flags != Flags::default() || h.flags.contains(Flags::BUDGET_EXHAUSTED) {
        bad.push("trace flags");
    }
    if is64 {
        // Flags from the geometry: ORIGIN_INSIDE when the start point is over the
        // footprint and under the surface (the hit is at `t_min`), SIDE when the ray
        // enters the footprint from outside under the surface, WALL only on the
        // discontinuous surfaces.
        let f = h.flags;
        let p0 = q64.at(q64.t_min());
        let in_fp = p0[0] >= 0.0 && p0[0] <= xm && p0[1] >= 0.0 && p0[1] <= ym;
        let inside_flag_ok = if f.contains(Flags::ORIGIN_INSIDE) {
            in_fp && h.t.to_f64() == q64.t_min()
        } else {
            !(in_fp && tb == q64.t_min())
        };
        if !inside_flag_ok {
            bad.push("ORIGIN_INSIDE");
        }
        let side_hit =
            !in_fp && footprint_entry(&q64, xm, ym).is_some_and(|te| (tb - te).abs() * dlen <= tol);
        // A hit just past the entry (within `tol`) of a ray that enters above the
        // surface is not a side hit: it came down through the top.
        let enters_above = || {
            footprint_entry(&q64, xm, ym).is_some_and(|te| {
                let p = q64.at(te);
                p[2] > surface.height_at(&hf, p[0], p[1])
            })
        };
        let side_ok = if f.contains(Flags::SIDE) {
            // The normal of a side hit is the outward side normal.
            side_hit && n[2] == 0.0 && n[0].abs() + n[1].abs() == 1.0
        } else {
            !side_hit || enters_above()
        };
        if !side_ok {
            bad.push("SIDE");
        }
        if f.contains(Flags::WALL)
            && !matches!(surface, Surface::HeightPlanes | Surface::CornerPlanes)
        {
            bad.push("WALL");
        }
    } else if oracle.hit.map(|o| o.flags) != Some(h.flags)
        && flags_resolved(&hf, surface, &q64, &oracle)
    {
        // Flags f32 can resolve: the same on the oracle's rays moved by δ (an origin
        // exactly on the surface is inside, and a hit a hair later once lifted).
        bad.push("flags differ from the f64 traversal");
    }
    if bad.is_empty() {
        (Outcome::Right(Some(e)), true)
    } else {
        let what = bad.join(", ");
        (Outcome::Wrong(desc(&what, format!("{h:?}"))), true)
    }
}

/// Per-case counts of [`judge`] outcomes.
#[derive(Debug, Default)]
pub struct Judged {
    pub tally: Tally,
    pub touches: u64,
    pub ties: u64,
}

impl Judged {
    pub fn new(name: impl Into<String>) -> Judged {
        Judged {
            tally: Tally::new(name),
            ..Judged::default()
        }
    }
    /// Judges one query and counts the outcome.
    pub fn add<R: Real>(&mut self, field: &Field, surface: Surface, q: &Query<R>) {
        self.add_trace(field, surface, q, &dda::trace(&field.hf(), surface, q));
    }
    /// Judges another march's trace `tr` of `q` and counts the outcome.
    pub fn add_trace<R: Real>(
        &mut self,
        field: &Field,
        surface: Surface,
        q: &Query<R>,
        tr: &Trace<R>,
    ) {
        let (outcome, brute_hits) = judge_march(field, surface, q, *tr);
        let t = &mut self.tally;
        t.tried += 1;
        if brute_hits {
            t.hits += 1;
        }
        match outcome {
            Outcome::Right(Some(e)) => t.err(e),
            Outcome::Right(None) => {}
            Outcome::Ambiguous => t.ambiguous += 1,
            Outcome::Touch => {
                t.ambiguous += 1;
                self.touches += 1;
            }
            Outcome::Tie => self.ties += 1,
            Outcome::Wrong(s) => t.wrong(|| s),
        }
    }
    /// Adds another case's counts.
    pub fn absorb(&mut self, o: &Judged) {
        self.tally.absorb(&o.tally);
        self.touches += o.touches;
        self.ties += o.ties;
    }
    /// The report lines.
    pub fn report(&self, out: &mut String) {
        self.tally.report(out);
        if self.touches + self.ties > 0 {
            out.push_str(&format!(
                "    of the ambiguous, touches: {}; wall-point ties (checked only for order): {}\n",
                self.touches, self.ties
            ));
        }
    }
}

/// `per_kind` random rays of every [`RayKind`], then `2 · per_kind` grazing rays over
/// the footprint: up or down at 1e-4 to 0.1 rad, starting up to 0.05 above `surface`.
pub fn rays_with_grazing(
    field: &Field,
    surface: Surface,
    rng: &mut Rng,
    per_kind: usize,
) -> Vec<RaySpec> {
    let mut v = kind_blocks(rng, field, surface, &RayKind::ALL, per_kind);
    let hf = field.hf();
    let (xm, ym) = field.far_corner();
    for _ in 0..per_kind * 2 {
        let (x, y) = (rng.range(0.0, xm), rng.range(0.0, ym));
        let el = rng.sign() * 10f64.powf(rng.range(-4.0, -1.0));
        let az = rng.range(0.0, std::f64::consts::TAU);
        let z = surface.height_at(&hf, x, y) + rng.range(0.0, 0.05);
        v.push(RaySpec::whole(
            [x, y, z],
            [az.cos() * el.cos(), az.sin() * el.cos(), el.sin()],
        ));
    }
    v
}

/// Clearance of the ray above `surface` at `t` (negative under it).
pub fn clearance(field: &Field, surface: Surface, q: &Query<f64>, t: f64) -> f64 {
    let p = q.at(t);
    p[2] - surface.height_at(&field.hf(), p[0], p[1])
}

/// A touch: at the hit `t_hit` the ray meets `surface` without going under it (its
/// clearance 1e-4, 1e-3 and 1e-2 texel further on is at least `-eps`), so that which
/// side of the surface it passes by is decided by rounding (ambiguous, docs/DESIGN.md).
pub fn is_touch(field: &Field, surface: Surface, q: &Query<f64>, t_hit: f64, eps: f64) -> bool {
    let d = q.dir();
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [1e-4, 1e-3, 1e-2]
        .iter()
        .all(|s| clearance(field, surface, q, t_hit + s / len) >= -eps)
}

/// Parameters in `[t0, t1]` between which the clearance above the triangle surface is
/// linear: the ends and the crossings of the lines x, y, x − y, x + y = integer (cell
/// edges and both diagonals), sorted.
pub fn breakpoints(q: &Query<f64>, t0: f64, t1: f64) -> Vec<f64> {
    let (o, d) = (q.origin(), q.dir());
    let mut ts = vec![t0, t1];
    for [a, b] in [[1.0, 0.0], [0.0, 1.0], [1.0, -1.0], [1.0, 1.0]] {
        let (s0, ds) = (a * o[0] + b * o[1], a * d[0] + b * d[1]);
        if ds == 0.0 {
            continue;
        }
        let (sa, sb) = (s0 + ds * t0, s0 + ds * t1);
        for k in sa.min(sb).ceil() as i64..=sa.max(sb).floor() as i64 {
            let t = (k as f64 - s0) / ds;
            if t > t0 && t < t1 {
                ts.push(t);
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    ts
}

/// The main axis (0: x, 1: y) and direction (±1) of a ray class.
pub fn class_axis(class: RayClass) -> (usize, f64) {
    match class {
        RayClass::XPos => (0, 1.0),
        RayClass::XNeg => (0, -1.0),
        RayClass::YPos => (1, 1.0),
        RayClass::YNeg => (1, -1.0),
    }
}

/// Where the independent checks of the safety bakes draw their rays: the field's
/// view, its height scale ([`Field::z_scale`]) and relief ([`Field::relief`]).
pub struct Probe<'a> {
    pub hf: HeightField<'a>,
    pub zs: f64,
    pub relief: f64,
}

impl Probe<'_> {
    pub fn new(field: &Field) -> Probe<'_> {
        Probe {
            hf: field.hf(),
            zs: field.z_scale(),
            relief: field.relief(),
        }
    }

    /// The start of check ray number `r` from texel `(m, n)` (main axis `ax`): over
    /// the texel's segment across the main axis, at one of its ends, its middle or
    /// anywhere on it (by `r % 6`); on the triangle surface, 1e-6 · z above it or up
    /// to 0.3 × the relief above it (by `r % 4`).
    pub fn start(&self, rng: &mut Rng, ax: usize, [m, n]: [u32; 2], r: u32) -> [f64; 3] {
        let ln = f64::from(if ax == 0 {
            self.hf.height()
        } else {
            self.hf.width()
        });
        let y = match r % 6 {
            0 => f64::from(n) - 0.5,
            1 => f64::from(n) + 0.5,
            2 => f64::from(n),
            _ => f64::from(n) + rng.range(-0.5, 0.5),
        }
        .clamp(0.0, ln - 1.0);
        let mut p = [0.0; 3];
        p[ax] = f64::from(m);
        p[1 - ax] = y;
        let above = match r % 4 {
            0 => 0.0,
            1 => 1e-6 * self.zs,
            _ => rng.range(0.0, 0.3) * self.relief * rng.unit(),
        };
        p[2] = Surface::Triangles.height_at(&self.hf, p[0], p[1]) + above;
        p
    }

    /// How far ahead check ray number `r` aims (main-axis distance in `[1e-3, k)`) and
    /// its sideways slope: ±1, 0 or random in `[-1, 1)` (by `r % 5`).
    pub fn reach(rng: &mut Rng, k: u32, r: u32) -> (f64, f64) {
        let dist = rng.range(0.0, f64::from(k)).max(1e-3);
        let slope = match r % 5 {
            0 => 1.0,
            1 => -1.0,
            2 => 0.0,
            _ => rng.range(-1.0, 1.0),
        };
        (dist, slope)
    }
}

/// An independent bake check over `fields`, drawing from one generator seeded with
/// `seed`: `case(name, field, rng)` checks the field's bakes as they are (asserting no
/// violation) and returns the violations it finds with every claim inflated by one, of
/// which there must be some ([`assert_check_bites`]).
pub fn check_bakes(
    seed: u64,
    fields: Vec<(String, Field)>,
    mut case: impl FnMut(&str, &Field, &mut Rng) -> u64,
) {
    let mut rng = Rng::new(seed);
    let inflated_bad = fields
        .iter()
        .map(|(name, field)| case(name, field, &mut rng))
        .sum();
    assert_check_bites(inflated_bad);
}

/// The fractal field of the row-range tests: 23×17, rows padded to a stride of 25.
pub fn rows_field(seed: u64) -> Field {
    fractal_field(&mut Rng::new(seed), 23, 17, 25, 5.0)
}

/// `whole`, a byte map of `row` bytes a row, baked again by `bake_rows(rows, out)` in
/// the row ranges `ranges` (every row once), each into its rows of a buffer of
/// `whole`'s size: the bytes must be `whole`'s.
pub fn assert_rows_rebake(
    whole: &[u8],
    row: usize,
    ranges: &[Range<u32>],
    mut bake_rows: impl FnMut(Range<u32>, &mut [u8]),
) {
    let mut parts = vec![0u8; whole.len()];
    for r in ranges {
        bake_rows(
            r.clone(),
            &mut parts[r.start as usize * row..r.end as usize * row],
        );
    }
    assert_eq!(whole, parts);
}

/// An independent bake check must fail somewhere on the bakes inflated by one (their
/// `inflated_bad` violations): a check that never fails checks nothing.
pub fn assert_check_bites(inflated_bad: u64) {
    assert!(
        inflated_bad > 0,
        "the check never fails, even on an inflated bake"
    );
}

/// Judges the trace `got` of `q` on `surface` against the `f64` exact traversal: `Some(true)` right, `Some(false)` wrong, `None`
/// ambiguous.
pub fn judge_trace<R: Real>(
    field: &Field,
    surface: Surface,
    got: &Trace<R>,
    q: &Query<R>,
    zs: f64,
) -> Option<bool> {
    let oracle = dda::trace(&field.hf(), surface, &q.cast::<f64>());
    if oracle.clearance < eps_f32(zs) {
        return None;
    }
    let mask = Flags(Flags::ORIGIN_INSIDE.0 | Flags::SIDE.0);
    let right = match (oracle.hit, got.hit) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            let pa = a.point.to_array();
            let pb = R::xyz(b.point).map(|x| x.to_f64());
            dist(pa, pb) <= 1e-3 && (a.flags.0 & mask.0) == (b.flags.0 & mask.0)
        }
        _ => false,
    };
    // A touch (the ray meets the surface at zero clearance without going under it,
    // e.g. level with a ridge) is decided by rounding: ambiguous, as in docs/DESIGN.md.
    match oracle.hit {
        Some(hit) if !right && is_touch(field, surface, &q.cast(), hit.t, eps_f32(zs)) => None,
        _ => Some(right),
    }
}
