//! The header drift check: regenerates `include/hfcast.h` with cbindgen (pinned
//! 0.29.4) and fails when the committed header differs. `HFCAST_BLESS=1` writes it.

use std::path::PathBuf;

/// The generated header text: cbindgen's output for this crate, with the version
/// macros of Cargo.toml.
fn generate() -> String {
    let crate_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut config =
        cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("read cbindgen.toml");
    config.after_includes = Some(format!(
        "\n/* Version of the header; hf_version() returns the library's. */\n\
         #define HFCAST_VERSION_MAJOR {}\n#define HFCAST_VERSION_MINOR {}\n\
         #define HFCAST_VERSION_PATCH {}\n#define HFCAST_VERSION_STRING \"{}\"",
        env!("CARGO_PKG_VERSION_MAJOR"),
        env!("CARGO_PKG_VERSION_MINOR"),
        env!("CARGO_PKG_VERSION_PATCH"),
        env!("CARGO_PKG_VERSION"),
    ));
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_crate(&crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen")
        .write(&mut out);
    String::from_utf8(out).expect("utf-8 header")
}

#[test]
fn header_matches_the_source() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../include/hfcast.h");
    let fresh = generate();
    if std::env::var_os("HFCAST_BLESS").is_some() {
        std::fs::write(&path, &fresh).expect("write include/hfcast.h");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "include/hfcast.h is out of date: regenerate it with \
         `HFCAST_BLESS=1 cargo test -p hfcast-capi --test header` and commit it"
    );
}

#[test]
fn version_macros_match_cargo_toml() {
    let header = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../include/hfcast.h"),
    )
    .expect("read include/hfcast.h");
    let manifest =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../Cargo.toml"))
            .expect("read Cargo.toml");
    // The workspace version, read from the file itself rather than from cargo.
    let version = manifest
        .lines()
        .skip_while(|l| l.trim() != "[workspace.package]")
        .find_map(|l| l.trim().strip_prefix("version = "))
        .expect("workspace version")
        .trim_matches('"')
        .to_string();
    let parts: Vec<&str> = version.split('.').collect();
    for (name, value) in [
        ("HFCAST_VERSION_MAJOR", parts[0].to_string()),
        ("HFCAST_VERSION_MINOR", parts[1].to_string()),
        ("HFCAST_VERSION_PATCH", parts[2].to_string()),
        ("HFCAST_VERSION_STRING", format!("\"{version}\"")),
    ] {
        let line = format!("#define {name} {value}");
        assert!(header.contains(&line), "header lacks `{line}`");
    }
}
