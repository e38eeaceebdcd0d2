//! Maximum mipmaps: the bake against its definition, updates against a full re-bake, and
//! the march against the f64 exact DDA (zero wrong rays without LOD) on synthetic fields.
#![cfg(feature = "maxmip")]

mod common;

use common::{dist, eps_f32, fractal_field, is_ambiguous, kind_blocks, p64, Field, RayKind, Rng};
use hfcast::maxmip::{self, Ascent, Layout, MaxMip, Options, PyramidError};
use hfcast::{dda, HeightField, Query, Real, Surface, Trace};

/// The pyramid by its definition: texel (i, j) of level L is the highest sample of the
/// cells [i·2ᴸ, (i+1)·2ᴸ) × [j·2ᴸ, (j+1)·2ᴸ) that exist.
fn naive_pyramid(hf: &HeightField) -> Vec<f32> {
    let layout = Layout::of(hf);
    let cells = layout.dims(0);
    let mut out = Vec::new();
    for level in 0..layout.levels() {
        let [w, h] = layout.dims(level);
        for j in 0..h {
            for i in 0..w {
                let mut m = f32::NEG_INFINITY;
                for y in (j << level)..=((j + 1) << level).min(cells[1]) {
                    for x in (i << level)..=((i + 1) << level).min(cells[0]) {
                        m = m.max(hf.at(x, y));
                    }
                }
                out.push(m);
            }
        }
    }
    out
}

fn baked(hf: &HeightField) -> Vec<f32> {
    let mut p = vec![f32::NAN; maxmip::pyramid_len(hf.width(), hf.height())];
    maxmip::bake(hf, &mut p).unwrap();
    p
}

/// A `w × h` fractal field (rows not padded, amplitude `amp`) drawn from `rng`, and
/// its pyramid.
fn fractal_pyramid(rng: &mut Rng, w: u32, h: u32, amp: f64) -> (Field, Vec<f32>) {
    let field = fractal_field(rng, w, h, w as usize, amp);
    let pyramid = baked(&field.hf());
    (field, pyramid)
}

#[test]
fn layout_sizes() {
    assert_eq!(maxmip::pyramid_len(2, 2), 1);
    assert_eq!(maxmip::pyramid_len(1, 5), 0);
    // 3 × 3 cells: 9 + 4 + 1.
    assert_eq!(maxmip::pyramid_len(4, 4), 14);
    // 1 × 63 cells: 63 + 32 + 16 + 8 + 4 + 2 + 1.
    assert_eq!(maxmip::pyramid_len(2, 64), 126);
    let l = Layout::new(129, 65).unwrap();
    assert_eq!(l.dims(0), [128, 64]);
    assert_eq!(l.dims(l.levels() - 1), [1, 1]);
    assert_eq!(l.levels(), 8);
    assert_eq!(l.offset(1), 128 * 64);
    let l = Layout::new(1 << 24, 2).unwrap();
    assert_eq!(l.levels(), 25);
    assert!(Layout::new((1 << 24) + 1, 2).is_none());
    let hf_s = [0.0f32; 4];
    let hf = HeightField::new(&hf_s, 2, 2, 2).unwrap();
    assert_eq!(
        maxmip::bake(&hf, &mut []),
        Err(PyramidError::TooShort {
            what: "pyramid",
            needed: 1,
            given: 0
        })
    );
    let mut p = [0.0];
    assert_eq!(
        maxmip::update_rect(&hf, &mut p, 1, 0, 0, 1),
        Err(PyramidError::BadRect)
    );
    assert_eq!(
        maxmip::update_rect(&hf, &mut p, 0, 0, 3, 1),
        Err(PyramidError::BadRect)
    );
}

/// The field sizes (samples) the bake is checked on: one cell, single rows and columns
/// of cells, power-of-two cell counts (129 × 65) and others.
const BAKE_SIZES: [(u32, u32); 8] = [
    (2, 2),
    (3, 2),
    (2, 64),
    (64, 2),
    (37, 23),
    (129, 65),
    (17, 33),
    (64, 64),
];

