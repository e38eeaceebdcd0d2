//! `hfcast shader`: the generated shader of a scene described by options.

use std::path::Path;
use std::process::Command;

fn hfcast(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn shader_prints_a_minimal_shader_and_writes_files() {
    let (ok, glsl, err) = hfcast(&[
        "shader",
        "--method",
        "cc",
        "--surface",
        "triangles",
        "--lang",
        "glsl",
        "--no-shadows",
        "--rays",
        "x+,y-",
        "--outside-only",
        "--max-view-angle",
        "80",
    ]);
    assert!(ok, "{err}");
    assert!(
        glsl.contains("Scene: method cc, surface triangles, rays x+,y-"),
        "{glsl}"
    );
    assert!(glsl.contains("Trace hf_trace(Query q)"));
    assert!(!glsl.contains("uniform uint hf_surface") && !glsl.contains("hf_pyramid"));

    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("shader_cli");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cc.wgsl");
    let (ok, _, err) = hfcast(&[
        "shader",
        "--method",
        "cc",
        "--lang",
        "wgsl",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let wgsl = std::fs::read_to_string(&file).unwrap();
    assert!(wgsl.contains("fn hf_trace(q: Query) -> Trace"), "{wgsl}");

    let (ok, all, err) = hfcast(&["shader", "--all-methods"]);
    assert!(ok, "{err}");
    assert!(all.contains("uniform uint hf_method;") && all.contains("hf_trace_cc(q)"));
    assert!(all.lines().count() > 2 * glsl.lines().count());
}

#[test]
fn shader_rejects_what_no_port_does() {
    let (ok, _, err) = hfcast(&["shader", "--method", "safety", "--surface", "bilinear"]);
    assert!(!ok && err.contains("triangle surface only"), "{err}");
    let (ok, _, err) = hfcast(&["shader", "--method", "maxmip", "--lod"]);
    assert!(!ok && err.contains("LOD"), "{err}");
    let (ok, _, err) = hfcast(&["shader", "--lang", "hlsl"]);
    assert!(!ok && err.contains("--lang"), "{err}");
    let (ok, _, err) = hfcast(&["shader", "--rays", "z+"]);
    assert!(!ok && err.contains("--rays"), "{err}");
}
