//! `hfcast impostor` (issue 22): meshes read from OBJ and PLY agree, bad meshes are
//! clear errors, a capture directory reads back as written, and the CPU render agrees
//! with the mesh itself (Möller–Trumbore) on nearly every pixel.

use hfcast::impostor::{Combine, Frustum, Mesh};
use hfcast_tools::impostor::{capture, load_mesh, render, world_ray, Capture, Orbit, TOWER};
use std::path::{Path, PathBuf};

fn bunny_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mesh_stanford_bunny.obj")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hfcast-impostor-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn obj_and_ply_give_the_same_mesh() {
    let obj = load_mesh(&bunny_path()).unwrap();
    assert_eq!((obj.positions.len(), obj.triangles.len()), (1839, 3674));
    // The same mesh as an ASCII PLY with quads split back by the reader's fan.
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        obj.positions.len(),
        obj.triangles.len()
    );
    for p in &obj.positions {
        ply += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    for t in &obj.triangles {
        ply += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    let path = scratch("ply").join("bunny.ply");
    std::fs::write(&path, ply).unwrap();
    let from_ply = load_mesh(&path).unwrap();
    assert_eq!(from_ply.positions, obj.positions);
    assert_eq!(from_ply.triangles, obj.triangles);
    // A quad is fanned into two triangles; colours are read.
    let quad = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 255 255 255\n4 0 1 2 3\n";
    let path = scratch("quad").join("quad.ply");
    std::fs::write(&path, quad).unwrap();
    let q = load_mesh(&path).unwrap();
    assert_eq!(q.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(q.colours.unwrap()[1], [0.0, 1.0, 0.0]);
}

#[test]
fn bad_meshes_are_clear_errors() {
    let dir = scratch("bad");
    let cases = [
        ("empty.obj", "", "no triangles"),
        ("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "NaN"),
        ("points.obj", "v 0 0 0\nv 1 0 0\n", "no triangles"),
        ("mesh.txt", "v 0 0 0\n", "want .obj or .ply"),
        ("bad.ply", "ply\nformat ascii 1.0\nend_header\ngarbage", ""),
        ("missing.obj", "", ""),
    ];
    for (name, text, want) in cases {
        let path = dir.join(name);
        if name != "missing.obj" {
            std::fs::write(&path, text).unwrap();
        }
        let err = load_mesh(&path)
            .and_then(|m| capture(&m, Frustum::DEFAULT_REVERSE, 16, 16).map(|_| ()))
            .err()
            .unwrap_or_else(|| panic!("{name} accepted"));
        assert!(err.contains(want), "{name}: {err}");
        println!("{name}: {err}");
    }
}

#[test]
fn a_capture_reads_back_as_written() {
    let mesh = load_mesh(Path::new(TOWER)).unwrap();
    let cap = capture(&mesh, Frustum::DEFAULT_REVERSE, 48, 64).unwrap();
    let dir = scratch("roundtrip");
    cap.write(&dir).unwrap();
    let back = Capture::read(&dir).unwrap();
    assert_eq!(back.layout, cap.layout);
    assert_eq!(back.heights, cap.heights);
    assert_eq!(back.colour, cap.colour);
    for (a, b) in back
        .normal
        .iter()
        .flatten()
        .zip(cap.normal.iter().flatten())
    {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= 1.0 / 127.0, "{a:?} {b:?}");
        }
    }
    // A truncated field is an error that names the file.
    let f = dir.join("heights-py.f32");
    let bytes = std::fs::read(&f).unwrap();
    std::fs::write(&f, &bytes[..bytes.len() - 4]).unwrap();
    let err = Capture::read(&dir).err().unwrap();
    assert!(err.contains("heights-py.f32"), "{err}");
}

/// The CPU render's hit pixels against the mesh's own first hits: at most 1 % of the
/// pixels differ, and the hits' depths are within 2 % of the cube's side on average.
#[test]
fn the_render_matches_the_mesh() {
    let data = load_mesh(&bunny_path()).unwrap();
    let mesh = Mesh::new(&data.positions, &data.triangles).unwrap();
    let cap = capture(&data, Frustum::Orthographic, 128, 128).unwrap();
    let orbit = Orbit::default();
    let (w, h) = (96, 96);
    let r = render(&cap, Combine::Intersection, orbit, w, h).unwrap();
    let (mut wrong, mut both, mut err) = (0, 0, 0.0);
    let cam = orbit.pinhole(&cap.layout, w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            let (eye, dir) = world_ray(&cam.ray(x, y, f32::INFINITY).unwrap());
            let len = dir.iter().map(|v| v * v).sum::<f64>().sqrt();
            let truth = mesh
                .first_hit(eye, dir, 0.0, f64::INFINITY)
                .map(|(t, _)| t * len);
            let got = r.depth[(y * w + x) as usize];
            match (truth, got.is_finite()) {
                (Some(t), true) => {
                    both += 1;
                    err += (t - got).abs() / (2.0 * cap.layout.half());
                }
                (None, false) => {}
                _ => wrong += 1,
            }
        }
    }
    let mean = err / f64::from(both);
    println!(
        "{wrong} of {} pixels differ, mean depth error {mean:.5} sides",
        w * h
    );
    assert!(both > 1000);
    assert!(wrong * 100 <= w * h, "{wrong}");
    assert!(mean < 0.02, "{mean}");
}

/// The command line: capture and render succeed and say what they did; an empty
/// capture directory, a bad side and a bad mesh are errors that say why.
#[test]
fn the_command_line_captures_and_renders() {
    let bin = env!("CARGO_BIN_EXE_hfcast");
    let dir = scratch("cli");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(bin).args(args).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        (out.status.success(), text)
    };
    let cap = dir.join("cap");
    let png = dir.join("tower.png");
    let (ok, text) = run(&[
        "impostor",
        "capture",
        "tower",
        "--side",
        "32",
        "--out",
        cap.to_str().unwrap(),
    ]);
    assert!(ok && text.contains("wrote"), "{text}");
    let (ok, text) = run(&[
        "impostor",
        "render",
        cap.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(ok && text.contains("pixels hit"), "{text}");
    assert!(png.exists());
    let obj = dir.join("tower.obj");
    let (ok, text) = run(&[
        "impostor",
        "export",
        "tower",
        "--out",
        obj.to_str().unwrap(),
    ]);
    assert!(ok, "{text}");
    let back = load_mesh(&obj).unwrap();
    let tower = load_mesh(Path::new(TOWER)).unwrap();
    // The same triangles (the reader may renumber the vertices).
    let corners = |m: &hfcast_tools::impostor::MeshData| -> Vec<[[f32; 3]; 3]> {
        m.triangles
            .iter()
            .map(|t| t.map(|i| m.positions[i as usize]))
            .collect()
    };
    assert!(
        corners(&back) == corners(&tower),
        "the exported tower differs"
    );
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (ok, text) = run(&["impostor", "render", empty.to_str().unwrap()]);
    assert!(!ok && text.contains("impostor.json"), "{text}");
    let (ok, text) = run(&[
        "impostor",
        "capture",
        "tower",
        "--side",
        "1",
        "--out",
        cap.to_str().unwrap(),
    ]);
    assert!(!ok && text.contains("--side"), "{text}");
    let (ok, text) = run(&[
        "impostor",
        "capture",
        "no-such.obj",
        "--out",
        cap.to_str().unwrap(),
    ]);
    assert!(!ok && text.contains("no-such.obj"), "{text}");
}
