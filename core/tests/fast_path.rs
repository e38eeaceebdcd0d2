//! The fast path against the oracle: `dda::trace` on `Query<f32>` must give the same
//! answers as on the same query in `f64` (the cast is exact, so both trace exactly the
//! same ray) on fractal fields, except for ambiguous rays (the oracle's clearance below
//! docs/DESIGN.md's `2⁻¹³ · max(1, |z|)`), which are counted and printed. Hit points must
//! agree within 1e-4 texel (growing with the coordinates beyond 32, see `tight`;
//! docs/DESIGN.md's "wrong" is 1e-3).
//!
//! On the discontinuous surfaces (height planes, corner planes) a ray passing within
//! 1e-4 texel of a point where two walls touch along a vertical edge (a "pinch": quarter
//! corners, grid points) is ambiguous too: which side it passes is decided by rounding
//! of its horizontal position, which the clearance (a vertical distance) cannot see.
//!
//! And watertightness: a dense fan of `f32` rays aimed exactly at cell corners, along
//! shared edges and along cell diagonals, and vertical rays at integer and
//! half-integer coordinates, must never miss a surface the oracle hits. A naive `f32`
//! intersector (independent Möller–Trumbore tests per triangle) runs on the same fan
//! for comparison; its misses are printed to show that the fan does aim at the cracks.

mod common;

use common::*;
use hfcast::{dda, judge, Query, Surface};

/// The tighter bound this test holds the `f32` traversal to: 1e-4 texel for hit points
/// within 32 units of the origin, growing with the coordinates beyond (the spacing of
/// `f32` values does; 1e-4 is ~26 ulps at 32).
fn tight(p: [f64; 3]) -> f64 {
    1e-4 * 1f64.max(p.iter().fold(0f64, |m, v| m.max(v.abs())) / 32.0)
}

/// Compares the `f32` and `f64` traversals on one ray: wrong when hit or miss differ or
/// the points are further apart than [`tight`]; `over` counts right hits more than
/// 1e-4 texel apart (possible only far from the origin).
fn compare(field: &Field, surface: Surface, q32: &Query<f32>, tally: &mut Tally, over: &mut u64) {
    let hf = field.hf();
    let q64 = q32.cast::<f64>();
    let oracle = dda::trace(&hf, surface, &q64);
    let fast = dda::trace(&hf, surface, q32);
    let ambiguous =
        is_ambiguous(&oracle, eps_f32(field.z_scale())) || near_pinch(field, surface, &q64, PINCH);
    if !tally.ray(oracle.hit.is_some(), ambiguous) {
        return;
    }
    match (oracle.hit, fast.hit) {
        (None, None) => {}
        (Some(o), Some(f)) => {
            let e = tally.err_between(p64::<f64>(o.point), p64::<f32>(f.point));
            if e > WRONG {
                tally.wrong(|| format!("{surface:?} {q32:?}: f64 {o:?} f32 {f:?}"));
            } else if e > tight(p64::<f64>(o.point)) {
                tally.wrong(|| format!("{surface:?} {q32:?} off by {e:e}: f64 {o:?} f32 {f:?}"));
            } else if e > 1e-4 {
                *over += 1;
            }
        }
        (o, f) => tally.wrong(|| format!("{surface:?} {q32:?}: f64 {o:?} f32 {f:?}")),
    }
}

#[test]
fn f32_traversal_matches_f64_on_fractal_fields() {
    let mut rng = Rng::new(0xFA57);
    let fields = [
        ("64x64 amp 8", fractal_field(&mut rng, 64, 64, 64, 8.0)),
        (
            "129x77 stride 131 amp 30",
            fractal_field(&mut rng, 129, 77, 131, 30.0),
        ),
        ("96x40 amp 2 offset +200", {
            let mut f = fractal_field(&mut rng, 96, 40, 96, 2.0);
            f.samples.iter_mut().for_each(|h| *h += 200.0);
            f
        }),
    ];
    const RAYS_PER_KIND: usize = 120;
    let mut total = Tally::new("all fields, all surfaces");
    let mut total_over = 0;
    let mut out = String::from("f32 DDA vs f64 DDA on fractal fields (ambiguous: 2^-13 max(1,|z|), or near a wall pinch)\n");
    for (name, field) in &fields {
        for surface in Surface::ALL {
            let mut t = Tally::new(format!("{name} / {}", surface.name()));
            let mut over = 0;
            for spec in of_kinds(&mut rng, field, surface, &RayKind::ALL, RAYS_PER_KIND) {
                compare(field, surface, &spec.q32(), &mut t, &mut over);
            }
            t.report(&mut out);
            if over > 0 {
                out.push_str(&format!(
                    "    {over} right hits are 1e-4 .. tight() texel off (far from the origin)\n"
                ));
            }
            total.absorb(&t);
            total_over += over;
        }
    }
    total.report(&mut out);
    println!(
        "{out}    {total_over} right hits are 1e-4 .. tight() texel off (far from the origin)"
    );
    assert_eq!(total.wrong, 0, "f32 traversal wrong against the f64 oracle");
    assert!(total.ambiguous * 10 < total.tried);
}

