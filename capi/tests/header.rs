//! The drift checks of what the C API generates: `include/hfcast.h` (cbindgen, pinned
//! 0.29.4, plus the declarations that mirror the core's registry: the `hf_method`,
//! `hf_surface` and `hf_impostor_combine` enums and the `HF_KTX2_*` map kinds) and
//! `src/features.rs` (which of the registry's method features this build has). Each
//! fails when the committed file differs; `HFCAST_BLESS=1` writes them. Also checks the headers of smaller builds
//! (`examples/header.rs`).

use std::path::PathBuf;

#[path = "../examples/header.rs"]
#[allow(dead_code)]
mod header_example;

use hfcore::impostor::Combine;
use hfcore::ktx2::MapKind;
use hfcore::scene::{MethodKind, FEATURES};
use hfcore::Surface;

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
        config
            .defines
            .insert(format!("feature = {}", f.name), f.have_macro.to_string());
    }
    after.push('\n');
    after.push_str(registry_declarations().trim_end());
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_crate(&crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen")
        .write(&mut out);
    String::from_utf8(out).expect("utf-8 header")
}

/// Compares the committed file `path` (from the crate's directory) with `fresh`, or
/// writes it under `HFCAST_BLESS=1` (the workspace's one bless-or-compare,
/// `hfcast_shaders::check_generated`).
fn check_generated(path: &str, fresh: &str) {
    let full = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path);
    hfcast_shaders::check_generated(
        &full,
        fresh,
        &format!("{path} is out of date"),
        "HFCAST_BLESS=1 cargo test -p hfcast-capi --test header",
    );
}

#[test]
fn header_matches_the_source() {
    check_generated("src/features.rs", &features_source());
    check_generated("../include/hfcast.h", &generate());
}

/// The first lines of a generated Rust source: what it mirrors and how to regenerate it.
fn generated_by(what: &str) -> String {
    format!(
        "//! {what}\n//!\n//! Generated from the core's registry by `capi/tests/header.rs`: edit the \
         registry\n//! and run `HFCAST_BLESS=1 cargo test -p hfcast-capi --test header`; the \
         test fails\n//! when this file is out of date.\n"
    )
}

/// `doc` (a doc comment's lines) rewrapped as `//` comments of at most 88 columns,
/// indented by `indent`.
fn doc_lines(doc: &str, indent: &str) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in doc.split_whitespace() {
        if !line.is_empty() && indent.len() + 3 + line.len() + 1 + word.len() > 88 {
            out += &format!("{indent}// {line}\n");
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line += word;
    }
    out + &format!("{indent}// {line}\n")
}

/// `s` with its first letter in lower case.
fn lower_first(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or(String::new(), |f| f.to_lowercase().chain(c).collect())
}

/// `name` in C: upper case, `-` as `_`.
fn c_name(prefix: &str, name: &str) -> String {
    format!("{prefix}{}", name.to_uppercase().replace('-', "_"))
}

/// A C enum of `uint32_t` values `(doc, name, value)`, declared as cbindgen declares
/// the crate's own (a fixed underlying type where C23 or C++ allow it, else the
/// `uint32_t` typedef).
fn c_enum(doc: &str, name: &str, variants: &[(&str, String, u32)]) -> String {
    const FIXED: &str = "defined(__cplusplus) || __STDC_VERSION__ >= 202311L";
    let mut s = format!(
        "\n{}enum {name}\n#if {FIXED}\n  : uint32_t\n#endif // {FIXED}\n {{\n",
        doc_lines(doc, "")
    );
    for (doc, v, value) in variants {
        s += &format!("{}  {v} = {value},\n", doc_lines(doc, "  "));
    }
    s + &format!(
        "}};\n#ifndef __cplusplus\n#if __STDC_VERSION__ >= 202311L\ntypedef enum {name} {name};\n\
         #else\ntypedef uint32_t {name};\n#endif // __STDC_VERSION__ >= 202311L\n#endif // __cplusplus\n"
    )
}

