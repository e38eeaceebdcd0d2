//! Bake plans ([`Scene::bake_plan`]): every method bakes exactly what its march reads,
//! and the safety-shape bakes that skip ray classes the scene never casts equal the
//! full bakes on the kept classes, leave 0 (a zero jump) elsewhere, and trace the
//! kept classes' rays exactly as the full bakes do.

mod common;

use hfcast::scene::{MethodKind, Need, Product, RayClasses, Scene};
use hfcast::{RayClass, Surface};

/// The general scene of `method` narrowed to `classes`.
fn scene(method: MethodKind, classes: RayClasses) -> Scene {
    Scene {
        ray_classes: classes,
        ..Scene::general(method, Surface::Triangles)
    }
}

#[test]
fn every_method_bakes_what_its_march_reads() {
    use Product as P;
    for m in MethodKind::ALL {
        let plan = scene(m, RayClasses::ALL).bake_plan();
        assert_eq!(plan.method, m);
        let kept: Vec<Product> = P::ALL
            .into_iter()
            .filter(|&p| plan.need(p) == Need::Keep)
            .collect();
        let scratch: Vec<Product> = P::ALL
            .into_iter()
            .filter(|&p| plan.need(p) == Need::Scratch)
            .collect();
        let (want_kept, want_scratch): (&[P], &[P]) = match m {
            MethodKind::Exact | MethodKind::LinearBinary | MethodKind::LinearSecant => (&[], &[]),
            MethodKind::MaxMip => (&[P::Pyramid], &[]),
            MethodKind::Cone => (&[P::ConeMap], &[P::Pyramid]),
            MethodKind::Relaxed => (&[P::RelaxedMap], &[P::Pyramid]),
            MethodKind::Qdm => (&[P::QdmMap], &[P::Pyramid]),
            MethodKind::Safety => (&[P::SafetyMap], &[P::SafetyScratch]),
            MethodKind::Cc => (&[P::CcMap], &[P::SafetyScratch, P::NBuffer]),
            MethodKind::Radius => (&[P::RadiusMap], &[P::SafetyScratch]),
        };
        assert_eq!(kept, want_kept, "{}", m.name());
        assert_eq!(scratch, want_scratch, "{}", m.name());
        assert_eq!(plan.bakes_nothing(), want_kept.is_empty(), "{}", m.name());
        // Every product not baked is listed with a reason, and nothing else is (all
        // classes occur, so no channel is skipped).
        let skipped: Vec<_> = plan.skipped().collect();
        assert_eq!(skipped.len(), 9 - kept.len() - scratch.len(), "{skipped:?}");
        assert!(skipped.iter().all(|(what, why)| {
            P::ALL.iter().any(|p| p.name() == *what && !plan.bakes(*p)) && !why.is_empty()
        }));
        let shapes = matches!(m, MethodKind::Safety | MethodKind::Cc);
        let classes = if shapes {
            RayClasses::ALL
        } else {
            RayClasses::NONE
        };
        assert_eq!(plan.classes, classes, "{}", m.name());
        assert!(!plan.isotropic);
    }
}

#[test]
fn built_methods_follow_the_features() {
    for (m, on) in [
        (MethodKind::Exact, true),
        (MethodKind::LinearBinary, cfg!(feature = "search")),
        (MethodKind::LinearSecant, cfg!(feature = "search")),
        (MethodKind::MaxMip, cfg!(feature = "maxmip")),
        (MethodKind::Safety, cfg!(feature = "safety")),
        (MethodKind::Cone, cfg!(feature = "cone")),
        (MethodKind::Relaxed, cfg!(feature = "relaxed")),
        (MethodKind::Qdm, cfg!(feature = "qdm")),
        (MethodKind::Cc, cfg!(feature = "safety")),
        (MethodKind::Radius, cfg!(feature = "safety")),
    ] {
        assert_eq!(m.built(), on, "{}", m.name());
    }
}

