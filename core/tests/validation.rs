//! Input validation: `HeightField::new`, `from_u8`, `from_u16` and `Query` refuse bad
//! input with the right error (and never panic or allocate on absurd sizes); the
//! integer conversions map the full range onto `[0, depth]`; extreme but valid queries
//! trace without panics or NaN.

mod common;

use common::*;
use hfcast::field::MAX_SIDE;
use hfcast::{dda, FieldError, HeightField, Query, RayError, Surface};

#[test]
fn height_field_sizes_and_strides() {
    let s = [0.0f32; 64];
    let short = |needed, given| FieldError::SliceTooShort { needed, given };
    // (samples given, width, height, stride, the error)
    let refused = [
        (64, 1, 4, 4, FieldError::TooSmall),
        (64, 4, 1, 4, FieldError::TooSmall),
        (64, 0, 0, 0, FieldError::TooSmall),
        (64, 4, 4, 3, FieldError::StrideTooSmall),
        (64, MAX_SIDE + 1, 2, usize::MAX, FieldError::TooLarge),
        (64, 2, MAX_SIDE + 1, 2, FieldError::TooLarge),
        // Slice too short: exactly one sample missing, with and without padding.
        (15, 4, 4, 4, short(16, 15)),
        (20, 3, 4, 6, short(21, 20)),
        // Huge strides over a short slice: errors, no panic, no allocation.
        (64, 4, 3, usize::MAX / 2 + 1, FieldError::SizeOverflow),
        (64, 4, 2, usize::MAX - 3, FieldError::SizeOverflow),
        (64, 4, 2, usize::MAX - 4, short(usize::MAX, 64)),
        (64, 4, 5, usize::MAX / 4, FieldError::SizeOverflow),
    ];
    for (n, w, h, stride, e) in refused {
        let got = HeightField::new(&s[..n], w, h, stride).unwrap_err();
        assert_eq!(got, e, "{n} samples, {w} x {h}, stride {stride}");
    }
    // The last row needs only `width` samples, not a full stride.
    assert!(HeightField::new(&s[..21], 3, 4, 6).is_ok());
    let mut out = [0.0f32; 16];
    assert_eq!(
        HeightField::from_u8(&[0u8; 8], 4, 3, usize::MAX / 2 + 1, 1.0, &mut out).unwrap_err(),
        FieldError::SizeOverflow
    );
    assert_eq!(
        HeightField::from_u16(&[0u16; 8], 4, 2, usize::MAX / 2, 1.0, &mut out).unwrap_err(),
        FieldError::SliceTooShort {
            needed: usize::MAX / 2 + 4,
            given: 8
        }
    );
    for e in [
        FieldError::TooSmall,
        FieldError::TooLarge,
        FieldError::StrideTooSmall,
        FieldError::SizeOverflow,
        FieldError::SliceTooShort {
            needed: 2,
            given: 1,
        },
        FieldError::NotFinite { index: 3 },
        FieldError::OutputTooShort { needed: 4 },
    ] {
        assert!(!e.to_string().is_empty());
    }
}

#[test]
fn height_field_rows_and_non_finite_heights() {
    // 3 × 2 with stride 5: padding holds NaN and must be ignored.
    let s = [1.0f32, 2.0, 3.0, f32::NAN, f32::NAN, 4.0, -5.0, 6.0];
    let hf = HeightField::new(&s, 3, 2, 5).unwrap();
    assert_eq!((hf.width(), hf.height(), hf.stride()), (3, 2, 5));
    assert_eq!((hf.min_height(), hf.max_height()), (-5.0, 6.0));
    assert_eq!(hf.at(2, 0), 3.0);
    assert_eq!(hf.at(0, 1), 4.0);
    assert_eq!(hf.cell_corners(1, 0), [2.0, 3.0, -5.0, 6.0]);
    // Bad heights, reported with their slice index.
    for (index, bad) in [
        (0, f32::NAN),
        (2, f32::INFINITY),
        (6, f32::NEG_INFINITY),
        (7, f32::NAN),
    ] {
        let mut t = s;
        t[index] = bad;
        assert_eq!(
            HeightField::new(&t, 3, 2, 5).unwrap_err(),
            FieldError::NotFinite { index },
            "{bad} at {index}"
        );
    }
    // The first bad one wins.
    let mut t = s;
    t[5] = f32::NAN;
    t[7] = f32::NAN;
    assert_eq!(
        HeightField::new(&t, 3, 2, 5).unwrap_err(),
        FieldError::NotFinite { index: 5 }
    );
    // Large but finite heights are fine.
    let big = [f32::MAX, -f32::MAX, 0.0, 1.0];
    assert!(HeightField::new(&big, 2, 2, 2).is_ok());
}