/// Fields for the watertightness fan: a fractal, integer-valued needles on a flat
/// ground, and a checkerboard of ridges (every cell a saddle or a fold).
fn crack_fields(rng: &mut Rng) -> Vec<(&'static str, Field)> {
    let needles = {
        let mut r = Rng::new(rng.next_u64());
        Field::from_fn(33, 29, 35, |_, _| {
            if r.chance(0.15) {
                r.int(1, 9) as f32
            } else {
                0.0
            }
        })
    };
    let checker = Field::from_fn(31, 31, 31, |i, j| ((i + j) % 2) as f32 * 3.0);
    vec![
        ("fractal 48x40", fractal_field(rng, 48, 40, 48, 6.0)),
        ("needles 33x29", needles),
        ("checker 31x31", checker),
    ]
}

/// The fan: `f32` queries whose xy path passes exactly through grid points, along
/// shared edges or along cell diagonals; every coordinate involved is exact in `f32`.
fn fan(field: &Field, surface: Surface, rng: &mut Rng) -> Vec<Query<f32>> {
    let hf = field.hf();
    let (w, h) = (field.w as i64, field.h as i64);
    let mut out = Vec::new();
    let q = |o: [f32; 3], d: [f32; 3]| Query::from_arrays(o, d, 0.0, f32::INFINITY).unwrap();
    let top = field.range().1 as f32 + 2.0;
    // Vertical rays at every grid point and every edge midpoint.
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (i as f32, j as f32);
            out.push(q([x, y, top], [0.0, 0.0, -1.0]));
            if i + 1 < w {
                out.push(q([x + 0.5, y, top], [0.0, 0.0, -1.0]));
            }
            if j + 1 < h {
                out.push(q([x, y + 0.5, top], [0.0, 0.0, -1.0]));
            }
        }
    }
    // Rays through grid points from small integer directions, passing the point a
    // little under the surface (so the hit is right next to the point, on whichever
    // side), and rays along edges (one horizontal component zero) and diagonals.
    for j in 0..h {
        for i in 0..w {
            for _ in 0..6 {
                let d = loop {
                    let d = [rng.int(-2, 2) as f32, rng.int(-2, 2) as f32];
                    if d != [0.0, 0.0] {
                        break d;
                    }
                };
                let dz = -(rng.int(1, 24) as f32) / 8.0;
                let zc = surface.height_at(&hf, i as f32, j as f32);
                let below = [0.01f32, 0.001, 0.1][rng.below(3)];
                let k = rng.int(1, 4) as f32;
                let o = [
                    i as f32 - k * d[0],
                    j as f32 - k * d[1],
                    zc - below - k * dz,
                ];
                out.push(q(o, [d[0], d[1], dz]));
            }
        }
    }
    out
}

/// Naive `f32` ray–triangle test (Möller–Trumbore), each triangle on its own.
fn moller_trumbore(o: [f32; 3], d: [f32; 3], v: [[f32; 3]; 3]) -> Option<f32> {
    let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f32; 3], b: [f32; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(o, v[0]);
    let u = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = cross(s, e1);
    let vv = dot(d, qv) * inv;
    if vv < 0.0 || u + vv > 1.0 {
        return None;
    }
    let t = dot(e2, qv) * inv;
    (t >= 0.0).then_some(t)
}