#[test]
fn bake_matches_definition() {
    let mut rng = Rng::new(41);
    for (w, h) in BAKE_SIZES {
        let stride = w as usize + rng.below(3);
        let f = fractal_field(&mut rng, w, h, stride, 10.0);
        let hf = f.hf();
        assert_eq!(baked(&hf), naive_pyramid(&hf), "{w} x {h}");
        // Row-range bake, level by level in two halves, as a job system would.
        let layout = Layout::of(&hf);
        let mut p = vec![f32::NAN; layout.texel_count()];
        for level in 0..layout.levels() {
            let [lw, lh] = layout.dims(level);
            let (finer, out) = layout.split_level(&mut p, level);
            let mid = lh / 2;
            let (top, bottom) = out.split_at_mut((mid * lw) as usize);
            maxmip::bake_rows(&hf, level, mid..lh, finer, bottom);
            maxmip::bake_rows(&hf, level, 0..mid, finer, top);
        }
        assert_eq!(p, baked(&hf), "rows {w} x {h}");
    }
}

#[test]
fn updates_equal_rebake() {
    let mut rng = Rng::new(7);
    let sizes = [
        (2, 2),
        (2, 9),
        (9, 2),
        (37, 23),
        (64, 64),
        (129, 65),
        (33, 17),
    ];
    let mut updates = 0;
    for (w, h) in sizes {
        let stride = w as usize + rng.below(2);
        let mut f = fractal_field(&mut rng, w, h, stride, 5.0);
        let mut pyr = baked(&f.hf());
        for _ in 0..60 {
            let x0 = rng.int(0, w as i64 - 1) as u32;
            let y0 = rng.int(0, h as i64 - 1) as u32;
            let x1 = (x0 + 1 + rng.int(0, 12) as u32).min(w);
            let y1 = (y0 + 1 + rng.int(0, 12) as u32).min(h);
            // Raise, lower (so maxima drop) or flatten.
            let mode = rng.below(3);
            for j in y0..y1 {
                for i in x0..x1 {
                    let s = &mut f.samples[j as usize * stride + i as usize];
                    *s = match mode {
                        0 => *s + rng.range(0.0, 10.0) as f32,
                        1 => *s - rng.range(0.0, 10.0) as f32,
                        _ => 1.0,
                    };
                }
            }
            let hf = f.hf();
            maxmip::update_rect(&hf, &mut pyr, x0, y0, x1, y1).unwrap();
            assert_eq!(pyr, baked(&hf), "{w} x {h} after [{x0},{x1}) x [{y0},{y1})");
            updates += 1;
        }
        // An empty rectangle changes nothing.
        maxmip::update_rect(&f.hf(), &mut pyr, 1, 1, 1, 2).unwrap();
    }
    println!("{updates} random updates, each equal to a full re-bake");
}

/// Needles: a low, gently noisy base with single tall texels.
fn needles(rng: &mut Rng, w: u32, h: u32) -> Field {
    let mut f = Field::from_fn(w, h, w as usize, |_, _| rng.range(0.0, 0.2) as f32);
    for _ in 0..(w * h / 40).max(2) {
        let (i, j) = (rng.below(w as usize), rng.below(h as usize));
        f.samples[j * w as usize + i] = rng.range(3.0, 40.0) as f32;
    }
    f
}

/// 1-texel walls: whole rows, columns and diagonals of tall samples on a flat floor,
/// some with one-texel gaps.
fn walls(rng: &mut Rng, w: u32, h: u32) -> Field {
    let mut f = Field::from_fn(w, h, w as usize, |_, _| 0.0);
    for _ in 0..4 {
        let z = rng.range(2.0, 20.0) as f32;
        let k = rng.below(3);
        let at = rng.below(w.min(h) as usize);
        let gap = rng.below(w.max(h) as usize);
        for s in 0..w.max(h) as usize {
            let (i, j) = match k {
                0 => (s, at),
                1 => (at, s),
                _ => (s, s),
            };
            if i < w as usize && j < h as usize && s != gap {
                f.samples[j * w as usize + i] = z;
            }
        }
    }
    f
}

