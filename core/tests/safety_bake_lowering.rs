//! The error-tolerant radius bake's strip bound subtracts the ray set's lowering
//! (`RaySet::lowering`): the radii must equal those of the same ray set scanned with
//! the plain strip bound (lowering reported as 0, so only the limiting test sees it).
#![cfg(feature = "safety")]

mod common;

use common::{fractal_field, march_fields, Field, Rng};
use hfcast::radius::{self, BakeOptions, Lowered};
use hfcast::safety::{self, Options, RaySet, Sigma, Tri, Variant};

/// `Lowered` whose strip bound is not told about the lowering.
struct Plain(Lowered);

impl RaySet for Plain {
    fn limiting(&self, sigma: &Sigma, tri: &Tri) -> bool {
        self.0.limiting(sigma, tri)
    }
}

fn fields() -> Vec<(String, Field)> {
    let mut v = march_fields(0x1ee, 5, ("checkerboard 24x20", 2.0, -1.0), Vec::new(), 6);
    v.push((
        "fractal 70x52".into(),
        fractal_field(&mut Rng::new(3), 70, 52, 70, 9.0),
    ));
    v
}

#[test]
fn lowered_strip_bound_changes_no_radius() {
    for (name, field) in fields() {
        let hf = field.hf();
        let (w, h) = (field.w, field.h);
        let mut scratch = vec![0f32; radius::scratch_len(w, h)];
        radius::prepare(&hf, &mut scratch).unwrap();
        for e in [0.0f32, 0.25, 1.0, 3.0] {
            let opts = BakeOptions {
                tolerance: e,
                ..BakeOptions::default()
            };
            let mut fast = vec![0u8; radius::map_len(w, h)];
            radius::bake_rows(&hf, &scratch, 0..h, opts, &mut fast).unwrap();
            let iso = Options {
                variant: Variant::Isotropic,
                ..Options::default()
            };
            let mut plain = vec![0u8; safety::map_len(w, h, Variant::Isotropic)];
            let rays = Plain(Lowered(f64::from(e)));
            safety::bake_rows_with(&hf, &scratch, &rays, 0..h, iso, &mut plain).unwrap();
            assert_eq!(fast, plain, "{name}, tolerance {e}");
        }
    }
}
