//! `hfcast trace` with every method of the core, end to end: the exact ones answer the
//! exact traversal's hits on the bundled map, the others answer well-formed lines; a
//! method that does not trace the surface is refused.

mod common;

use hfcast::scene::MethodKind;
use hfcast_tools::parse_method;

/// Runs `hfcast trace ARGS` on `stdin`: exit success, stdout and stderr (a refused
/// command exits before it reads: the pipe may be closed then).
fn trace(args: &[&str], stdin: &str) -> (bool, String, String) {
    let run = common::run_hfcast(None, &[&["trace"], args].concat(), stdin);
    (run.ok, run.stdout, run.stderr)
}

/// Rays over the bundled 403 × 344 map: downwards in all four horizontal classes,
/// shallow and steep, one that flies over everything, one that starts below the
/// surface.
const RAYS: &str = "\
200 170 500 0 0 -1
-50 170 60 1 0.1 -0.12
450 100 70 -1 0.3 -0.3
100 -40 60 0.2 1 -0.1
300 380 60 -0.1 -1 -0.3
10 10 80 1 0.8 -0.25
0 0 200 1 1 0.2
150 150 -5 0.3 0.2 1
";

/// `(hit point or None)` of each output line.
fn points(out: &str) -> Vec<Option<[f64; 3]>> {
    out.lines()
        .map(|l| {
            let w: Vec<&str> = l.split(' ').collect();
            match w[0] {
                "hit" => Some([2, 3, 4].map(|k| w[k].parse().unwrap())),
                "miss" => None,
                other => panic!("unexpected answer {other:?} in {l:?}"),
            }
        })
        .collect()
}

#[test]
fn every_method_answers_and_the_exact_ones_match_the_dda() {
    let (ok, want, err) = trace(&["--method", "exact"], RAYS);
    assert!(ok, "{err}");
    let want = points(&want);
    assert_eq!(want.len(), 8);
    assert!(want.iter().filter(|p| p.is_some()).count() >= 6, "{want:?}");
    for kind in MethodKind::ALL {
        let (ok, out, err) = trace(&["--method", kind.name()], RAYS);
        assert!(ok, "{}: {err}", kind.name());
        let got = points(&out);
        assert_eq!(got.len(), want.len(), "{}: {out}", kind.name());
        if !parse_method(kind.name()).unwrap().is_exact() {
            continue;
        }
        for (k, (w, g)) in want.iter().zip(&got).enumerate() {
            match (w, g) {
                (None, None) => {}
                (Some(w), Some(g)) => {
                    let e = (0..3).map(|i| (w[i] - g[i]).powi(2)).sum::<f64>().sqrt();
                    assert!(e < 1e-3, "{} ray {k}: {g:?} vs {w:?}", kind.name());
                }
                _ => panic!("{} ray {k}: {g:?} vs {w:?}", kind.name()),
            }
        }
    }
}

#[test]
fn baked_methods_trace_the_surfaces_they_bound() {
    // The safety-shape maps bound the view-linear surface too.
    let (ok, want, err) = trace(&["--method", "exact", "--surface", "view-linear"], RAYS);
    assert!(ok, "{err}");
    let (ok, got, err) = trace(&["--method", "cc", "--surface", "view-linear"], RAYS);
    assert!(ok, "{err}");
    assert!(err.contains("baked cc"), "{err}");
    let (want, got) = (points(&want), points(&got));
    for (w, g) in want.iter().zip(&got) {
        assert_eq!(w.is_some(), g.is_some(), "{got:?} vs {want:?}");
    }
    // The cone family marches the triangle surface only.
    let (ok, out, err) = trace(&["--method", "cone", "--surface", "bilinear"], RAYS);
    assert!(!ok && out.is_empty(), "{out}");
    assert!(err.contains("does not trace the bilinear surface"), "{err}");
    let (ok, _, err) = trace(&["--method", "nonsense"], RAYS);
    assert!(!ok && err.contains("unknown method"), "{err}");
}
