//! Issue 25, item 1, through the C API: rays far from the field, tiny and huge
//! directions, heights near ±10³⁸, a depth of `FLT_MAX`. Every case calls the exported
//! `hf_*` functions and compares with the `f64` exact traversal of the core on the same
//! ray; each failed before the rays were conditioned (`hfcore::condition`), as the
//! tests show by tracing the same rays unconditioned with the core's `f32` DDA.

use crate::bake::{hf_bake, hf_bake_options, hf_bake_options_default, hf_map_len};
use crate::field::{hf_field, hf_field_create_f32, hf_field_create_u16, hf_field_destroy};
use crate::field::{hf_field_get_info, hf_field_info};
use crate::hf_result::{self, *};
use crate::trace::{hf_hit, hf_ray, hf_trace, hf_trace_options};
use hfcore::scene::MethodKind;
use hfcore::{dda, HeightField, Query, Surface};
use std::ffi::c_void;

/// A field through the C API, its heights kept for the oracle, and its maps.
struct Field {
    w: u32,
    h: u32,
    heights: Vec<f32>,
    handle: *mut hf_field,
    pyr: Vec<f32>,
    sd: Vec<u8>,
    cc: Vec<u8>,
    rad: Vec<u8>,
    cone: Vec<f32>,
    qdm: Vec<f32>,
}

const CC_CAP: u32 = 64;

/// `len` elements of `T`'s zero.
fn zeros<T: Clone + Default>(len: usize) -> Vec<T> {
    vec![T::default(); len]
}

/// `method`'s map of `handle`, baked through `hf_map_len` and `hf_bake` on two
/// threads with the default options changed by `set`.
fn baked<T: Copy + Default>(
    handle: *mut hf_field,
    method: MethodKind,
    set: impl FnOnce(&mut hf_bake_options),
) -> Vec<T> {
    // SAFETY: valid buffers and lengths throughout.
    unsafe {
        let mut o = core::mem::zeroed::<hf_bake_options>();
        assert_eq!(hf_bake_options_default(method as u32, &mut o), HF_OK);
        o.threads = 2;
        set(&mut o);
        let mut info = core::mem::zeroed::<hf_field_info>();
        assert_eq!(hf_field_get_info(handle, &mut info), HF_OK);
        let mut n = 0;
        assert_eq!(
            hf_map_len(method as u32, info.width, info.height, &o, &mut n),
            HF_OK
        );
        let mut map = zeros::<T>(n);
        let r = hf_bake(method as u32, handle, &o, map.as_mut_ptr().cast(), n);
        assert_eq!(r, HF_OK);
        map
    }
}

impl Field {
    fn new(w: u32, h: u32, heights: Vec<f32>) -> Field {
        let mut handle = core::ptr::null_mut();
        // SAFETY: valid buffers and lengths throughout.
        unsafe {
            let r = hf_field_create_f32(
                heights.as_ptr(),
                heights.len(),
                w,
                h,
                w as usize,
                &mut handle,
            );
            assert_eq!(r, HF_OK);
            let pyr = baked(handle, MethodKind::MaxMip, |_| {});
            let sd = baked(handle, MethodKind::Safety, |_| {});
            let cc = baked(handle, MethodKind::Cc, |o| {
                o.slope = 1;
                o.cap = CC_CAP;
            });
            let rad = baked(handle, MethodKind::Radius, |_| {});
            let cone = baked(handle, MethodKind::Cone, |_| {});
            let qdm = baked(handle, MethodKind::Qdm, |_| {});
            Field {
                w,
                h,
                heights,
                handle,
                pyr,
                sd,
                cc,
                rad,
                cone,
                qdm,
            }
        }
    }

    fn view(&self) -> HeightField<'_> {
        HeightField::new(&self.heights, self.w, self.h, self.w as usize).unwrap()
    }

    /// Every exact method's answer to `r` through the C API, named.
    fn trace_all(&self, r: &hf_ray) -> Vec<(&'static str, hf_result, hf_hit)> {
        let opts = hf_trace_options {
            steps: 100_000,
            ..hf_trace_options::default()
        };
        let bytes = |m: &[u8]| (m.as_ptr().cast::<c_void>(), m.len());
        let floats = |m: &[f32]| (m.as_ptr().cast::<c_void>(), m.len());
        let maps = [
            (MethodKind::Exact, (std::ptr::null(), 0)),
            (MethodKind::MaxMip, floats(&self.pyr)),
            (MethodKind::Safety, bytes(&self.sd)),
            (MethodKind::Cc, bytes(&self.cc)),
            (MethodKind::Radius, bytes(&self.rad)),
            (MethodKind::Cone, floats(&self.cone)),
            (MethodKind::Qdm, floats(&self.qdm)),
        ];
        let mut out = Vec::new();
        for (m, (map, len)) in maps {
            let mut hit = hf_hit::default();
            // SAFETY: live handle, valid maps and pointers.
            let code = unsafe { hf_trace(self.handle, m as u32, map, len, &opts, r, &mut hit) };
            out.push((m.name(), code, hit));
        }
        out
    }
}