/// The header's declarations that mirror the core's registry: the `hf_method`,
/// `hf_surface` and `hf_impostor_combine` enums (`MethodKind`, `Surface`, `Combine`:
/// their numbers, names and doc comments) and the `HF_KTX2_*` map kinds (`MapKind`).
fn registry_declarations() -> String {
    let methods: Vec<_> = MethodKind::ALL
        .iter()
        .map(|m| (m.doc(), c_name("HF_METHOD_", m.name()), *m as u32))
        .collect();
    let mut s = c_enum(
        "The marching methods (the core's registry). Passed as `uint32_t`.",
        "hf_method",
        &methods,
    );
    let surfaces: Vec<_> = Surface::ALL
        .iter()
        .map(|m| (m.doc(), c_name("HF_SURFACE_", m.name()), *m as u32))
        .collect();
    s += &c_enum(
        "Height reconstruction between samples (docs/DESIGN.md, \"Surfaces\"). Passed as \
         `uint32_t`.",
        "hf_surface",
        &surfaces,
    );
    let combines: Vec<_> = Combine::ALL
        .iter()
        .map(|c| (c.doc(), c_name("HF_IMPOSTOR_", c.name()), *c as u32))
        .collect();
    s += &c_enum(
        "How `hf_impostor_trace_batch` makes the object of the six fields (the core's \
         `impostor::Combine`). Passed as `uint32_t`.",
        "hf_impostor_combine",
        &combines,
    );
    for m in MapKind::ALL {
        let baked_by = MethodKind::ALL
            .into_iter()
            .find(|k| k.info().map == Some(m))
            .map_or(String::new(), |k| {
                format!(" (`hf_bake` of `{}`)", c_name("HF_METHOD_", k.name()))
            });
        let doc = format!(
            "Map kind (`hf_ktx2_desc::map`): {}{baked_by}, `{}` (docs/DESIGN.md, \
             \"Texture layouts\").",
            lower_first(m.doc().trim().trim_end_matches('.')),
            m.format().name(),
        );
        s += &format!(
            "\n{}#define {} {}\n",
            doc_lines(&doc, ""),
            c_name("HF_KTX2_", m.name()),
            m as u32
        );
    }
    s
}

/// `src/features.rs`: whether each of the registry's method features is on in this
/// build of the C API.
fn features_source() -> String {
    let mut s = generated_by(
        "Which of the registry's cargo features (`hfcast::scene::FEATURES`) this build of\n//! \
         the C API has on. Its own list, since the C API may leave out the exports of a\n//! \
         feature the core turns on for another (a cone build bakes through the core's\n//! \
         maxmip module but exports no maxmip function). Shared with `examples/header.rs`.",
    );
    s += "\n/// Whether the C API's feature `name` is on; `None` for a name that is not a\n\
          /// method feature.\npub fn feature_on(name: &str) -> Option<bool> {\n    Some(match name {\n";
    for f in FEATURES {
        s += &format!("        \"{0}\" => cfg!(feature = \"{0}\"),\n", f.name);
    }
    s + "        _ => return None,\n    })\n}\n"
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
/// API's forwarding each to the core (cbindgen's defines and `src/features.rs` are
/// generated from it).
#[test]
fn feature_lists_match_the_registry() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(dir.join(p)).expect(p);
    let (capi, core) = (read("Cargo.toml"), read("../core/Cargo.toml"));
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
            // The C API's turns on the core's (and the shader crate's of the same
            // name, where it has one: the GPU bakes' host side), and may leave out
            // exports of what the core's needs (a cone build does not export the
            // maxmip functions).
            let core = format!("hfcore/{}", f.name);
            let shaders = format!("hfcast-shaders/{}", f.name);
            assert!(
                deps.contains(&core),
                "capi: feature {} lacks {core}",
                f.name
            );
            let other = deps
                .iter()
                .find(|d| **d != core && **d != shaders && !needs.contains(d));
            assert_eq!(other, None, "capi: feature {}", f.name);
        }
    }
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
