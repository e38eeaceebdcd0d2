//! Stiff cases (from the issue): grazing elevation 1e-4 rad; axis-parallel rays;
//! vertical rays at integer and half-integer coordinates; origins exactly on corners;
//! an 8193 × 16 field (f32 cell-index precision); height ranges 1e-6 and 1e6; all-equal
//! heights; 2 × 2 fields; 2 × 4096 fields. For each, the `f32` and `f64` traversals
//! against brute force (`common::judge`): zero wrong rays, ambiguous ones counted.
//!
//! Plus the stiff spots of the bilinear quadratic (`surface::smallest_root_in_unit`):
//! far-apart roots, `A = 0` exactly, a (near-)double root, and rays parallel to cell
//! edges and along diagonals of saddle cells.
//!
//! "Wrong" for `f32` is docs/DESIGN.md's: hit/miss differs or the hit point is more than
//! 1e-3 from brute force's, as a 3-D distance in grid units. Readings documented here:
//! for the 1e6 height range the `z` of a hit cannot be within 1e-3 in `f32` (its spacing
//! there is 0.06), so that case measures the `f32` error as the horizontal distance plus
//! the `z` distance relative to `max(1, |z|)` — the same scaling the ambiguity rule
//! uses — and keeps ray origins near the footprint horizontally (an origin 1e5 texels
//! away costs any `f32` computation ~1e-2 texel, whatever the heights). On the
//! 8193-wide field `f32` positions near x = 8192 are spaced 2⁻¹⁰ ≈ 1e-3 apart; the
//! traversal's hit points must still be within 1e-3.

mod common;

use common::*;
use hfcast::surface::smallest_root_in_unit;
use hfcast::{brute, dda, Query, Surface};

/// The `f64` and `f32` judgements of one case: "`name` / f64" and "`name` / f32".
struct Both {
    j64: Judged,
    j32: Judged,
}

impl Both {
    fn new(name: &str) -> Both {
        Both {
            j64: Judged::new(format!("{name} / f64")),
            j32: Judged::new(format!("{name} / f32")),
        }
    }

    /// Judges `spec` on `field` and `surface` in both precisions.
    fn add(&mut self, field: &Field, surface: Surface, spec: &RaySpec) {
        self.j64.add(field, surface, &spec.q64());
        self.j32.add(field, surface, &spec.q32());
    }

    /// Appends both per-case lines to `out` and adds both counts to `all`.
    fn report_into(&self, out: &mut String, all: &mut Judged) {
        self.j64.report(out);
        self.j32.report(out);
        all.absorb(&self.j64);
        all.absorb(&self.j32);
    }
}

/// Judges every ray of `rays` on every surface, in `f64` and in `f32`, and appends the
/// per-case lines; returns both precisions' counts together.
fn run_case(
    out: &mut String,
    name: &str,
    field: &Field,
    rays: &mut dyn FnMut(Surface) -> Vec<RaySpec>,
) -> Judged {
    let mut both = Both::new(name);
    for surface in Surface::ALL {
        for spec in rays(surface) {
            both.add(field, surface, &spec);
        }
    }
    let Both { mut j64, j32 } = both;
    j64.report(out);
    j32.report(out);
    j64.absorb(&j32);
    j64
}

/// Appends the totals `all` to `out`, prints it and asserts no wrong ray and few
/// enough ambiguous ones (under 1 in 7) for the case to be a test.
fn finish(mut out: String, all: &Judged) {
    all.report(&mut out);
    println!("{out}");
    assert_eq!(all.tally.wrong, 0);
    assert!(
        all.tally.ambiguous * 7 < all.tally.tried,
        "too few rays compared"
    );
}