/// Builds `target`'s pyramid the dynamic way: bake an unrelated field of the same size,
/// then copy the samples over in random rectangles, updating after each; checks the
/// result against a full bake.
fn pyramid_by_updates(rng: &mut Rng, target: &Field) -> Vec<f32> {
    let mut f = fractal_field(rng, target.w, target.h, target.stride, 30.0);
    let mut pyr = baked(&f.hf());
    let (w, h) = (target.w, target.h);
    let (bw, bh) = (rng.int(1, 20) as u32, rng.int(1, 20) as u32);
    for y0 in (0..h).step_by(bh as usize) {
        for x0 in (0..w).step_by(bw as usize) {
            let (x1, y1) = ((x0 + bw).min(w), (y0 + bh).min(h));
            for j in y0..y1 {
                for i in x0..x1 {
                    let k = j as usize * f.stride + i as usize;
                    f.samples[k] = target.samples[k];
                }
            }
            maxmip::update_rect(&f.hf(), &mut pyr, x0, y0, x1, y1).unwrap();
        }
    }
    assert_eq!(pyr, baked(&target.hf()));
    pyr
}

/// Counts of one case.
#[derive(Default)]
struct Count {
    tried: u64,
    wrong: u64,
    ambiguous: u64,
    ambiguous_differ: u64,
    /// Rays whose hit differs in any bit from `dda::trace` in the same precision.
    not_dda: u64,
    fetches_dda: u64,
    fetches: [u64; 2],
    examples: Vec<String>,
}

/// Compares one maxmip answer with the oracle: wrong when hit/miss, the flags, or the
/// hit point (by more than 1e-3 texel) differ.
fn differs<R: Real>(mm: &Trace<R>, oracle: &Trace<f64>) -> bool {
    match (&mm.hit, &oracle.hit) {
        (None, None) => false,
        (Some(a), Some(b)) => dist(p64::<R>(a.point), b.point.into()) > 1e-3 || a.flags != b.flags,
        _ => true,
    }
}

/// Traces `q` (in precision `R`) with both ascents; counts it; returns the answers.
fn check<R: Real>(
    hf: &HeightField,
    mip: &MaxMip,
    surface: Surface,
    q: &Query<R>,
    oracle: &Trace<f64>,
    ambiguous: bool,
    n: &mut Count,
) {
    let dda_r = dda::trace(hf, surface, q);
    n.tried += 1;
    n.fetches_dda += u64::from(dda_r.fetches);
    let mut bad = false;
    for (k, ascent) in [Ascent::OneLevel, Ascent::Highest].into_iter().enumerate() {
        let opts = Options {
            ascent,
            ..Options::default()
        };
        let mm = maxmip::trace(hf, mip, surface, q, &opts);
        n.fetches[k] += u64::from(mm.fetches);
        if mm.hit != dda_r.hit {
            n.not_dda += 1;
        }
        if differs(&mm, oracle) && !bad {
            bad = true;
            if ambiguous {
                n.ambiguous_differ += 1;
            } else {
                n.wrong += 1;
                if n.examples.len() < 4 {
                    n.examples.push(format!(
                        "{ascent:?} {q:?}: maxmip {:?} oracle {:?}",
                        mm.hit, oracle.hit
                    ));
                }
            }
        }
    }
    n.ambiguous += u64::from(ambiguous);
}

fn print_case(name: &str, n: &Count) {
    let per = |f: u64| f as f64 / n.tried.max(1) as f64;
    println!(
        "{name:<34} tried {:>5}  wrong {:>2}  ambiguous {:>3} (differ {:>2})  not-dda {:>2}  \
         fetches/ray dda {:>7.1} one-level {:>6.1} highest {:>6.1}",
        n.tried,
        n.wrong,
        n.ambiguous,
        n.ambiguous_differ,
        n.not_dda,
        per(n.fetches_dda),
        per(n.fetches[0]),
        per(n.fetches[1]),
    );
    for e in &n.examples {
        println!("    e.g. {e}");
    }
}

