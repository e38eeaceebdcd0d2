//! The header drift check: regenerates `include/hfcast.h` with cbindgen (pinned
//! 0.29.4) and fails when the committed header differs. `HFCAST_BLESS=1` writes it.
//! Also checks the headers of smaller builds (`examples/header.rs`).

use std::path::PathBuf;

#[path = "../examples/header.rs"]
#[allow(dead_code)]
mod header_example;

use hfcore::scene::FEATURES;

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
    let after = config.after_includes.get_or_insert_with(String::new);
    after.push_str(
        "\n\n/* The methods this build of the library has (cargo features of hfcast-capi; see\n   \
         hf_build_has_method). The declarations of each are inside\n   \
         #if defined(HF_HAVE_<METHOD>); the header of a build with fewer methods, printed by\n   \
         `cargo run -p hfcast-capi --no-default-features --features <methods> --example\n   \
         header`, defines fewer and has the others' declarations removed. */",
    );
    for f in FEATURES {
        after.push_str(&format!("\n#define {} 1", f.have_macro));
    }
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

/// The `[features]` table of a `Cargo.toml`: each feature's line, `name = [...]`.
fn features_of(manifest: &str) -> Vec<(String, Vec<String>)> {
    let table = manifest
        .lines()
        .skip_while(|l| l.trim() != "[features]")
        .skip(1);
    let lines = table.take_while(|l| !l.trim_start().starts_with('['));
    lines
        .filter_map(|l| {
            let (name, list) = l.split_once(" = ")?;
            let items = list.trim_matches(|c| c == '[' || c == ']').split(',');
            let items = items.map(|i| i.trim().trim_matches('"').to_string());
            Some((
                name.trim().to_string(),
                items.filter(|i| !i.is_empty()).collect(),
            ))
        })
        .collect()
}

/// The registry's feature list (`hfcore::scene::FEATURES`) is the one list: both
/// `Cargo.toml`s declare exactly those features (plus `all-methods` turning them all
/// on, and the core's `alloc` and `std`) with the registry's dependencies, the C
/// API's forwarding each to the core, and `cbindgen.toml` defines the registry's macro
/// for each.
#[test]
fn feature_lists_match_the_registry() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(dir.join(p)).expect(p);
    let (toml, capi, core) = (
        read("cbindgen.toml"),
        read("Cargo.toml"),
        read("../core/Cargo.toml"),
    );
    let names: Vec<String> = FEATURES.iter().map(|f| f.name.to_string()).collect();
    for (manifest, who, extra) in [(&core, "core", &["alloc", "std"][..]), (&capi, "capi", &[])] {
        let table = features_of(manifest);
        let find = |n: &str| table.iter().find(|(k, _)| k == n).map(|(_, v)| v.clone());
        assert_eq!(
            find("all-methods"),
            Some(names.clone()),
            "{who}: all-methods"
        );
        let declared: Vec<&String> = table.iter().map(|(k, _)| k).collect();
        let mut want: Vec<String> = ["default", "all-methods"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        want.extend(names.iter().cloned());
        want.extend(extra.iter().map(|s| s.to_string()));
        let mut got: Vec<String> = declared.into_iter().cloned().collect();
        got.sort();
        want.sort();
        assert_eq!(got, want, "{who}: the features declared");
        for f in FEATURES {
            let deps = find(f.name).unwrap_or_default();
            let needs: Vec<String> = f.needs.iter().map(|s| s.to_string()).collect();
            if who == "core" {
                assert_eq!(deps, needs, "core: feature {}", f.name);
                continue;
            }
            // The C API's turns on the core's, and may leave out exports of what the
            // core's needs (a cone build does not export the maxmip functions).
            let core = format!("hfcore/{}", f.name);
            assert!(
                deps.contains(&core),
                "capi: feature {} lacks {core}",
                f.name
            );
            let other = deps.iter().find(|d| **d != core && !needs.contains(d));
            assert_eq!(other, None, "capi: feature {}", f.name);
        }
    }
    for f in FEATURES {
        let on = header_example::features::feature_on(f.name);
        assert!(
            on.is_some(),
            "capi/src/features.rs does not know {}",
            f.name
        );
        let line = format!("\"feature = {}\" = \"{}\"", f.name, f.have_macro);
        assert!(toml.contains(&line), "cbindgen.toml lacks `{line}`");
    }
    let defines = toml
        .lines()
        .filter(|l| l.starts_with("\"feature = "))
        .count();
    assert_eq!(
        defines,
        FEATURES.len(),
        "cbindgen.toml defines other features"
    );
}

#[test]
fn smaller_builds_declare_only_their_methods() {
    use header_example::strip;
    let full = generate();
    let all: Vec<&str> = FEATURES.iter().map(|f| f.have_macro).collect();
    assert_eq!(
        strip(&full, &all),
        full,
        "every feature on: the full header"
    );
    // The header of this very build.
    let this = strip(&full, &header_example::this_build());
    assert_eq!(
        this.matches("#define HF_HAVE_").count(),
        header_example::this_build().len()
    );
    let cone = strip(&full, &["HF_HAVE_CONE"]);
    // Declarations only: the documentation of what stays may name what is gone.
    let code = |h: &str| -> String {
        h.lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let cone_code = code(&cone);
    for gone in [
        "hf_maxmip_levels(",
        "hf_maxmip_update_rect(",
        "HF_SAFETY_DIRECTIONAL",
        "HF_CC_SLOPE_EXACT",
        "HF_RADIUS_WALK",
        "HF_HAVE_SAFETY",
        "HF_MAX_LEVELS",
    ] {
        assert!(
            !cone_code.contains(gone),
            "the cone build's header declares {gone}"
        );
    }
    for kept in [
        "hf_bake(",
        "hf_map_len(",
        "hf_bake_rows(",
        "hf_trace(",
        "hf_trace_batch(",
        "hf_trace_options_default(",
        "hf_method_name(",
        "hf_build_has_method(",
        "hf_scene_bake_plan(",
        "#define HF_HAVE_CONE 1",
    ] {
        assert!(cone.contains(kept), "the cone build's header lacks {kept}");
    }
    let none = strip(&full, &[]);
    assert!(!none.contains("HF_HAVE_CONE") && none.contains("hf_trace("));
    for h in [&cone, &none] {
        let opens = h.lines().filter(|l| l.starts_with("#if")).count();
        let closes = h.lines().filter(|l| l.starts_with("#endif")).count();
        assert_eq!(opens, closes);
        assert!(!h.contains("\n\n\n"), "no runs of blank lines");
    }
}