impl Drop for Field {
    fn drop(&mut self) {
        // SAFETY: the live handle from `new`, destroyed once.
        unsafe { hf_field_destroy(self.handle) };
    }
}

/// A small deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Rolling hills with a needle, `w × h`.
fn hills(w: u32, h: u32) -> Vec<f32> {
    let mut v: Vec<f32> = (0..w * h)
        .map(|k| {
            let (i, j) = ((k % w) as f32, (k / w) as f32);
            2.0 + 1.5 * (0.31 * i).sin() * (0.23 * j).cos() + 0.4 * (1.7 * i + 0.9 * j).sin()
        })
        .collect();
    v[(h / 2 * w + w / 3) as usize] = 9.0;
    v
}

/// The oracle's answer to the ray `o + t·d` (`f32` values), and its clearance.
fn oracle(hf: &HeightField, o: [f32; 3], d: [f32; 3]) -> (Option<[f64; 3]>, f64) {
    let q =
        Query::<f64>::from_arrays(o.map(f64::from), d.map(f64::from), 0.0, f64::INFINITY).unwrap();
    let tr = dda::trace(hf, Surface::Triangles, &q);
    (tr.hit.map(|h| h.point.to_array()), tr.clearance)
}

/// Largest distance over the axes.
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).fold(0.0, |m, k| m.max((a[k] - b[k]).abs()))
}

/// The error of an answer against the oracle: 0 for agreeing misses, ∞ for a
/// hit/miss disagreement, else the distance between the hit points.
fn error(hit: &hf_hit, want: Option<[f64; 3]>) -> f64 {
    match (hit.hit == 1, want) {
        (false, None) => 0.0,
        (true, Some(p)) => dist(hit.point.map(f64::from), p),
        _ => f64::INFINITY,
    }
}