#[test]
fn integer_maps() {
    let mut out = [0.0f32; 12];
    // Errors: depth, output, slice, sizes.
    for depth in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(
            HeightField::from_u8(&[0u8; 12], 4, 3, 4, depth, &mut out).unwrap_err(),
            FieldError::NotFinite { index: 0 }
        );
        assert_eq!(
            HeightField::from_u16(&[0u16; 12], 4, 3, 4, depth, &mut out).unwrap_err(),
            FieldError::NotFinite { index: 0 }
        );
    }
    assert_eq!(
        HeightField::from_u8(&[0u8; 12], 4, 3, 4, 1.0, &mut out[..11]).unwrap_err(),
        FieldError::OutputTooShort { needed: 12 }
    );
    // Padded input (stride 5) still needs only W × H outputs.
    assert!(HeightField::from_u16(&[0u16; 14], 4, 3, 5, 1.0, &mut out).is_ok());
    assert_eq!(
        HeightField::from_u16(&[0u16; 13], 4, 3, 5, 1.0, &mut out).unwrap_err(),
        FieldError::SliceTooShort {
            needed: 14,
            given: 13
        }
    );
    for (w, stride, e) in [
        (1, 4, FieldError::TooSmall),
        (4, 3, FieldError::StrideTooSmall),
    ] {
        let got = HeightField::from_u8(&[0u8; 12], w, 3, stride, 1.0, &mut out).unwrap_err();
        assert_eq!(got, e, "{w} x 3, stride {stride}");
    }

    // Values: 0 → 0, full scale → depth (within 1 ulp), monotone, padding skipped,
    // output row-major with stride = width.
    let within_ulp = |a: f32, b: f32| (a - b).abs() <= b.abs() * f32::EPSILON;
    for depth in [1.0f32, 0.1, 3.7, 1000.0, 1e-3, 12345.678, 1e30, -2.5] {
        // Sample (0, 0) is 0, the full-scale one at `full` reads `depth`, the one at
        // `mid` its `share` of it.
        let scaled = |hf: &HeightField, full: [u32; 2], (mid, share): ([u32; 2], f32)| {
            assert_eq!(hf.at(0, 0), 0.0);
            let top = hf.at(full[0], full[1]);
            assert!(within_ulp(top, depth), "full scale -> {top} vs {depth}");
            assert!((hf.at(mid[0], mid[1]) - share * depth).abs() <= depth.abs() * 1e-6);
        };
        let s8 = [0u8, 1, 128, 255, 7, 7, 254, 2, 3];
        let hf = HeightField::from_u8(&s8, 3, 3, 3, depth, &mut out).unwrap();
        scaled(&hf, [0, 1], ([2, 0], 128.0 / 255.0));
        let s16 = [0u16, 1, 65535, 9, 65534, 32768, 0, 0];
        let hf = HeightField::from_u16(&s16, 3, 2, 4, depth, &mut out).unwrap();
        assert_eq!(hf.stride(), 3);
        scaled(&hf, [2, 0], ([1, 1], 32768.0 / 65535.0));
        assert_eq!(hf.samples().len(), 6);
        // Monotone over the whole range.
        let all16: Vec<u16> = (0..=u16::MAX).collect();
        let mut big = vec![0.0f32; all16.len()];
        let hf = HeightField::from_u16(&all16, 256, 256, 256, depth.abs(), &mut big).unwrap();
        assert!(hf.samples().windows(2).all(|w| w[0] <= w[1]));
        assert!(within_ulp(hf.max_height(), depth.abs()));
        let all8: Vec<u8> = (0..=u8::MAX).collect();
        let mut o8 = [0.0f32; 256];
        let hf = HeightField::from_u8(&all8, 16, 16, 16, depth.abs(), &mut o8).unwrap();
        assert!(hf.samples().windows(2).all(|w| w[0] <= w[1]));
        assert!(within_ulp(hf.max_height(), depth.abs()));
    }
}

