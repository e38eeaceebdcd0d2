//! `hfcast report` over a data folder with unreadable maps: they are skipped with a
//! warning (and a line in the report) when a scene of `--scenes` names them, never read
//! when none does.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A data folder with one good 16-bit map (`good`), a file that is no PNG (`broken`:
/// the listing fails) and a PNG cut off in its samples (`truncated`: loading fails).
fn data_folder() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report_bad_maps_data");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (w, h) = (20u32, 14u32);
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, w, h);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Sixteen);
        let mut writer = enc.write_header().unwrap();
        let samples: Vec<u8> = (0..w * h)
            .flat_map(|k| ((k * 7919 % 65536) as u16).to_be_bytes())
            .collect();
        writer.write_image_data(&samples).unwrap();
    }
    std::fs::write(dir.join("good.png"), &png_bytes).unwrap();
    std::fs::write(dir.join("broken.png"), b"not a png at all").unwrap();
    // Its header reads (the listing passes it), its samples do not.
    let cut = png_bytes.len() - 20;
    std::fs::write(dir.join("truncated.png"), &png_bytes[..cut]).unwrap();
    dir
}

/// Runs a tiny quick report on `data` keeping `scenes`: success, stderr, README.md.
fn report(data: &Path, scenes: &str, out: &str) -> (bool, String, String) {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(out);
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .env("HFCAST_DATA", data)
        .args(["report", "--quick", "--scenes", scenes])
        .args(["--synthetic", "16", "--size", "8x6", "--reps", "1", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
    let md = std::fs::read_to_string(out.join("README.md")).unwrap_or_default();
    (run.status.success(), stderr, md)
}

#[test]
fn unreadable_maps_are_skipped_and_excluded_ones_never_read() {
    let data = data_folder();
    let (ok, err, md) = report(&data, "good,broken,truncated", "report_bad_maps");
    assert!(ok, "{err}");
    for name in ["broken.png", "truncated.png"] {
        assert!(
            err.lines()
                .any(|l| l.contains("warning") && l.contains(name)),
            "no warning for {name}: {err}"
        );
        assert!(
            md.lines()
                .any(|l| l.starts_with("- Skipped a map") && l.contains(name)),
            "no report line for {name}"
        );
    }
    assert!(md.contains("### good@0.05") && md.contains("### good@0.15"));

    // Excluded by --scenes: not even a warning.
    let (ok, err, md) = report(&data, "good@0.05", "report_bad_maps_excluded");
    assert!(ok, "{err}");
    assert!(
        !err.contains("broken") && !err.contains("truncated"),
        "{err}"
    );
    assert!(md.contains("### good@0.05") && !md.contains("### good@0.15"));
    assert!(!md.contains("Skipped a map"));
}