#[test]
fn stiff_rays_on_small_fields() {
    let mut rng = Rng::new(0x57_1FF);
    let mut out = String::from("stiff rays: f64 / f32 DDA vs brute force\n");
    let mut fields: Vec<Field> = (0..40).map(|_| small_field(&mut rng)).collect();
    fields.push(fractal_field(&mut rng, 24, 20, 27, 3.0));
    // A tilted plane: grazing rays along the slope graze at every step.
    fields.push(Field::from_fn(12, 9, 12, |i, j| {
        0.3 * i as f32 + 0.1 * j as f32
    }));

    type Gen = fn(&mut Rng, &Field, Surface) -> Vec<RaySpec>;
    let cases: [(&str, Gen); 4] = [
        ("grazing 1e-4 rad", |r, f, s| grazing(r, f, s, 40, 1e-4)),
        ("axis-parallel", |r, f, s| {
            of_kinds(r, f, s, &[RayKind::AxisX, RayKind::AxisY], 12)
        }),
        ("vertical, integer / half-integer xy", |r, f, s| {
            of_kinds(r, f, s, &[RayKind::VerticalInt, RayKind::VerticalHalf], 12)
        }),
        ("origin on a corner / centerline", |r, f, s| {
            of_kinds(
                r,
                f,
                s,
                &[RayKind::CornerOrigin, RayKind::CenterlineOrigin],
                12,
            )
        }),
    ];
    let mut all = Judged::new("all stiff rays, both precisions");
    for (name, gen) in cases {
        let mut both = Both::new(name);
        for field in &fields {
            for surface in Surface::ALL {
                for spec in gen(&mut rng, field, surface) {
                    both.add(field, surface, &spec);
                }
            }
        }
        both.report_into(&mut out, &mut all);
    }
    finish(out, &all);
}

#[test]
fn stiff_fields() {
    let mut rng = Rng::new(0xF1E1D);
    let mut out = String::from("stiff fields: f64 / f32 DDA vs brute force\n");
    let mut all = Judged::new("all stiff fields, both precisions");

    // All-equal heights (several levels), 2 × 2 fields, tiny and huge height ranges.
    for level in [0.0f32, 2.5, -3.0, 1000.0] {
        let field = Field::from_fn(7, 5, 9, |_, _| level);
        let name = format!("all heights {level}");
        all.absorb(&run_case(&mut out, &name, &field, &mut |s| {
            of_kinds(&mut rng, &field, s, &RayKind::ALL, 12)
        }));
    }
    {
        let mut both = Both::new("2x2 fields");
        for k in 0..150 {
            let stride = 2 + k % 3;
            let field = Field::from_fn(2, 2, stride, |_, _| {
                if k % 2 == 0 {
                    rng.int(0, 2) as f32
                } else {
                    rng.range(-1.0, 1.0) as f32
                }
            });
            for surface in Surface::ALL {
                for spec in of_kinds(&mut rng, &field, surface, &RayKind::ALL, 2) {
                    both.add(&field, surface, &spec);
                }
            }
        }
        both.report_into(&mut out, &mut all);
    }
    let tiny = Field::from_fn(9, 7, 9, |_, _| (rng.unit() * 1e-6) as f32);
    all.absorb(&run_case(&mut out, "height range 1e-6", &tiny, &mut |s| {
        of_kinds(&mut rng, &tiny, s, &RayKind::ALL, 12)
    }));
    let small_hills = fractal_field(&mut rng, 2, 4096, 2, 3.0);
    all.absorb(&run_case(&mut out, "2 x 4096", &small_hills, &mut |s| {
        of_kinds(&mut rng, &small_hills, s, &RayKind::ALL, 4)
    }));
    let wide = fractal_field(&mut rng, 4096, 2, 4100, 3.0);
    all.absorb(&run_case(&mut out, "4096 x 2", &wide, &mut |s| {
        of_kinds(&mut rng, &wide, s, &RayKind::ALL, 4)
    }));
    finish(out, &all);
}

