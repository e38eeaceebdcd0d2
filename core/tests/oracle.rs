//! The oracle checked against brute force: `dda::trace` in `f64` must agree with
//! `brute::first_hit` (every cell tested, no grid walk) on thousands of random small
//! fields (2×2 … 12×9, strides above the width with NaN padding, integer and float
//! heights) and random rays of every stiff kind, for every surface.
//!
//! Compared per ray (see `common::judge`): hit or miss, the hit position (within 1e-9
//! of the scene's length scale), the hit cell, the flags (ORIGIN_INSIDE, SIDE and WALL
//! against the geometry), the normal. Left out of the comparison, counted and printed:
//!
//! - ambiguous rays, *in `f64`*: the oracle's clearance is below `1e-9 · max(1, |z|)`
//!   (docs/DESIGN.md's `2⁻¹³` is the `f32` threshold; both sides here are `f64`, so this
//!   test uses a far tighter one);
//! - touches: the two disagree because one of them meets the surface at zero clearance
//!   without going under it (e.g. a horizontal ray at exactly the height of a ridge);
//!   rounding decides, and by docs/DESIGN.md's rule such a ray is ambiguous.
//!
//! Contract readings this test documents (the code implements them; docs/DESIGN.md does not
//! spell them out):
//!
//! - The discontinuous surfaces (height planes, corner planes) are the graph of a
//!   height *function* with the tie rule "a point on a boundary belongs to the larger
//!   index" (stated for height planes; the traversal applies it to linear-plane cells
//!   too). A ray that runs exactly along a wall line (vertical, or axis-parallel) is
//!   decided by that rule, and brute force applies it too.
//! - Brute force builds the closed solid (union of closed columns). Where that differs
//!   from the function's graph — a ray starting exactly on a wall, or passing exactly
//!   through a point where walls meet — the rays are counted as wall-point ties and
//!   checked only for what both readings share: the traversal's hit is never earlier
//!   than the closed solid's.
//! - A hit where the traced span begins (origin under the surface, side entry) reports
//!   its depth under the surface as its clearance, so an origin just under the surface
//!   is ambiguous, a deep one is not.

mod common;

use common::*;
use hfcast::Surface;

#[test]
fn dda_f64_equals_brute_force_on_random_small_fields() {
    let mut rng = Rng::new(0x0AC1E);
    let mut cases: Vec<Vec<Judged>> = Surface::ALL
        .iter()
        .map(|s| {
            RayKind::ALL
                .iter()
                .map(|k| Judged::new(format!("{} / {:?}", s.name(), k)))
                .collect()
        })
        .collect();
    const FIELDS: usize = 3000;
    const RAYS_PER_KIND: usize = 3;
    for _ in 0..FIELDS {
        let field = small_field(&mut rng);
        for (si, &surface) in Surface::ALL.iter().enumerate() {
            for (ki, &kind) in RayKind::ALL.iter().enumerate() {
                for _ in 0..RAYS_PER_KIND {
                    let spec = random_ray(&mut rng, &field, surface, kind);
                    cases[si][ki].add(&field, surface, &spec.q64());
                }
            }
        }
    }
    let mut out = format!(
        "oracle: f64 DDA vs brute force on {FIELDS} random fields; ambiguous: clearance < 1e-9 max(1,|z|)\n"
    );
    let mut total = Judged::new("all surfaces, all kinds");
    for c in cases.iter().flatten() {
        c.report(&mut out);
        total.absorb(c);
    }
    total.report(&mut out);
    println!("{out}");
    let t = &total.tally;
    assert_eq!(t.wrong, 0, "the f64 DDA disagrees with brute force");
    // The test must have teeth: most rays compared, plenty of hits.
    assert!(t.ambiguous * 20 < t.tried && total.ties * 50 < t.tried);
    assert!(t.hits * 2 > t.tried && t.compared_hits * 2 > t.tried);
}