#[test]
fn march_matches_oracle() {
    let mut rng = Rng::new(2008);
    let mut fields: Vec<(String, Field)> = Vec::new();
    for (w, h) in [(64, 64), (37, 23), (2, 2), (2, 64), (64, 2), (129, 65)] {
        let stride = w as usize + rng.below(2);
        let f = fractal_field(&mut rng, w, h, stride, 0.1 * w.max(h) as f64 + 1.0);
        fields.push((format!("fractal {w}x{h}"), f));
    }
    fields.push(("needles 48x40".into(), needles(&mut rng, 48, 40)));
    fields.push(("needles 129x65".into(), needles(&mut rng, 129, 65)));
    fields.push(("walls 40x33".into(), walls(&mut rng, 40, 33)));
    fields.push(("walls 64x64".into(), walls(&mut rng, 64, 64)));
    let rays_per_kind = 120;
    let mut total = (0, 0, 0);
    for (name, field) in &fields {
        let pyr = pyramid_by_updates(&mut rng, field);
        let hf = field.hf();
        let mip = MaxMip::new(&hf, &pyr).unwrap();
        let eps = eps_f32(field.z_scale());
        for surface in [Surface::Triangles, Surface::Bilinear] {
            let (mut n32, mut n64) = (Count::default(), Count::default());
            for spec in kind_blocks(&mut rng, field, surface, &RayKind::ALL, rays_per_kind) {
                let q32 = spec.q32();
                let q64: Query<f64> = q32.cast();
                let oracle = dda::trace(&hf, surface, &q64);
                let amb = is_ambiguous(&oracle, eps);
                check(&hf, &mip, surface, &q32, &oracle, amb, &mut n32);
                check(&hf, &mip, surface, &q64, &oracle, amb, &mut n64);
            }
            print_case(&format!("{name} {} f32", surface.name()), &n32);
            print_case(&format!("{name} {} f64", surface.name()), &n64);
            for n in [&n32, &n64] {
                total = (total.0 + n.tried, total.1 + n.wrong, total.2 + n.ambiguous);
            }
            // f64 maxmip is the f64 DDA itself: not one bit differs.
            assert_eq!(
                n64.not_dda, 0,
                "{name} {surface:?}: f64 maxmip differs from f64 dda"
            );
            assert_eq!(n32.wrong + n64.wrong, 0, "{name} {surface:?}: wrong rays");
        }
    }
    println!(
        "total: tried {}  wrong {}  ambiguous {}",
        total.0, total.1, total.2
    );
}

#[test]
fn other_surfaces_match_dda() {
    // Height planes and view-linear are bounded by the corners too: maxmip = DDA exactly.
    // Corner planes are not, and go to the DDA.
    let mut rng = Rng::new(99);
    let (field, pyr) = fractal_pyramid(&mut rng, 37, 29, 6.0);
    let hf = field.hf();
    let mip = MaxMip::new(&hf, &pyr).unwrap();
    for surface in [
        Surface::HeightPlanes,
        Surface::ViewLinear,
        Surface::CornerPlanes,
    ] {
        let mut differ = 0;
        for spec in kind_blocks(&mut rng, &field, surface, &RayKind::ALL, 100) {
            let q = spec.q64();
            let mm = maxmip::trace(&hf, &mip, surface, &q, &Options::default());
            differ += usize::from(mm.hit != dda::trace(&hf, surface, &q).hit);
        }
        println!(
            "{:<14} tried 1300  differ from dda {differ}",
            surface.name()
        );
        assert_eq!(differ, 0, "{surface:?}");
    }
}