/// Heights up to 1e6: in `f32` the hit's `z` is only good to its spacing (0.06 at 1e6),
/// so the error is the horizontal distance plus `|Δz| / max(1, |z|)`.
#[test]
fn height_range_1e6() {
    let mut rng = Rng::new(0xB16);
    let field = Field::from_fn(9, 7, 9, |_, _| (rng.unit() * 1e6) as f32);
    let hf = field.hf();
    let mut out = String::new();
    let mut j64 = Judged::new("height range 1e6 / f64");
    let mut t32 = Tally::new("height range 1e6 / f32 (z relative)");
    let eps = eps_f32(field.z_scale());
    let mut raw_max = 0f64;
    let (xm, ym) = field.far_corner();
    for surface in Surface::ALL {
        // Origins near the footprint horizontally (far origins cost `f32` the same
        // precision on any field), at any height; aimed at points of the box, or vertical.
        let rays: Vec<RaySpec> = (0..200)
            .map(|k| {
                let o = [
                    rng.range(-2.0, xm + 2.0),
                    rng.range(-2.0, ym + 2.0),
                    rng.range(-2e5, 1.5e6),
                ];
                let d = if k % 5 == 0 {
                    [0.0, 0.0, -1.0]
                } else {
                    let p = [rng.range(0.0, xm), rng.range(0.0, ym), rng.range(0.0, 1e6)];
                    [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
                };
                let o = if k % 10 == 0 {
                    [o[0].round(), (o[1] * 2.0).round() / 2.0, o[2]]
                } else {
                    o
                };
                RaySpec::whole(o, d)
            })
            .collect();
        for spec in rays {
            j64.add(&field, surface, &spec.q64());
            let q32 = spec.q32();
            let q64 = q32.cast::<f64>();
            let oracle = dda::trace(&hf, surface, &q64);
            let bf = brute::first_hit(&hf, surface, &q64);
            let fast = dda::trace(&hf, surface, &q32);
            t32.tried += 1;
            t32.hits += u64::from(bf.is_some());
            let (o_agrees, _) = judge(&field, surface, &q64);
            if oracle.clearance < eps
                || near_pinch(&field, surface, &q64, PINCH)
                || !matches!(o_agrees, Outcome::Right(_))
            {
                t32.ambiguous += 1;
                continue;
            }
            match (bf, fast.hit) {
                (None, None) => {}
                (Some((tb, _)), Some(h)) => {
                    let (pb, pf) = (q64.at(tb), p64::<f32>(h.point));
                    let e = ((pb[0] - pf[0]).powi(2) + (pb[1] - pf[1]).powi(2)).sqrt()
                        + (pb[2] - pf[2]).abs() / pb[2].abs().max(1.0);
                    t32.err(e);
                    raw_max = raw_max.max(dist(pb, pf));
                    if e > WRONG {
                        t32.wrong(|| format!("{surface:?} {q32:?} brute {pb:?} f32 {pf:?}"));
                    }
                }
                (b, f) => t32.wrong(|| format!("{surface:?} {q32:?} brute {b:?} f32 {f:?}")),
            }
        }
    }
    j64.report(&mut out);
    t32.report(&mut out);
    out.push_str(&format!(
        "    (plain 3-D distance of the f32 hits: max {raw_max:.1e})\n"
    ));
    println!("{out}");
    assert_eq!(j64.tally.wrong + t32.wrong, 0);
}

/// A smooth 8193 × 16 field: x up to 8192 = 2¹³, where `f32` spacing is 2⁻¹⁰. Random
/// rays against brute force (O(cells) per ray, so few), then long rays that cross the
/// whole length and hit a ramp at the far end, whose hit point is known exactly.
#[test]
fn field_8193_by_16() {
    let mut rng = Rng::new(0x2001);
    let mut out = String::new();
    let hills = fractal_field(&mut rng, 8193, 16, 8193, 4.0);
    let random = run_case(&mut out, "8193 x 16 random rays", &hills, &mut |s| {
        of_kinds(
            &mut rng,
            &hills,
            s,
            &[
                RayKind::Down,
                RayKind::Grazing,
                RayKind::AxisX,
                RayKind::Outside,
            ],
            10,
        )
    });

    // Flat at 0 up to x = 8190, then a ramp to 10 at x = 8191 and a plateau, the same
    // in every row: a horizontal ray at height z hits x = 8190 + z / 10 (triangles,
    // bilinear, view-linear and corner planes agree; height planes hit the wall at
    // x = 8190.5).
    let ramp = Field::from_fn(8193, 16, 8193, |i, _| if i <= 8190 { 0.0 } else { 10.0 });
    let hf = ramp.hf();
    let mut long = Tally::new("8193 x 16 long rays, exact far hit / f32+f64");
    let mut j = Judged::new("8193 x 16 long rays vs brute force");
    for k in 0..40 {
        let z = 0.5 + 9.0 * rng.unit();
        let o = [
            if k % 2 == 0 {
                rng.range(0.0, 3.0)
            } else {
                -rng.range(0.5, 40.0)
            },
            rng.range(0.0, 15.0),
            z,
        ];
        let dy = rng.range(-1.0, 1.0) * (14.0 - 1.0) / 8200.0;
        let d = [rng.range(0.5, 2.0), dy, 0.0];
        for surface in Surface::ALL {
            let spec = RaySpec::whole(o, d);
            let q32 = spec.q32();
            let q64 = q32.cast::<f64>();
            let [ox, oy, oz] = q64.origin();
            let y_at = |x: f64| oy + (x - ox) / q64.dir()[0] * q64.dir()[1];
            if !(0.0..=15.0).contains(&y_at(8191.0)) || !(0.0..=15.0).contains(&y_at(ox.max(0.0))) {
                continue;
            }
            let x_hit = if surface == Surface::HeightPlanes {
                8190.5
            } else {
                8190.0 + oz / 10.0
            };
            let t_exact = (x_hit - ox) / q64.dir()[0];
            if k < 8 {
                j.add(&ramp, surface, &q64);
                j.add(&ramp, surface, &q32);
            }
            let check = |name: &str, hit: Option<(f64, [f64; 3])>, long: &mut Tally| {
                long.tried += 1;
                match hit {
                    Some((t, p)) => {
                        long.hits += 1;
                        let e = dist(p, q64.at(t_exact));
                        long.err(e);
                        // t itself, relative to its size: no drift along the way.
                        let rel = (t - t_exact).abs() / t_exact;
                        if e > WRONG || rel > 1e-6 {
                            long.wrong(|| {
                                format!("{name} {surface:?} {q32:?}: t {t} exact {t_exact}")
                            });
                        }
                    }
                    None => long.wrong(|| format!("{name} {surface:?} {q32:?}: miss")),
                }
            };
            let h64 = dda::trace(&hf, surface, &q64)
                .hit
                .map(|h| (h.t, p64::<f64>(h.point)));
            let h32 = dda::trace(&hf, surface, &q32)
                .hit
                .map(|h| (h.t as f64, p64::<f32>(h.point)));
            check("f64", h64, &mut long);
            check("f32", h32, &mut long);
        }
    }
    long.report(&mut out);
    j.report(&mut out);
    println!("{out}");
    assert!(long.tried > 200);
    assert_eq!(random.tally.wrong + long.wrong + j.tally.wrong, 0);
}

#[test]
fn quadratic_roots_are_stable() {
    // Far-apart roots: A = 1e-12, B = −1, C = 0.5 has roots ≈ 0.5 and ≈ 1e12; the naive
    // (−B − √D) / 2A loses the small one to cancellation.
    let naive = (1.0 - (1.0 - 2e-12f64).sqrt()) / 2e-12;
    let stable = 0.5 / (0.5 * (1.0 + (1.0 - 2e-12f64).sqrt()));
    println!("A = 1e-12, B = -1, C = 0.5: naive root {naive:.17}, stable {stable:.17}");
    let r64 = smallest_root_in_unit(1e-12f64, -1.0, 0.5).unwrap();
    assert!((r64 - stable).abs() < 1e-15, "{r64} vs {stable}");
    let r32 = smallest_root_in_unit(1e-12f32, -1.0, 0.5).unwrap();
    assert!((r32 as f64 - stable).abs() < 1e-7, "{r32}");
    // Tiny A of either sign, and a root near 1.
    for a in [1e-20f64, -1e-20, 1e-9, -1e-9] {
        let r = smallest_root_in_unit(a, -1.0, 0.999_999).unwrap();
        assert!((r - 0.999_999).abs() < 1e-8, "A = {a}: {r}");
    }
    // A = 0 exactly: one root −C / B; A = B = 0: a root only when C = 0.
    assert_eq!(smallest_root_in_unit(0.0f64, -2.0, 1.0), Some(0.5));
    assert_eq!(smallest_root_in_unit(0.0f32, -4.0, 1.0), Some(0.25));
    assert_eq!(smallest_root_in_unit(0.0f64, 1.0, 0.5), None); // root at −0.5
    assert_eq!(smallest_root_in_unit(0.0f64, 0.0, 1.0), None);
    assert_eq!(smallest_root_in_unit(0.0f64, 0.0, 0.0), Some(0.0));
    // Exact double roots.
    for r in [0.0, 0.25, 0.5, 0.75, 1.0] {
        let (a, b, c) = (4.0f64, -8.0 * r, 4.0 * r * r);
        assert_eq!(smallest_root_in_unit(a, b, c), Some(r), "double root {r}");
    }
    // Near-double roots 1e-6 apart: the smaller one, to the conditioning.
    let mut rng = Rng::new(0xD0);
    for _ in 0..1000 {
        let r1 = rng.range(0.0, 0.99);
        let r2 = r1 + 1e-6;
        let s = rng.range(0.1, 10.0);
        let (a, b, c) = (s, -s * (r1 + r2), s * r1 * r2);
        let r = smallest_root_in_unit(a, b, c).expect("two real roots");
        assert!((r - r1).abs() < 1e-8, "{r} vs {r1}");
    }
    // No root in [0, 1]: both outside, or complex.
    assert_eq!(smallest_root_in_unit(1.0f64, 0.0, 1.0), None);
    assert_eq!(smallest_root_in_unit(1.0f64, -5.0, 6.0), None); // roots 2 and 3
    assert_eq!(smallest_root_in_unit(1.0f64, 3.0, 2.0), None); // roots −1 and −2
}

/// A field of saddles: h = (i + j) mod 2, every cell a saddle with twist e = −2.
#[test]
fn saddle_cells() {
    let field = Field::from_fn(6, 6, 6, |i, j| ((i + j) % 2) as f32);
    let hf = field.hf();
    let mut out = String::new();
    let mut j = Judged::new("saddles: edge-parallel and diagonal rays");
    // Rays parallel to the cell edges at many offsets (A = 0 exactly) and slopes.
    for k in 0..=16 {
        let v = k as f64 / 8.0;
        for (dz, z) in [
            (0.0, 0.5),
            (0.0, 0.3),
            (-0.05, 0.9),
            (0.02, 0.1),
            (-0.3, 1.5),
        ] {
            for (o, d) in [
                ([-0.5, v, z], [1.0, 0.0, dz]),
                ([v, 5.5, z], [0.0, -1.0, dz]),
                ([5.5, v + 0.0625, z], [-1.0, 0.0, dz]),
            ] {
                let spec = RaySpec::whole(o, d);
                j.add(&field, Surface::Bilinear, &spec.q64());
                j.add(&field, Surface::Bilinear, &spec.q32());
                j.add(&field, Surface::ViewLinear, &spec.q64());
                j.add(&field, Surface::Triangles, &spec.q32());
            }
        }
    }
    // Along the diagonal of cell (0, 0) (h = 2u(1 − u) there, peak 0.5): horizontal rays
    // under, at and over the peak.
    for z in [0.4, 0.5, 0.6] {
        for q in [
            Query::<f64>::from_arrays([0.0, 0.0, z], [1.0, 1.0, 0.0], 0.0, 1.0).unwrap(),
            Query::<f64>::from_arrays([0.0, 0.0, z], [1.0, 1.0, 0.0], 0.0, 1.0)
                .unwrap()
                .cast::<f32>()
                .cast::<f64>(),
        ] {
            // 2u(1 − u) = z.
            let zq = q.origin()[2];
            let expect = (zq <= 0.5).then(|| (1.0 - (1.0 - 2.0 * zq).sqrt()) / 2.0);
            let got = dda::trace(&hf, Surface::Bilinear, &q).hit.map(|h| h.t);
            let got32 = dda::trace(&hf, Surface::Bilinear, &q.cast::<f32>())
                .hit
                .map(|h| h.t as f64);
            let b = brute::first_hit(&hf, Surface::Bilinear, &q).map(|b| b.0);
            for (name, g, tol) in [
                ("f64", got, 1e-12),
                ("f32", got32, 1e-6),
                ("brute", b, 1e-12),
            ] {
                j.tally.tried += 1;
                let ok = match (g, expect) {
                    (Some(g), Some(e)) => (g - e).abs() < tol,
                    (None, None) => true,
                    _ => false,
                };
                if !ok {
                    j.tally
                        .wrong(|| format!("diagonal z {z}: {name} {g:?}, expected {expect:?}"));
                }
            }
        }
    }
    j.report(&mut out);
    println!("{out}");
    assert_eq!(j.tally.wrong, 0);
}
