//! The `hfcast` binary from a user's point of view: `render` with no arguments, and
//! `trace` on stdin.

mod common;

use hfcast_tools::maps::load_map;
use std::path::Path;

fn hfcast(dir: &Path, args: &[&str], stdin: &str) -> (bool, String) {
    let run = common::run_hfcast(Some(dir), args, stdin);
    assert!(run.fed, "hfcast closed its input before reading it");
    // Shown by the test harness only when the test fails.
    eprint!("{}", run.stderr);
    (run.ok, run.stdout)
}

#[test]
fn render_with_no_arguments_writes_a_picture() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render_no_args");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, out) = hfcast(&dir, &["render"], "");
    assert!(ok, "{out}");
    assert!(out.contains("Mrays/s"), "{out}");
    // At least a quarter of the pixels differ from the first (the sky).
    let file = std::fs::File::open(dir.join("out/render.png")).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let pixels: Vec<&[u8]> = buf.chunks(3).collect();
    let distinct = pixels.iter().filter(|p| **p != pixels[0]).count();
    assert!(distinct > pixels.len() / 4, "picture nearly uniform");
}

#[test]
fn trace_answers_every_line_and_flags_errors() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let rays = "# a comment\n\n200 170 500 0 0 -1\n0 0 0 0 0 0\n-10 -10 -10 -1 0 0 0 5\n";
    let (ok, out) = hfcast(dir, &["trace"], rays);
    assert!(!ok, "an error line must make the exit status non-zero");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].starts_with("hit "), "{out}");
    assert!(lines[1].starts_with("error "), "{out}");
    assert_eq!(lines[2], "miss 0");
    // The hit lies on the bundled map's surface, straight under the origin.
    let map = load_map(hfcast_tools::maps::bundled_map(), None).unwrap();
    let z: f32 = lines[0].split(' ').nth(4).unwrap().parse().unwrap();
    assert!((z - map.field().at(200, 170)).abs() < 1e-4, "{out}");

    let (ok, out) = hfcast(dir, &["trace", "200", "170", "500", "0", "0", "-1"], "");
    assert!(ok && out.starts_with("hit "), "{out}");
}