/// `true` when the naive intersector finds any triangle of the split docs/DESIGN.md uses.
fn naive_hits(field: &Field, q: &Query<f32>) -> bool {
    let (o, d) = (q.origin(), q.dir());
    let hf = field.hf();
    for j in 0..field.h - 1 {
        for i in 0..field.w - 1 {
            let (x, y) = (i as f32, j as f32);
            let [h00, h10, h01, h11] = hf.cell_corners(i, j);
            let p00 = [x, y, h00];
            let p10 = [x + 1.0, y, h10];
            let p01 = [x, y + 1.0, h01];
            let p11 = [x + 1.0, y + 1.0, h11];
            let tris = if h00 + h11 <= h10 + h01 {
                [[p00, p10, p11], [p00, p11, p01]]
            } else {
                [[p00, p10, p01], [p10, p11, p01]]
            };
            if tris.iter().any(|&t| moller_trumbore(o, d, t).is_some()) {
                return true;
            }
        }
    }
    false
}

#[test]
fn f32_traversal_is_watertight_on_corners_edges_and_diagonals() {
    let mut rng = Rng::new(0x7A7E);
    let mut total = Tally::new("all fields, all surfaces");
    let mut out = String::from("watertightness: f32 fan at corners, edges, diagonals vs f64 DDA\n");
    for (name, field) in crack_fields(&mut rng) {
        let hf = field.hf();
        for surface in Surface::ALL {
            let rays = fan(&field, surface, &mut rng);
            let mut t = Tally::new(format!("fan {name} / {}", surface.name()));
            // Misses of rays the oracle hits, among ambiguous rays (allowed, counted).
            let mut ambiguous_slips = 0;
            let mut naive_misses = 0;
            for q in &rays {
                let oracle = dda::trace(&hf, surface, &q.cast::<f64>());
                let fast = dda::trace(&hf, surface, q);
                t.tried += 1;
                let Some(oh) = oracle.hit else {
                    // Every fan ray passes under a continuous surface: it must hit. (On
                    // the discontinuous ones the height at a grid point depends on the
                    // cell the ray comes from, so some rays pass.)
                    if surface.is_continuous() {
                        t.wrong(|| format!("oracle misses a fan ray {q:?}"));
                    }
                    if fast.hit.is_some() {
                        t.wrong(|| format!("{surface:?} f32 hits where the oracle does not {q:?}"));
                    }
                    continue;
                };
                t.hits += 1;
                if surface == Surface::Triangles && !naive_hits(&field, q) {
                    naive_misses += 1;
                }
                // A touch (a double root: the ray grazes a bilinear patch) has its zero
                // clearance at the hit, where the oracle's measure stops: docs/DESIGN.md's
                // rule (moving the origin by δ) flags it. Asked only where the answers
                // differ: a fan ray passes samples, and the rule flags a fifth of them.
                let q64 = q.cast::<f64>();
                let off = fast
                    .hit
                    .is_none_or(|fh| dist(p64::<f64>(oh.point), p64::<f32>(fh.point)) > WRONG);
                if is_ambiguous(&oracle, eps_f32(field.z_scale()))
                    || near_pinch(&field, surface, &q64, PINCH)
                    || off && judge::ambiguous(&hf, surface, &q64, &oracle)
                {
                    t.ambiguous += 1;
                    if fast.hit.is_none() {
                        ambiguous_slips += 1;
                    }
                    continue;
                }
                match fast.hit {
                    None => {
                        t.wrong(|| format!("{surface:?} f32 slips through {q:?}, oracle {oh:?}"))
                    }
                    Some(fh) => {
                        if t.err_between(p64::<f64>(oh.point), p64::<f32>(fh.point)) > WRONG {
                            t.wrong(|| format!("{surface:?} {q:?}: f64 {oh:?} f32 {fh:?}"));
                        }
                    }
                }
            }
            t.report(&mut out);
            if ambiguous_slips > 0 {
                out.push_str(&format!(
                    "    ambiguous rays the f32 path misses: {ambiguous_slips}\n"
                ));
            }
            if surface == Surface::Triangles {
                out.push_str(&format!(
                    "    naive f32 per-triangle test (Moller-Trumbore) misses {naive_misses} of these {} rays\n",
                    rays.len()
                ));
            }
            total.absorb(&t);
        }
    }
    total.report(&mut out);
    println!("{out}");
    assert_eq!(total.wrong, 0, "the f32 traversal lets rays through");
    // Teeth: most of the fan is compared (the pinch points of the discontinuous
    // surfaces take the bulk of the ambiguous rays).
    assert!(total.ambiguous * 5 < total.tried);
}