#[test]
fn query_validation() {
    let ok = |o: [f32; 3], d: [f32; 3], a: f32, b: f32| Query::<f32>::from_arrays(o, d, a, b);
    let (o, d) = ([0.5f32, 0.5, 1.0], [0.0f32, 0.0, -1.0]);
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for k in 0..3 {
            let mut ob = o;
            ob[k] = bad;
            assert_eq!(ok(ob, d, 0.0, 1.0).unwrap_err(), RayError::OriginNotFinite);
            let mut db = d;
            db[k] = bad;
            assert_eq!(
                ok(o, db, 0.0, 1.0).unwrap_err(),
                RayError::DirectionNotFinite
            );
        }
        assert_eq!(
            ok(o, d, bad, f32::INFINITY).unwrap_err(),
            RayError::RangeNotFinite
        );
    }
    assert_eq!(
        ok(o, [0.0; 3], 0.0, 1.0).unwrap_err(),
        RayError::ZeroDirection
    );
    assert_eq!(
        ok(o, [-0.0, 0.0, -0.0], 0.0, 1.0).unwrap_err(),
        RayError::ZeroDirection
    );
    assert_eq!(
        ok(o, d, 0.0, f32::NAN).unwrap_err(),
        RayError::RangeNotFinite
    );
    assert_eq!(
        ok(o, d, 0.0, f32::NEG_INFINITY).unwrap_err(),
        RayError::RangeNotFinite
    );
    assert_eq!(ok(o, d, 2.0, 1.0).unwrap_err(), RayError::EmptyRange);
    assert_eq!(ok(o, d, -1.0, -1.5).unwrap_err(), RayError::EmptyRange);
    // Accepted: t_max = +∞, an empty-length range, negative t_min, tiny directions.
    assert!(ok(o, d, 0.0, f32::INFINITY).is_ok());
    assert!(ok(o, d, 1.0, 1.0).is_ok());
    assert!(ok(o, d, -5.0, 0.0).is_ok());
    assert!(ok(o, [1e-40, 0.0, 0.0], 0.0, 1.0).is_ok());
    // f64 the same; `new` takes glam vectors and agrees with `from_arrays`.
    assert_eq!(
        Query::<f64>::from_arrays([0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0], 0.0, 1.0).unwrap_err(),
        RayError::OriginNotFinite
    );
    assert_eq!(
        Query::<f64>::from_arrays([0.0; 3], [0.0; 3], 0.0, 1.0).unwrap_err(),
        RayError::ZeroDirection
    );
    let q = Query::<f32>::new(
        glam::Vec3::new(0.5, 0.5, 1.0),
        glam::Vec3::new(0.0, 0.0, -1.0),
        0.0,
        1.0,
    );
    assert_eq!(q, ok(o, d, 0.0, 1.0));
    let q = Query::<f64>::new(glam::DVec3::new(0.5, 0.5, 1.0), glam::DVec3::ZERO, 0.0, 1.0);
    assert_eq!(q.unwrap_err(), RayError::ZeroDirection);
    for e in [
        RayError::OriginNotFinite,
        RayError::DirectionNotFinite,
        RayError::ZeroDirection,
        RayError::RangeNotFinite,
        RayError::EmptyRange,
    ] {
        assert!(!e.to_string().is_empty());
    }
}

/// Valid but extreme queries (tiny, huge and subnormal directions, far origins, zero
/// length ranges) on every surface: no panic, no NaN, hits inside the box.
#[test]
fn extreme_valid_queries_trace_cleanly() {
    let mut rng = Rng::new(0xE7);
    let field = fractal_field(&mut rng, 9, 7, 11, 2.0);
    let hf = field.hf();
    let (lo, hi) = field.range();
    let mut queries: Vec<Query<f32>> = Vec::new();
    for scale in [1e-38f32, 1e-40, 1e-20, 1e-6, 1.0, 1e6, 1e20, 1e38] {
        for d in [
            [1.0, 0.3, -0.5],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [-0.7, 1.0, 0.2],
            [1.0, 1.0, -1.0],
        ] {
            let d = d.map(|v: f32| v * scale);
            if d == [0.0; 3] {
                continue;
            }
            for o in [
                [4.0, 3.0, 10.0],
                [-3.0, 3.5, 1.0],
                [4.0, 3.0, -100.0],
                [1e7, -2e7, 3e7],
            ] {
                for (a, b) in [(0.0, f32::INFINITY), (0.0, 0.0), (-1e30, 1e30), (1.0, 2.0)] {
                    if let Ok(q) = Query::from_arrays(o, d, a, b) {
                        queries.push(q);
                    }
                }
            }
        }
    }
    let mut hits = 0;
    let mut disagree = 0;
    for q in &queries {
        for surface in Surface::ALL {
            let t32 = dda::trace(&hf, surface, q);
            let t64 = dda::trace(&hf, surface, &q.cast::<f64>());
            // Within f32's range of parameters the two precisions agree (unless ambiguous).
            let m = q.dir().iter().fold(0f32, |m, v| m.max(v.abs()));
            let tame = (1e-20..=1e20).contains(&m) && q.origin()[0].abs() < 1e3;
            if tame
                && t32.hit.is_some() != t64.hit.is_some()
                && !is_ambiguous(&t64, eps_f32(field.z_scale()))
                && !near_pinch(&field, surface, &q.cast::<f64>(), PINCH)
            {
                disagree += 1;
                println!("{surface:?} {q:?}: f32 {:?} f64 {:?}", t32.hit, t64.hit);
            }
            assert!(!t32.clearance.is_nan() && !t64.clearance.is_nan(), "{q:?}");
            for p in [
                t32.hit.map(|h| p64::<f32>(h.point)),
                t64.hit.map(|h| p64::<f64>(h.point)),
            ]
            .into_iter()
            .flatten()
            {
                hits += 1;
                let slack = 1e-3 * (1.0 + p[2].abs());
                assert!(p.iter().all(|v| v.is_finite()), "{q:?} {p:?}");
                assert!(
                    p[0] >= -1e-3 && p[0] <= 8.001 && p[1] >= -1e-3 && p[1] <= 6.001,
                    "{q:?} {p:?}"
                );
                // Corner planes may rise one range above the highest sample.
                assert!(p[2] <= hi + (hi - lo) + slack, "{q:?} {p:?}");
            }
        }
    }
    println!(
        "extreme queries: {} traced on 5 surfaces x 2 precisions, {hits} hits",
        queries.len()
    );
    assert!(hits > 100);
    assert_eq!(disagree, 0);
}