#[test]
fn ray_classes_narrow_the_safety_shape_bakes() {
    let two = RayClasses::NONE.with(RayClass::XPos).with(RayClass::YNeg);
    let one = RayClasses::NONE.with(RayClass::YPos);
    for m in [MethodKind::Safety, MethodKind::Cc] {
        let plan = scene(m, two).bake_plan();
        assert_eq!(plan.classes, two);
        assert!(!plan.isotropic);
        let skipped: Vec<&str> = plan.skipped().map(|(what, _)| what).collect();
        assert!(skipped.contains(&"x- channel") && skipped.contains(&"y+ channel"));
        assert!(!skipped.contains(&"x+ channel") && !skipped.contains(&"y- channel"));
        let plan = scene(m, one).bake_plan();
        assert_eq!(plan.classes, one);
        // One class: the safety map is isotropic (exact for that class); the CC map
        // has no isotropic layout.
        assert_eq!(plan.isotropic, m == MethodKind::Safety);
        let skipped: Vec<&str> = plan.skipped().map(|(what, _)| what).collect();
        assert_eq!(
            skipped.contains(&"directional channels"),
            m == MethodKind::Safety
        );
    }
    // Methods without safety shapes ignore the classes (the radius is isotropic: one
    // byte for every class).
    for m in [MethodKind::MaxMip, MethodKind::Radius] {
        let plan = scene(m, one).bake_plan();
        assert_eq!(plan.classes, RayClasses::NONE);
        assert!(plan.skipped().all(|(what, _)| !what.ends_with("channel")));
    }
}

#[cfg(feature = "safety")]
mod safety_classes {
    use super::*;
    use common::{fractal_field, random_ray, Field, RayKind, Rng};
    use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
    use hfcast::safety::{self, AllRays, Options, SafetyMap, Variant, CLASSES};
    use hfcast::Query;

    fn field() -> Field {
        fractal_field(&mut Rng::new(8), 41, 29, 41, 6.0)
    }

    fn bake(f: &Field, classes: RayClasses, opts: Options) -> Vec<u8> {
        let hf = f.hf();
        let mut scratch = vec![0.0; safety::scratch_len(f.w, f.h)];
        safety::prepare(&hf, &mut scratch).unwrap();
        let mut out = vec![0xAA; safety::map_len(f.w, f.h, opts.variant)];
        safety::bake_rows_classes(&hf, &scratch, &AllRays, classes, 0..f.h, opts, &mut out)
            .unwrap();
        out
    }

    fn bake_cc(f: &Field, classes: RayClasses, opts: CcOptions) -> Vec<u8> {
        let hf = f.hf();
        let mut scratch = vec![0.0; safety::scratch_len(f.w, f.h)];
        let mut nb = vec![0.0; cc::nbuffer_len(f.w, f.h, opts.cap)];
        safety::prepare(&hf, &mut scratch).unwrap();
        cc::prepare_nbuffer(&hf, opts.cap, &mut nb).unwrap();
        let mut out = vec![0xAA; cc::map_len(f.w, f.h)];
        cc::bake_rows_classes(&hf, &scratch, &nb, classes, 0..f.h, opts, &mut out).unwrap();
        out
    }

    /// Rays of every kind whose class is in `classes`.
    fn rays_of(f: &Field, classes: RayClasses, n: usize) -> Vec<Query<f32>> {
        let mut rng = Rng::new(99);
        let kinds = [
            RayKind::Down,
            RayKind::Up,
            RayKind::Grazing,
            RayKind::Horizontal,
            RayKind::Diagonal,
            RayKind::AxisX,
            RayKind::AxisY,
        ];
        let mut out = Vec::new();
        for k in 0.. {
            if out.len() == n {
                break;
            }
            assert!(k < 100 * n, "too few rays of {classes:?}");
            let q = random_ray(&mut rng, f, Surface::Triangles, kinds[k % kinds.len()]).q32();
            if classes.contains(RayClass::of(q.dir()[0], q.dir()[1])) {
                out.push(q);
            }
        }
        out
    }

    fn kept_and_skipped() -> [RayClasses; 3] {
        [
            RayClasses::NONE.with(RayClass::XPos).with(RayClass::YNeg),
            RayClasses::NONE.with(RayClass::XNeg),
            RayClasses::NONE,
        ]
    }

