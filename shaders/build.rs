//! Embeds every file of `glsl/` and `wgsl/` (whichever exist) as `include_str!`
//! tables, so that the crate builds while a port is still being written.

use std::fmt::Write as _;
use std::path::Path;

fn table(dir: &Path, ext: &str) -> String {
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(ext))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    let mut s = String::from("&[\n");
    for n in &names {
        let path = dir.join(n);
        println!("cargo:rerun-if-changed={}", path.display());
        let stem = &n[..n.len() - ext.len()];
        writeln!(
            s,
            "    ({stem:?}, include_str!({:?})),",
            path.display().to_string()
        )
        .unwrap();
    }
    s.push(']');
    s
}

fn main() {
    // The manifest directory of this build, not the one the build script was compiled
    // in (a target directory copied from another checkout keeps the script).
    let root = std::env::var("CARGO_MANIFEST_DIR").unwrap();
    let root = Path::new(&root);
    let out = Path::new(&std::env::var("OUT_DIR").unwrap()).join("files.rs");
    let text = format!(
        "/// `(stem, text)` of every file of `shaders/glsl`, sorted by name.\n\
         pub(crate) static GLSL_FILES: &[(&str, &str)] = {};\n\
         /// `(stem, text)` of every file of `shaders/wgsl`, sorted by name.\n\
         pub(crate) static WGSL_FILES: &[(&str, &str)] = {};\n",
        table(&root.join("glsl"), ".glsl"),
        table(&root.join("wgsl"), ".wgsl"),
    );
    std::fs::write(out, text).unwrap();
}