#[test]
fn revalidating_a_changed_rectangle() {
    let (w, h, stride) = (7u32, 5u32, 9usize);
    let base = vec![1.0f32; stride * (h as usize - 1) + w as usize];
    let before = HeightField::new(&base, w, h, stride).unwrap();
    assert_eq!((before.min_height(), before.max_height()), (1.0, 1.0));
    // Raise one sample and lower another inside [2, 5) x [1, 3).
    let mut changed = base.clone();
    changed[stride + 2] = 9.0;
    changed[2 * stride + 4] = -3.0;
    let after = before.revalidate_rect(&changed, 2, 1, 5, 3).unwrap();
    assert_eq!((after.min_height(), after.max_height()), (-3.0, 9.0));
    // Bounds only widen: restoring a sample keeps the old extremes (conservative).
    let mut restored = changed.clone();
    restored[stride + 2] = 1.0;
    let again = after.revalidate_rect(&restored, 2, 1, 3, 2).unwrap();
    assert_eq!((again.min_height(), again.max_height()), (-3.0, 9.0));
    // A NaN inside the rectangle is found with its index.
    let mut bad = restored.clone();
    bad[2 * stride + 3] = f32::NAN;
    assert_eq!(
        again.revalidate_rect(&bad, 2, 1, 5, 3).unwrap_err(),
        FieldError::NotFinite {
            index: 2 * stride + 3
        }
    );
    for (x0, y0, x1, y1) in [(2, 1, 2, 3), (3, 1, 2, 3), (0, 0, 8, 1), (0, 0, 1, 6)] {
        assert_eq!(
            again
                .revalidate_rect(&restored, x0, y0, x1, y1)
                .unwrap_err(),
            FieldError::BadRect
        );
    }
    assert!(matches!(
        again.revalidate_rect(&restored[..10], 0, 0, 1, 1),
        Err(FieldError::SliceTooShort { .. })
    ));
    println!("revalidate_rect: bounds widened, NaN index and bad rectangles reported");
}

/// `Scene::validate`, the checks the C API's `hf_scene_check` and shader generation
/// share: one to four ray classes, a view angle in (0, 180].
#[test]
fn scenes_validate_their_ray_classes_and_view_angle() {
    use hfcast::scene::{MethodKind, RayClasses, Scene, SceneError};
    let general = Scene::general(MethodKind::Cc, hfcast::Surface::Triangles);
    assert_eq!(general.validate(), Ok(()));
    let cases = [
        (0, 90.0, Err(SceneError::RayClasses)),
        (16, 90.0, Err(SceneError::RayClasses)),
        (1, 0.0, Err(SceneError::ViewAngle)),
        (1, 180.5, Err(SceneError::ViewAngle)),
        (1, f32::NAN, Err(SceneError::ViewAngle)),
        (1, 1e-3, Ok(())),
        (15, 180.0, Ok(())),
    ];
    for (classes, angle, want) in cases {
        let scene = Scene {
            ray_classes: RayClasses(classes),
            max_view_angle_deg: angle,
            ..general
        };
        assert_eq!(scene.validate(), want, "classes {classes}, angle {angle}");
    }
}

