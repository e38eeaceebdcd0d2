//! `hfcast render` heat maps and method choice, and `hfcast advise`, end to end on the
//! bundled map.

use std::path::Path;
use std::process::Command;

/// Runs `hfcast ARGS` in `dir`: success, stdout, stderr.
fn hfcast(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (out.status.success(), text(&out.stdout), text(&out.stderr))
}

/// Size and RGB bytes of a PNG.
fn read_rgb(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    (info.width, info.height, buf)
}

fn fresh(name: &str) -> std::path::PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn render_writes_depth_and_fetch_heat_maps() {
    let dir = fresh("render_heat_maps");
    let args = [
        "render", "--width", "64", "--height", "48", "--method", "cc",
    ];
    let (ok, out, err) = hfcast(&dir, &args);
    assert!(ok, "{err}");
    assert!(out.contains("Mrays/s") && out.contains("bake"), "{out}");
    // The core's bake plan for the scene: the render's camera and light cast three of
    // the four ray classes.
    assert!(
        err.contains("bake plan: keeps cc map; scratch safety scratch, n-buffer; ray classes"),
        "{err}"
    );
    assert!(out.contains("render.depth.png (depth ") && out.contains("99th percentile"));
    let (w, h, picture) = read_rgb(&dir.join("out/render.png"));
    for name in ["out/render.depth.png", "out/render.fetches.png"] {
        let (hw, hh, heat) = read_rgb(&dir.join(name));
        assert_eq!((hw, hh), (w, h), "{name}");
        // Sky pixels of the depth map are black; terrain pixels are not; the ramp
        // spans several colours.
        let colours: std::collections::HashSet<&[u8]> = heat.chunks(3).collect();
        assert!(colours.len() > 20, "{name}: {} colours", colours.len());
    }
    let (_, _, depth) = read_rgb(&dir.join("out/render.depth.png"));
    let black = depth.chunks(3).filter(|p| p == &[0, 0, 0]).count();
    assert!(black > 0 && black < depth.len() / 3, "{black} black pixels");
    assert_ne!(picture, depth);

    // --no-heatmaps writes the picture only; an exact method draws the same picture.
    let dir = fresh("render_no_heat_maps");
    let (ok, out, err) = hfcast(
        &dir,
        &["render", "--width", "64", "--height", "48", "--no-heatmaps"],
    );
    assert!(ok, "{err}");
    assert!(!out.contains("depth.png"), "{out}");
    assert!(!dir.join("out/render.depth.png").exists());
    assert_eq!(read_rgb(&dir.join("out/render.png")).2, picture);
}

#[test]
fn advise_chooses_an_exact_method_and_render_auto_uses_it() {
    let dir = fresh("advise");
    let size = ["--width", "48", "--height", "36"];
    let (ok, out, err) = hfcast(&dir, &[&["advise", "--reps", "1"][..], &size].concat());
    assert!(ok, "{err}");
    for method in ["exact", "maxmip", "safety", "cc", "radius"] {
        let row = out
            .lines()
            .find(|l| l.starts_with(&format!("| {method} |")))
            .unwrap_or_else(|| panic!("no row for {method}: {out}"));
        // Every exact method answers the exact traversal's hits: 0 differ (last column).
        let differ = row.trim_end_matches(" |").rsplit(' ').next().unwrap();
        assert_eq!(differ, "0", "{row}");
    }
    let choice = out
        .lines()
        .find_map(|l| l.strip_prefix("choice: "))
        .unwrap_or_else(|| panic!("no choice: {out}"));
    let chosen = choice.split(' ').next().unwrap();
    assert!(out.contains("bake plan: "), "{out}");

    let args = [&["render", "--method", "auto"][..], &size].concat();
    let (ok, out, err) = hfcast(&dir, &args);
    assert!(ok, "{err}");
    assert!(err.contains("choice: "), "{err}");
    assert!(out.contains("Mrays/s"), "{out}");
    // The choice is noisy between runs (timings), but always an exact method.
    let used = err
        .lines()
        .find_map(|l| l.strip_prefix("render 48 x 36, method "))
        .and_then(|l| l.split(',').next())
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        ["exact", "maxmip", "safety", "cc", "radius"].contains(&used),
        "{used}"
    );
    assert!(["exact", "maxmip", "safety", "cc", "radius"].contains(&chosen));
}
