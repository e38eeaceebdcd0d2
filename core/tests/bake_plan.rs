//! Bake plans ([`Scene::bake_plan`]): every method bakes exactly what its march reads,
//! and the safety-shape bakes that skip ray classes the scene never casts equal the
//! full bakes on the kept classes, store nothing for the other classes (whose rays read zero jumps), and trace the
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
            MethodKind::Exact
            | MethodKind::LinearBinary
            | MethodKind::LinearSecant
            | MethodKind::Multires => (&[], &[]),
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
    use hfcast::safety::{self, AllRays, ClassRows, Options, SafetyMap, Variant, CLASSES};
    use hfcast::{Query, Trace};

    fn field() -> Field {
        fractal_field(&mut Rng::new(8), 41, 29, 41, 6.0)
    }

    /// The map of `classes` only, exactly [`safety::map_len_classes`] bytes long.
    fn bake(f: &Field, classes: RayClasses, opts: Options) -> Vec<u8> {
        let hf = f.hf();
        let mut scratch = vec![0.0; safety::scratch_len(f.w, f.h)];
        safety::prepare(&hf, &mut scratch).unwrap();
        let mut out = vec![0xAA; safety::map_len_classes(f.w, f.h, opts.variant, classes)];
        safety::bake_rows_classes(&hf, &scratch, &AllRays, classes, 0..f.h, opts, &mut out)
            .unwrap();
        out
    }

    /// The cylinder–cone map of `classes` only, exactly [`cc::map_len_classes`] bytes.
    fn bake_cc(f: &Field, classes: RayClasses, opts: CcOptions) -> Vec<u8> {
        let hf = f.hf();
        let mut scratch = vec![0.0; safety::scratch_len(f.w, f.h)];
        let mut nb = vec![0.0; cc::nbuffer_len(f.w, f.h, opts.cap)];
        safety::prepare(&hf, &mut scratch).unwrap();
        cc::prepare_nbuffer(&hf, opts.cap, &mut nb).unwrap();
        let mut out = vec![0xAA; cc::map_len_classes(f.w, f.h, classes)];
        cc::bake_rows_classes(&hf, &scratch, &nb, classes, 0..f.h, opts, &mut out).unwrap();
        out
    }

    /// The kinds of the rays the class tests trace, in turn: rays of every class, some
    /// of them along an axis or a cell diagonal.
    const KINDS: [RayKind; 7] = [
        RayKind::Down,
        RayKind::Up,
        RayKind::Grazing,
        RayKind::Horizontal,
        RayKind::Diagonal,
        RayKind::AxisX,
        RayKind::AxisY,
    ];

    /// `n` rays of the [`KINDS`] whose class is in `classes`.
    fn rays_of(f: &Field, classes: RayClasses, n: usize) -> Vec<Query<f32>> {
        let mut rng = Rng::new(99);
        let mut out = Vec::new();
        for k in 0.. {
            if out.len() == n {
                break;
            }
            assert!(k < 100 * n, "too few rays of {classes:?}");
            let q = random_ray(&mut rng, f, Surface::Triangles, KINDS[k % KINDS.len()]).q32();
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

    /// Texel `t`'s coordinates.
    fn ij(f: &Field, t: usize) -> (u32, u32) {
        ((t % f.w as usize) as u32, (t / f.w as usize) as u32)
    }

    #[test]
    fn maps_of_fewer_classes_hold_the_kept_rows_of_the_full_bake() {
        let f = field();
        let hf = f.hf();
        for positive in [false, true] {
            let opts = Options {
                positive,
                ..Options::default()
            };
            let full = bake(&f, RayClasses::ALL, opts);
            let full_map = SafetyMap::new(&hf, &full, Variant::Directional).unwrap();
            for classes in kept_and_skipped() {
                let part = bake(&f, classes, opts);
                assert_eq!(part.len(), (f.w * f.h * classes.count()) as usize);
                let map =
                    SafetyMap::with_classes(&hf, &part, Variant::Directional, classes).unwrap();
                for t in 0..(f.w * f.h) as usize {
                    let (i, j) = ij(&f, t);
                    for class in CLASSES {
                        let want = match ClassRows::of(f.w, Variant::Directional, classes, class) {
                            // The class's own row, `n` rows per texel row.
                            Some(at) => {
                                let slot = CLASSES[..class as usize]
                                    .iter()
                                    .filter(|&&c| classes.contains(c))
                                    .count();
                                assert_eq!(
                                    at.index(i, j),
                                    (j as usize * part.len() / (f.w * f.h) as usize + slot)
                                        * f.w as usize
                                        + i as usize
                                );
                                assert_eq!(part[at.index(i, j)], full_map.distance(class, i, j));
                                full_map.distance(class, i, j)
                            }
                            None => 0,
                        };
                        assert_eq!(
                            map.distance(class, i, j),
                            want,
                            "texel {t} {class:?} {classes:?}"
                        );
                    }
                }
                // Isotropic over the kept classes: the minimum of their distances.
                let iso = Options {
                    variant: Variant::Isotropic,
                    ..opts
                };
                let part = bake(&f, classes, iso);
                assert_eq!(part.len(), (f.w * f.h) as usize);
                for (t, v) in part.iter().enumerate() {
                    let (i, j) = ij(&f, t);
                    let kept = CLASSES
                        .into_iter()
                        .filter(|&class| classes.contains(class))
                        .map(|class| full_map.distance(class, i, j))
                        .min()
                        .unwrap_or(0);
                    assert_eq!(*v, kept, "texel {t} {classes:?}");
                }
            }
        }
    }

    /// `a` and `b` hit alike (hit or miss, `t` within 1e-3).
    fn same_hit(a: Trace<f32>, b: Trace<f32>, q: &Query<f32>) {
        match (a.hit, b.hit) {
            (Some(a), Some(b)) => assert!((a.t - b.t).abs() < 1e-3, "{q:?}"),
            (a, b) => assert_eq!(a.is_some(), b.is_some(), "{q:?}"),
        }
    }

    #[test]
    fn kept_classes_trace_as_with_the_full_bake() {
        let f = field();
        let hf = f.hf();
        let opts = Options::default();
        let full = bake(&f, RayClasses::ALL, opts);
        let full_map = SafetyMap::new(&hf, &full, Variant::Directional).unwrap();
        let iso = Options {
            variant: Variant::Isotropic,
            ..opts
        };
        for classes in kept_and_skipped() {
            if classes == RayClasses::NONE {
                continue;
            }
            let part = bake(&f, classes, opts);
            let map = SafetyMap::with_classes(&hf, &part, Variant::Directional, classes).unwrap();
            let iso_part = bake(&f, classes, iso);
            let iso_map =
                SafetyMap::with_classes(&hf, &iso_part, Variant::Isotropic, classes).unwrap();
            for q in rays_of(&f, classes, 600) {
                let want = safety::trace(&full_map, &hf, &q);
                assert_eq!(safety::trace(&map, &hf, &q), want, "{q:?}");
                if classes.count() == 1 {
                    assert_eq!(safety::trace(&iso_map, &hf, &q), want, "{q:?}");
                }
                same_hit(safety::trace(&iso_map, &hf, &q), want, &q);
            }
            // A class the map does not hold reads distance 0: its rays still trace
            // exactly (zero jumps walk cell by cell), on either layout.
            let others = RayClasses(!classes.0 & RayClasses::ALL.0);
            for q in rays_of(&f, others, 200) {
                let want = safety::trace(&full_map, &hf, &q);
                same_hit(safety::trace(&map, &hf, &q), want, &q);
                same_hit(safety::trace(&iso_map, &hf, &q), want, &q);
            }
        }
    }

    #[test]
    fn cc_maps_of_fewer_classes_hold_the_kept_rows_and_trace_the_same() {
        let f = field();
        let hf = f.hf();
        for slope in [Slope::Exact, Slope::NBuffer] {
            let opts = CcOptions { slope, cap: 24 };
            let full = bake_cc(&f, RayClasses::ALL, opts);
            let full_map = CcMap::new(&hf, &full, opts.cap).unwrap();
            for classes in kept_and_skipped() {
                let part = bake_cc(&f, classes, opts);
                assert_eq!(part.len(), (f.w * f.h * 2 * classes.count()) as usize);
                let map = CcMap::with_classes(&hf, &part, opts.cap, classes).unwrap();
                for t in 0..(f.w * f.h) as usize {
                    let (i, j) = ij(&f, t);
                    for class in CLASSES {
                        let want = if classes.contains(class) {
                            let at = ClassRows::of(f.w, Variant::Directional, classes, class);
                            let at = at.unwrap().index(i, j) * cc::BYTES_PER_CLASS;
                            assert_eq!(part[at..at + 2], full_map.texel(class, i, j));
                            full_map.texel(class, i, j)
                        } else {
                            [0, cc::NO_CONE]
                        };
                        assert_eq!(map.texel(class, i, j), want, "texel {t} {class:?}");
                    }
                }
                if classes == RayClasses::NONE {
                    continue;
                }
                for q in rays_of(&f, classes, 400) {
                    assert_eq!(cc::trace(&map, &hf, &q), cc::trace(&full_map, &hf, &q));
                }
                let others = RayClasses(!classes.0 & RayClasses::ALL.0);
                for q in rays_of(&f, others, 200) {
                    same_hit(cc::trace(&map, &hf, &q), cc::trace(&full_map, &hf, &q), &q);
                }
            }
        }
    }
}
