//! Maximum mipmaps on every real map of `../shared/data`: zero wrong rays against the
//! f64 exact DDA, for camera rays at 45° and 5° and random rays inside the box, on the
//! triangle and bilinear surfaces, in f32 and f64.

mod common;

use common::{ambiguity_eps, differs, maps, test_rays};
use hfcast::maxmip::{self, Ascent, MaxMip, Options};
use hfcast::{dda, HeightField, Surface};
use hfcast_tools::maps::load_map;

#[test]
fn maxmip_exact_on_every_map() {
    let mut total_wrong = 0;
    for info in &maps() {
        let map = load_map(&info.path, None).expect("map loads");
        let hf: HeightField = map.field();
        let mut pyr = vec![0f32; maxmip::pyramid_len(hf.width(), hf.height())];
        maxmip::bake(&hf, &mut pyr).unwrap();
        let mip = MaxMip::new(&hf, &pyr).unwrap();
        // docs/DESIGN.md's ambiguity threshold 2⁻¹³ · max(1, |z|), |z| over the whole map.
        let eps = ambiguity_eps(&hf);
        let rays = test_rays(&hf);
        for surface in [Surface::Triangles, Surface::Bilinear] {
            let (mut wrong, mut ambiguous, mut differ_amb, mut hits) = (0, 0, 0, 0);
            let (mut f_dda, mut f_mm) = (0u64, 0u64);
            for q in &rays {
                let oracle = dda::trace(&hf, surface, &q.cast::<f64>());
                let amb = oracle.clearance.abs() < eps;
                ambiguous += usize::from(amb);
                hits += usize::from(oracle.hit.is_some());
                f_dda += u64::from(dda::trace(&hf, surface, q).fetches);
                let mut bad = false;
                for ascent in [Ascent::OneLevel, Ascent::Highest] {
                    let opts = Options {
                        ascent,
                        ..Options::default()
                    };
                    let m32 = maxmip::trace(&hf, &mip, surface, q, &opts);
                    let m64 = maxmip::trace(&hf, &mip, surface, &q.cast::<f64>(), &opts);
                    if ascent == Ascent::OneLevel {
                        f_mm += u64::from(m32.fetches);
                    }
                    bad |= differs(&m32, &oracle) || differs(&m64, &oracle);
                }
                if bad && amb {
                    differ_amb += 1;
                } else if bad {
                    wrong += 1;
                    if wrong <= 3 {
                        println!("    wrong: {q:?}");
                    }
                }
            }
            println!(
                "{:<34} {:<9} tried {:>5}  wrong {wrong}  ambiguous {ambiguous:>2} (differ \
                 {differ_amb})  hits {hits:>5}  fetches/ray dda {:.1} maxmip {:.1}",
                info.name,
                surface.name(),
                rays.len(),
                f_dda as f64 / rays.len() as f64,
                f_mm as f64 / rays.len() as f64
            );
            total_wrong += wrong;
        }
    }
    assert_eq!(total_wrong, 0, "wrong rays");
}
