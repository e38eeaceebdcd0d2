//! `hfcast report` end to end on a tiny run: one synthetic scene, small images.

use std::path::Path;
use std::process::Command;

#[test]
fn report_writes_markdown_csv_and_plots() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report_tiny");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args([
            "report",
            "--quick",
            "--scenes",
            "synthetic-needles,synthetic-fractal-bilinear",
        ])
        .args([
            "--synthetic",
            "24",
            "--size",
            "12x9",
            "--reps",
            "1",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("## Summary"), "{stdout}");
    let md = std::fs::read_to_string(dir.join("README.md")).unwrap();
    for want in [
        "### synthetic-needles",
        "### synthetic-fractal-bilinear",
        "| dda f32 | yes | 0 | 0 |",
        "parry3d, split as ours",
        "maxmip iter",
        "plots/synthetic-needles.svg",
    ] {
        assert!(md.contains(want), "missing {want:?}");
    }
    let svg = std::fs::read_to_string(dir.join("plots/synthetic-needles.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("Pareto front"));
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    assert!(csv.lines().count() > 20);
    // Bad options are refused.
    let bad = Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args(["report", "--size", "0x3"])
        .output()
        .unwrap();
    assert!(!bad.status.success());
}