/// Rays from `far` texels away (around, above and at a slant), aimed at random points
/// of the field; each with the oracle's answer. Ambiguous rays (the oracle's clearance
/// under 2⁻¹³ near the hit) are left out.
fn far_rays(rng: &mut Rng, f: &Field, far: f64, n: usize) -> Vec<(hf_ray, Option<[f64; 3]>)> {
    let hf = f.view();
    let (xm, ym) = (f64::from(f.w - 1), f64::from(f.h - 1));
    let mut out = Vec::new();
    while out.len() < n {
        let k = out.len();
        let o = match k % 5 {
            0 => [-far, rng.range(0.0, ym), rng.range(0.0, 40.0)],
            1 => [xm + far, rng.range(0.0, ym), rng.range(0.0, 40.0)],
            2 => [rng.range(0.0, xm), -far, rng.range(0.0, 40.0)],
            3 => [far, far, far * 0.3],
            _ => [rng.range(0.0, xm), rng.range(0.0, ym), far],
        };
        let p = [rng.range(0.0, xm), rng.range(0.0, ym), rng.range(0.0, 4.0)];
        let o = o.map(|v| v as f32);
        let d = [0, 1, 2].map(|a| (p[a] - f64::from(o[a])) as f32);
        let (want, clearance) = oracle(&hf, o, d);
        if clearance.abs() < 1.0 / 8192.0 {
            continue;
        }
        let ray = hf_ray {
            origin: o,
            dir: d,
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        out.push((ray, want));
    }
    out
}

#[test]
fn far_orbits_hit_as_near_rays() {
    far_orbits(Field::new(65, 49, hills(65, 49)), &[1e4, 1e5, 1e6]);
}

#[test]
fn far_orbits_over_an_8193_wide_field() {
    // The box itself is 8192 long: 10^5 away is 12 of its extents, and a ray along it
    // crosses thousands of cells after the rebase.
    far_orbits(Field::new(8193, 9, hills(8193, 9)), &[1e5, 1e6]);
}

/// Far rays around `f` at each distance: every exact method within
/// `max(1e-3, 8 · eps32 · |p|∞)` texel of the oracle's hit `p` (what `f32` resolves
/// there, whatever the origin's distance), and the unconditioned `f32` DDA off by more
/// than four times the conditioned worst at 10^5 and beyond.
fn far_orbits(f: Field, distances: &[f64]) {
    let hf = f.view();
    let mut rng = Rng(25);
    for &far in distances {
        let rays = far_rays(&mut rng, &f, far, 60);
        let mut worst = 0.0f64;
        let mut plain_worst = 0.0f64;
        for (r, want) in &rays {
            for (name, code, hit) in f.trace_all(r) {
                assert_eq!(code, HF_OK, "{name}");
                let e = error(&hit, *want);
                // What f32 resolves at the hit, wherever the ray came from.
                let at = want.map_or(0.0, |p| p.iter().fold(0.0f64, |m, v| m.max(v.abs())));
                let tol = 1e-3f64.max(8.0 * f64::from(f32::EPSILON) * at);
                assert!(
                    e <= tol,
                    "{name} from {far:e}: error {e:e} texel, ray {r:?}"
                );
                worst = worst.max(e);
            }
            // The same ray traced unconditioned, as before issue 25.
            let q = Query::from_arrays(r.origin, r.dir, 0.0, f32::INFINITY).unwrap();
            let tr = dda::trace(&hf, Surface::Triangles, &q);
            let plain = match (tr.hit, want) {
                (None, None) => 0.0,
                (Some(h), Some(p)) => dist(h.point.to_array().map(f64::from), *p),
                _ => f64::INFINITY,
            };
            plain_worst = plain_worst.max(plain);
        }
        println!(
            "far orbits at {far:e} around {} x {}: {} rays, worst error {worst:.1e} texel \
             conditioned, {plain_worst:.1e} unconditioned",
            f.w,
            f.h,
            rays.len()
        );
        if far >= 1e5 {
            assert!(
                plain_worst > 4.0 * worst.max(1e-4),
                "the unconditioned f32 march was as good at {far:e}"
            );
        }
    }
}

/// One ray through every exact method: each hits at `want` (within `tol` texels).
fn all_hit(f: &Field, r: &hf_ray, want: [f64; 3], tol: f64) {
    for (name, code, hit) in f.trace_all(r) {
        assert_eq!(code, HF_OK, "{name}");
        let e = error(&hit, Some(want));
        assert!(e <= tol, "{name}: {hit:?}, want {want:?}");
    }
}

/// A needle at sample (2, 1) rising to 2 over a flat 5 × 4 field.
fn needle_field() -> Field {
    let mut h = vec![0.0f32; 20];
    h[5 + 2] = 2.0;
    Field::new(5, 4, h)
}

#[test]
fn a_level_ray_from_minus_1_8e9_hits() {
    let f = needle_field();
    let r = hf_ray {
        origin: [-1.8e9, 1.0, 1.0],
        dir: [1.0, 0.0, 0.0],
        t_min: 0.0,
        t_max: f32::INFINITY,
    };
    let q = Query::from_arrays(r.origin, r.dir, 0.0, f32::INFINITY).unwrap();
    assert!(dda::trace(&f.view(), Surface::Triangles, &q).hit.is_none());
    all_hit(&f, &r, [1.5, 1.0, 1.0], 1e-6);
}

#[test]
fn a_vertical_ray_from_3e8_reports_its_height() {
    let f = needle_field();
    let r = hf_ray {
        origin: [2.0, 1.0, 3e8],
        dir: [0.0, 0.0, -1.0],
        t_min: 0.0,
        t_max: f32::INFINITY,
    };
    let q = Query::from_arrays(r.origin, r.dir, 0.0, f32::INFINITY).unwrap();
    // Unconditioned, the f32 DDA's point was at z = 0 before the robust finish
    // (`dda::finish` recomputes it in f64); now it is right too.
    let plain = dda::trace(&f.view(), Surface::Triangles, &q).hit.unwrap();
    assert!((plain.point.z - 2.0).abs() < 1e-6, "{plain:?}");
    all_hit(&f, &r, [2.0, 1.0, 2.0], 1e-6);
}

#[test]
fn tiny_and_huge_directions_are_traced() {
    let f = needle_field();
    for scale in [1e-37f32, 1e-40, 1e-44, 1e-20, 1e20, 1e37] {
        let r = hf_ray {
            origin: [0.5, 1.0, 1.0],
            dir: [scale, 0.0, 0.0],
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        all_hit(&f, &r, [1.5, 1.0, 1.0], 1e-6);
        let q = Query::from_arrays(r.origin, r.dir, 0.0, f32::INFINITY).unwrap();
        let plain = dda::trace(&f.view(), Surface::Triangles, &q);
        println!(
            "direction {scale:e}: unconditioned hit {:?}",
            plain.hit.map(|h| h.point)
        );
        if scale <= 1e-40 {
            // Every quotient overflows: a miss without a fetch, before issue 25.
            assert!(
                plain.hit.is_none() && plain.fetches == 0,
                "{scale:e}: {plain:?}"
            );
        }
    }
}

#[test]
fn heights_near_1e38_are_traced() {
    // Heights from -1e38 to 1e38: the clip's margin (1 + range) overflows f32.
    let mut h = vec![-1e38f32; 16];
    h[5] = 1e38;
    h[6] = 0.0;
    let f = Field::new(4, 4, h);
    for o in [
        [1.25f32, 1.25, 2e38],
        [2.5, 2.5, 0.0],
        [1.0, 1.0, 3e38],
        [0.5, 2.0, -5e37],
    ] {
        let r = hf_ray {
            origin: o,
            dir: [0.0, 0.0, -1.0],
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        let want = oracle(&f.view(), o, r.dir)
            .0
            .expect("a ray down into the solid hits");
        let q = Query::from_arrays(r.origin, r.dir, 0.0, f32::INFINITY).unwrap();
        println!(
            "{o:?}: unconditioned {:?}",
            dda::trace(&f.view(), Surface::Triangles, &q).hit
        );
        let mut hit = hf_hit::default();
        // SAFETY: live handle, valid pointers.
        let exact = MethodKind::Exact as u32;
        let code = unsafe {
            hf_trace(
                f.handle,
                exact,
                std::ptr::null(),
                0,
                std::ptr::null(),
                &r,
                &mut hit,
            )
        };
        assert_eq!(code, HF_OK);
        assert_eq!(hit.hit, 1, "{o:?}: {hit:?}");
        let rel = dist(hit.point.map(f64::from), want) / 1e38;
        assert!(rel < 1e-6, "{o:?}: {hit:?}, want {want:?}");
    }
}

#[test]
fn a_depth_of_flt_max_is_finite() {
    let samples = [0u16, 65535, 32768, 1];
    let mut f = core::ptr::null_mut();
    // SAFETY: valid buffers.
    let r = unsafe { hf_field_create_u16(samples.as_ptr(), 4, 2, 2, 2, f32::MAX, &mut f) };
    assert_eq!(r, HF_OK);
    let mut info = hf_field_info::default();
    // SAFETY: the live handle.
    unsafe {
        assert_eq!(hf_field_get_info(f, &mut info), HF_OK);
        hf_field_destroy(f);
    }
    assert_eq!((info.min_height, info.max_height), (0.0, f32::MAX));
}

/// Item 2's touches: rays on the ray-class boundary (`|dx| = |dy|`) that pass exactly
/// through a needle's tip at a grid corner and stay above the surface on both sides.
/// docs/DESIGN.md calls a touch ambiguous (any exact method may report it or pass it);
/// the old rule (clearance before the hit under 2⁻¹³ · max|z|) did not, so the safety,
/// cylinder–cone and radius marches, which pass such a tip where the DDA and the
/// maximum mipmap report it, counted as wrong. Every exact method through the C API
/// must give one of the two answers, the touch or the pass (here a miss), nothing
/// else.
#[test]
fn grid_corner_touches_on_class_boundary_diagonals() {
    let (w, h) = (24u32, 24u32);
    let needles = [(6u32, 6u32), (12, 9), (17, 15)];
    let mut heights = vec![0.0f32; (w * h) as usize];
    for &(i, j) in &needles {
        heights[(j * w + i) as usize] = 4.0;
    }
    let f = Field::new(w, h, heights);
    let hf = f.view();
    let (mut touches, mut passes) = (0, 0);
    for &(i, j) in &needles {
        for (sx, sy) in [(1.0f32, 1.0f32), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
            // Exact in f32: at t = 16 the ray is at the tip (i, j, 4).
            let d = [sx, sy, -1.0 / 16.0];
            let o = [i as f32 - 16.0 * sx, j as f32 - 16.0 * sy, 5.0];
            let q =
                Query::<f64>::from_arrays(o.map(f64::from), d.map(f64::from), 0.0, f64::INFINITY)
                    .unwrap();
            let tr = dda::trace(&hf, Surface::Triangles, &q);
            assert!(
                hfcore::judge::ambiguous(&hf, Surface::Triangles, &q, &tr),
                "{o:?} {d:?}"
            );
            assert!(
                tr.clearance > 4.0 / 8192.0,
                "the old rule called it ambiguous: {tr:?}"
            );
            let tip = [f64::from(i), f64::from(j), 4.0];
            let r = hf_ray {
                origin: o,
                dir: d,
                t_min: 0.0,
                t_max: f32::INFINITY,
            };
            for (name, code, hit) in f.trace_all(&r) {
                if matches!(name, "cone" | "qdm") {
                    continue;
                }
                assert_eq!(code, HF_OK, "{name}");
                match hit.hit {
                    0 => passes += 1,
                    _ => {
                        assert!(
                            error(&hit, Some(tip)) <= 1e-5,
                            "{name}: {hit:?} at {o:?} {d:?}"
                        );
                        touches += 1;
                    }
                }
            }
        }
    }
    // The DDA reports touches (here all five methods do: 60 touches, 0 passes), and
    // every ray was traced by all five.
    assert!(touches > 0, "{touches} touches, {passes} passes");
    assert_eq!(touches + passes, needles.len() * 4 * 5);
}