#[test]
fn approximate_options() {
    // LOD and iterative bilinear are approximate: measured, not asserted exact.
    let (field, pyr) = fractal_pyramid(&mut Rng::new(5), 257, 129, 26.0);
    let hf = field.hf();
    let mip = MaxMip::new(&hf, &pyr).unwrap();
    let eps = eps_f32(field.z_scale());
    let cases: [(&str, Surface, Options); 4] = [
        (
            "lod 1/512",
            Surface::Triangles,
            Options {
                lod: Some(1.0 / 512.0),
                ..Options::default()
            },
        ),
        (
            "lod 1/128",
            Surface::Triangles,
            Options {
                lod: Some(1.0 / 128.0),
                ..Options::default()
            },
        ),
        (
            "bilinear iterative 4+4",
            Surface::Bilinear,
            Options {
                iterative_bilinear: Some((4, 4)),
                ..Options::default()
            },
        ),
        (
            "bilinear iterative 8+12",
            Surface::Bilinear,
            Options {
                iterative_bilinear: Some((8, 12)),
                ..Options::default()
            },
        ),
    ];
    let kinds = [
        RayKind::Down,
        RayKind::Outside,
        RayKind::Grazing,
        RayKind::Up,
    ];
    for (name, surface, opts) in cases {
        assert!(!opts.is_exact());
        let (mut tried, mut wrong, mut amb, mut f_exact, mut f_opt) = (0, 0, 0, 0u64, 0u64);
        for spec in kind_blocks(&mut Rng::new(6), &field, surface, &kinds, 500) {
            let q = spec.q32();
            let oracle = dda::trace(&hf, surface, &q.cast::<f64>());
            let exact = maxmip::trace(&hf, &mip, surface, &q, &Options::default());
            let approx = maxmip::trace(&hf, &mip, surface, &q, &opts);
            tried += 1;
            f_exact += u64::from(exact.fetches);
            f_opt += u64::from(approx.fetches);
            if is_ambiguous(&oracle, eps) {
                amb += 1;
            } else if differs(&approx, &oracle) {
                wrong += 1;
            }
        }
        println!(
            "{name:<24} tried {tried}  wrong {wrong}  ambiguous {amb}  fetches/ray exact {:.1} \
             approximate {:.1}",
            f_exact as f64 / tried as f64,
            f_opt as f64 / tried as f64
        );
    }
}

/// A pyramid of more levels than the lanes' level tables hold (a side of 2¹⁶ cells):
/// [`maxmip::trace_lanes`] answers as [`maxmip::trace`] (query by query, with or
/// without the SIMD token).
#[test]
fn lanes_on_a_pyramid_of_seventeen_levels() {
    let (w, h) = ((1u32 << 16) + 1, 3);
    let samples: Vec<f32> = (0..w * h).map(|k| ((k * 7919) % 13) as f32).collect();
    let hf = HeightField::new(&samples, w, h, w as usize).unwrap();
    let pyramid = baked(&hf);
    let mip = MaxMip::new(&hf, &pyramid).unwrap();
    assert_eq!(mip.layout().levels(), 17);
    let mut rng = Rng::new(17);
    let qs: Vec<Query<f32>> = (0..200)
        .map(|_| {
            let o = [
                rng.range(0.0, w as f64),
                rng.range(0.0, 2.0),
                rng.range(0.0, 16.0),
            ];
            let d = [
                rng.range(-1.0, 1.0),
                rng.range(-0.01, 0.01),
                rng.range(-0.2, 0.0),
            ];
            Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .unwrap()
        })
        .collect();
    let o = Options::default();
    let want: Vec<String> = qs
        .iter()
        .map(|q| bits(&maxmip::trace(&hf, &mip, Surface::Triangles, q, &o)))
        .collect();
    let mut got = vec![Trace::MISS; qs.len()];
    maxmip::trace_lanes(
        &hf,
        &mip,
        Surface::Triangles,
        &qs,
        &o,
        &mut got,
        hfcast::detect_avx2!(),
    );
    let got: Vec<String> = got.iter().map(bits).collect();
    assert_eq!(got, want);
    assert!(got.iter().any(|g| g.contains("hit: Some")), "some rays hit");
}