/// `Near::sight` (the first pass of a batch in AVX-512 lanes, two rays a vector)
/// answers as the scalar checks do, run by run: valid exactly when
/// `Query::from_arrays` accepts every ray, plain exactly when `Near::holds` holds for
/// every ray, and the rays that leave the eye, on rays built from every kind of bad
/// component and from values at the conditioning thresholds (runs of 1 to 64 rays,
/// odd lengths included). Skipped (with a note) on a CPU without AVX-512F.
#[test]
fn sighting_in_lanes_is_the_scalar_check() {
    use hfcast::condition::{Near, FAR};
    let Some(avx512) = hfcast::detect_avx2!().and_then(|a| a.avx512()) else {
        println!("no AVX-512F here: the lanes are not tested");
        return;
    };
    let heights: Vec<f32> = (0..33 * 17).map(|k| (k % 7) as f32 * 3.0 - 5.0).collect();
    let hf = HeightField::new(&heights, 33, 17, 33).unwrap();
    let near = Near::<f32>::of(&hf);
    // One more than the largest of W − 1, H − 1 and the height range: 33.
    let reach = (FAR * 33.0) as f32;
    let eye = [-4.0f32, 0.0, 12.5];
    let small = 1.0 / 4_294_967_296.0f32;
    // Components at and around every threshold, and every kind of bad value.
    let edges = [
        0.0,
        -0.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        small,
        small.next_down(),
        1.0 / small,
        (1.0 / small).next_up(),
        -reach,
        (-reach).next_down(),
        32.0 + reach,
        (32.0 + reach).next_up(),
        -5.0 - reach,
        16.0 + reach,
        f32::MAX,
        f32::MIN_POSITIVE,
    ];
    let mut rng = Rng::new(0x51_6e);
    let component = |rng: &mut Rng, lo: f32, hi: f32| match rng.below(8) {
        0 => edges[rng.below(edges.len())],
        _ => rng.range(f64::from(lo), f64::from(hi)) as f32,
    };
    let (mut runs, mut invalid_runs, mut odd_plain) = (0, 0, 0);
    for _ in 0..20_000 {
        let len = 1 + rng.below(64);
        let rays: Vec<[f32; 8]> = (0..len)
            .map(|_| {
                let mut r = [0.0f32; 8];
                for (k, v) in r.iter_mut().enumerate() {
                    *v = match k {
                        0..=2 if rng.below(3) == 0 => eye[k],
                        0..=2 => component(&mut rng, -40.0, 70.0),
                        3..=5 => component(&mut rng, -1.0, 1.0),
                        6 => component(&mut rng, 0.0, 5.0),
                        _ if rng.below(4) == 0 => f32::INFINITY,
                        _ => component(&mut rng, 0.0, 100.0),
                    };
                }
                // Some rays with no direction, some with a reversed range.
                match rng.below(32) {
                    0 => r[3..6].copy_from_slice(&[0.0, -0.0, 0.0]),
                    1 => (r[6], r[7]) = (r[7].max(1.0), r[6].min(0.5)),
                    _ => {}
                }
                // Mostly valid rays, so that the plain test is seen on whole runs.
                if rng.below(4) != 0 {
                    for v in r.iter_mut() {
                        if !v.is_finite() {
                            *v = 1.0;
                        }
                    }
                    r[7] = r[7].max(r[6]);
                }
                r
            })
            .collect();
        let queries: Vec<_> = rays
            .iter()
            .map(|r| Query::from_arrays([r[0], r[1], r[2]], [r[3], r[4], r[5]], r[6], r[7]))
            .collect();
        let valid = queries.iter().all(|q| q.is_ok());
        let at_eye = rays
            .iter()
            .enumerate()
            .filter(|(_, r)| r[0] == eye[0] && r[1] == eye[1] && r[2] == eye[2])
            .fold(0u64, |m, (k, _)| m | 1 << k);
        let got = near.sight(&rays, eye, avx512);
        assert_eq!(got.valid, valid, "{rays:?}");
        assert_eq!(got.at_eye, at_eye, "{rays:?}");
        if valid {
            let plain = queries.iter().flatten().all(|q| near.holds(q));
            assert_eq!(got.plain, plain, "{rays:?}");
            odd_plain += usize::from(!plain);
        }
        runs += 1;
        invalid_runs += usize::from(!valid);
    }
    println!("{runs} runs, {invalid_runs} with an invalid ray, {odd_plain} valid ones not plain");
    assert!(invalid_runs > 1000 && runs - invalid_runs > 1000 && odd_plain > 100);
}