    #[test]
    fn skipped_classes_are_zero_and_kept_ones_equal_the_full_bake() {
        let f = field();
        for positive in [false, true] {
            let opts = Options {
                positive,
                ..Options::default()
            };
            let full = bake(&f, RayClasses::ALL, opts);
            for classes in kept_and_skipped() {
                let part = bake(&f, classes, opts);
                let at = |class, t: usize| {
                    let (i, j) = ((t % f.w as usize) as u32, (t / f.w as usize) as u32);
                    safety::texel_offset(f.w, Variant::Directional, class, i, j)
                };
                for t in 0..(f.w * f.h) as usize {
                    for class in CLASSES {
                        let at = at(class, t);
                        let want = if classes.contains(class) { full[at] } else { 0 };
                        assert_eq!(part[at], want, "texel {t} class {class:?} {classes:?}");
                    }
                }
                // Isotropic over the kept classes: the minimum of their distances.
                let iso = Options {
                    variant: Variant::Isotropic,
                    ..opts
                };
                let part = bake(&f, classes, iso);
                for (t, v) in part.iter().enumerate() {
                    let kept = CLASSES
                        .into_iter()
                        .filter(|&class| classes.contains(class))
                        .map(|class| full[at(class, t)])
                        .min()
                        .unwrap_or(0);
                    assert_eq!(*v, kept, "texel {t} {classes:?}");
                }
            }
        }
    }

    #[test]
    fn kept_classes_trace_as_with_the_full_bake() {
        let f = field();
        let hf = f.hf();
        let opts = Options::default();
        let full = bake(&f, RayClasses::ALL, opts);
        let full_map = SafetyMap::new(&hf, &full, Variant::Directional).unwrap();
        for classes in kept_and_skipped() {
            if classes == RayClasses::NONE {
                continue;
            }
            let part = bake(&f, classes, opts);
            let map = SafetyMap::new(&hf, &part, Variant::Directional).unwrap();
            let one = classes.count() == 1;
            let iso = bake(
                &f,
                classes,
                Options {
                    variant: Variant::Isotropic,
                    ..opts
                },
            );
            let iso_map = SafetyMap::new(&hf, &iso, Variant::Isotropic).unwrap();
            for q in rays_of(&f, classes, 600) {
                let want = safety::trace(&full_map, &hf, &q);
                assert_eq!(safety::trace(&map, &hf, &q), want, "{q:?}");
                if one {
                    assert_eq!(safety::trace(&iso_map, &hf, &q), want, "{q:?}");
                }
            }
        }
        // A skipped class's rays still trace exactly (zero jumps walk cell by cell).
        let part = bake(&f, RayClasses::NONE.with(RayClass::XPos), opts);
        let map = SafetyMap::new(&hf, &part, Variant::Directional).unwrap();
        for q in rays_of(&f, RayClasses::NONE.with(RayClass::YPos), 200) {
            let (a, b) = (
                safety::trace(&map, &hf, &q),
                safety::trace(&full_map, &hf, &q),
            );
            match (a.hit, b.hit) {
                (Some(a), Some(b)) => assert!((a.t - b.t).abs() < 1e-3, "{q:?}"),
                (a, b) => assert_eq!(a.is_some(), b.is_some(), "{q:?}"),
            }
        }
    }

    #[test]
    fn cc_skipped_classes_have_no_shape_and_kept_ones_trace_the_same() {
        let f = field();
        let hf = f.hf();
        for slope in [Slope::Exact, Slope::NBuffer] {
            let opts = CcOptions { slope, cap: 24 };
            let full = bake_cc(&f, RayClasses::ALL, opts);
            let full_map = CcMap::new(&hf, &full, opts.cap).unwrap();
            for classes in kept_and_skipped() {
                let part = bake_cc(&f, classes, opts);
                for t in 0..(f.w * f.h) as usize {
                    for class in CLASSES {
                        let (i, j) = ((t % f.w as usize) as u32, (t / f.w as usize) as u32);
                        let at = cc::texel_offset(f.w, class, i, j);
                        let want = if classes.contains(class) {
                            &full[at..at + 4]
                        } else {
                            &[0, cc::NO_CONE, 0, 0]
                        };
                        assert_eq!(&part[at..at + 4], want, "texel {t} {class:?}");
                    }
                }
                if classes == RayClasses::NONE {
                    continue;
                }
                let map = CcMap::new(&hf, &part, opts.cap).unwrap();
                for q in rays_of(&f, classes, 400) {
                    assert_eq!(cc::trace(&map, &hf, &q), cc::trace(&full_map, &hf, &q));
                }
            }
        }
    }
}