#[test]
fn vertical_and_axis_rays_at_integers() {
    // Every integer grid point, straight down and along both axes through it.
    let (field, pyr) = fractal_pyramid(&mut Rng::new(3), 19, 11, 4.0);
    let hf = field.hf();
    let mip = MaxMip::new(&hf, &pyr).unwrap();
    let z = hf.max_height() + 1.0;
    let mut n = 0;
    for j in 0..11 {
        for i in 0..19 {
            let (x, y) = (i as f32, j as f32);
            let dirs = [
                [0.0, 0.0, -1.0],
                [1.0, 0.0, -0.3],
                [-1.0, 0.0, -0.3],
                [0.0, 1.0, -0.3],
                [0.0, -1.0, -0.3],
                [1.0, 1.0, -0.5],
                [0.0, 0.0, 1.0],
            ];
            for d in dirs {
                let q = Query::from_arrays([x, y, z], d, 0.0, f32::INFINITY).unwrap();
                for s in [Surface::Triangles, Surface::Bilinear] {
                    for ascent in [Ascent::OneLevel, Ascent::Highest] {
                        let opts = Options {
                            ascent,
                            ..Options::default()
                        };
                        let mm = maxmip::trace(&hf, &mip, s, &q, &opts);
                        assert_eq!(mm.hit, dda::trace(&hf, s, &q).hit, "{q:?} {s:?}");
                        n += 1;
                    }
                }
            }
        }
    }
    println!("{n} vertical / axis rays through grid points: all equal to the DDA");
}

/// A trace as text: equal texts are equal bit for bit (`-0.0` and `0.0` differ).
fn bits<R: Real>(tr: &Trace<R>) -> String {
    format!("{tr:?}")
}

/// [`maxmip::trace_lanes`] answers each query with exactly [`maxmip::trace`]'s answer,
/// hit, fetches and clearance, on every march field, surface and ray kind, with both
/// ascents, with level of detail and with the iterative bilinear search; fewer
/// queries than a set of lanes, more than one set and fewer than two, and more; with the
/// SIMD token (AVX-512's sixteen lanes where the CPU has them, and AVX2's eight) and
/// without.
#[test]
fn lanes_equal_the_scalar_march() {
    let mut rng = Rng::new(0x1a7e5);
    let fields = common::march_fields(0x1a7e, 3, ("checkerboard 24x20", 0.0, 1.0), Vec::new(), 4);
    let options = [
        Options::default(),
        Options {
            ascent: Ascent::Highest,
            ..Options::default()
        },
        Options {
            lod: Some(1.0 / 64.0),
            ..Options::default()
        },
        Options {
            iterative_bilinear: Some((4, 8)),
            ..Options::default()
        },
    ];
    let (mut tried, mut differ) = (0, 0);
    for (name, field) in &fields {
        let hf = field.hf();
        let pyramid = baked(&hf);
        let mip = MaxMip::new(&hf, &pyramid).unwrap();
        for surface in Surface::ALL {
            let specs = kind_blocks(&mut rng, field, surface, &RayKind::ALL, 7);
            for o in &options {
                for n in [1, 5, 12, 20, specs.len()] {
                    let qs: Vec<Query<f32>> = specs[..n].iter().map(|s| s.q32()).collect();
                    let want: Vec<String> = qs
                        .iter()
                        .map(|q| bits(&maxmip::trace(&hf, &mip, surface, q, o)))
                        .collect();
                    let avx2 = hfcast::detect_avx2!().map(|s| s.without_avx512());
                    for simd in [hfcast::detect_avx2!(), avx2, None] {
                        let mut got = vec![Trace::MISS; n];
                        maxmip::trace_lanes(&hf, &mip, surface, &qs, o, &mut got, simd);
                        let d = got
                            .iter()
                            .zip(&want)
                            .filter(|(g, w)| bits(*g) != **w)
                            .count();
                        assert_eq!(d, 0, "{name} {surface:?} {o:?} {n} queries, {simd:?}");
                        (tried, differ) = (tried + n, differ + d);
                    }
                }
            }
        }
    }
    println!(
        "lanes ({:?}): {tried} answers compared, {differ} differ",
        hfcast::detect_avx2!()
    );
    assert!(tried > 10_000);
}
