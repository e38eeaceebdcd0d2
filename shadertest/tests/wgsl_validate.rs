//! Every WGSL march (`shaders/wgsl`, composed per method by `hfcast-shaders`: the
//! general source, and the shader generated for 16-bit heights) parses and validates
//! with naga under every validation flag and no optional capability (the WebGPU
//! baseline), alone and with the parity test's entry point; every file takes part in a
//! method that validates; the textual conventions the shader generator relies on hold
//! and the bindings are those of `hfcast_shaders::wgsl_layout`; and the `//#`
//! directive lines and the functions of each GLSL file are mirrored in its WGSL port.

mod common;

use common::{general_source, int_heights_source, WRAPPER};
use hfcast::scene::MethodKind;
use hfcast_shaders::{file, parts, wgsl_layout, Lang};
use naga::valid::{Capabilities, ValidationFlags, Validator};

/// The capabilities the marches may use: none beyond the WebGPU baseline.
const CAPABILITIES: Capabilities = Capabilities::empty();

/// The GPU bakes may also use 64-bit floats (the safety-distance bake: the core's exact
/// predicates are `f64`).
const BAKE_CAPABILITIES: Capabilities = Capabilities::FLOAT64;

/// Parses and validates `src`; the error is naga's report with source excerpts.
fn validate(label: &str, src: &str) -> Result<naga::Module, String> {
    validate_with(label, src, CAPABILITIES)
}

/// [`validate`] with `capabilities`.
fn validate_with(
    label: &str,
    src: &str,
    capabilities: Capabilities,
) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(src)
        .map_err(|e| format!("{label}: parse error\n{}", e.emit_to_string(src)))?;
    Validator::new(ValidationFlags::all(), capabilities)
        .validate(&module)
        .map_err(|e| format!("{label}: validation error\n{}", e.emit_to_string(src)))?;
    Ok(module)
}

/// The stems of the files in `shaders/<lang>`, sorted.
fn stems(lang: Lang) -> Vec<String> {
    let ext = lang.ext();
    let dir = format!("{}/../shaders/{ext}", env!("CARGO_MANIFEST_DIR"));
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{dir}: {e}"));
    let mut stems: Vec<String> = entries
        .filter_map(|e| {
            let name = e.expect("entry").file_name().to_string_lossy().into_owned();
            name.strip_suffix(&format!(".{ext}")).map(String::from)
        })
        .collect();
    stems.sort();
    stems
}

/// `(file name, text)` of every file of `shaders/wgsl`, the text as hfcast-shaders
/// compiled it in.
fn wgsl_files() -> Vec<(String, &'static str)> {
    stems(Lang::Wgsl)
        .into_iter()
        .map(|stem| {
            let text = file(Lang::Wgsl, &stem)
                .unwrap_or_else(|| panic!("{stem}.wgsl is not compiled into hfcast-shaders"));
            (format!("{stem}.wgsl"), text)
        })
        .collect()
}

/// [`wgsl_files`] that have a GLSL port: all of them (the GPU bakes too).
fn ported_wgsl_files() -> Vec<(String, &'static str)> {
    wgsl_files()
}

/// The compiled-in GLSL file that `name` (`x.wgsl`) ports.
fn glsl_of(name: &str) -> &'static str {
    let stem = name.trim_end_matches(".wgsl");
    file(Lang::Glsl, stem).unwrap_or_else(|| panic!("{name} ports no {stem}.glsl"))
}

#[test]
fn every_glsl_file_has_a_wgsl_port() {
    for stem in stems(Lang::Glsl) {
        assert!(
            file(Lang::Wgsl, &stem).is_some(),
            "{stem}.glsl has no port {stem}.wgsl"
        );
    }
}

#[test]
fn every_method_has_one_hf_trace_and_no_markers() {
    for m in MethodKind::ALL {
        let s = general_source(m);
        let traces = s.matches("fn hf_trace(q: Query) -> Trace").count();
        assert_eq!(traces, 1, "{}: {traces} definitions of hf_trace", m.name());
        assert!(!s.contains("//#"), "{}: markers left", m.name());
        let int = int_heights_source(m);
        assert!(
            int.contains("var hf_heights: texture_2d<u32>;"),
            "{}",
            m.name()
        );
        assert!(
            !int.contains("var hf_heights: texture_2d<f32>;"),
            "{}",
            m.name()
        );
    }
}

#[test]
fn every_method_parses_and_validates() {
    let mut errors = Vec::new();
    for m in MethodKind::ALL {
        let (general, int) = (general_source(m), int_heights_source(m));
        for (label, src) in [
            (m.name().to_string(), general.clone()),
            (
                format!("{} + test entry point", m.name()),
                general + WRAPPER,
            ),
            (format!("{} 16-bit heights", m.name()), int.clone()),
            (
                format!("{} 16-bit heights + test entry point", m.name()),
                int + WRAPPER,
            ),
        ] {
            match validate(&label, &src) {
                Ok(module) => {
                    let hf_trace = module
                        .functions
                        .iter()
                        .any(|(_, f)| f.name.as_deref() == Some("hf_trace"));
                    assert!(hf_trace, "{label}: no hf_trace");
                    println!("{label}: ok ({} functions)", module.functions.len());
                }
                Err(e) => errors.push(e),
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn every_file_validates_as_part_of_its_methods() {
    for (name, text) in wgsl_files() {
        // A GPU bake is a compute shader of its own.
        if hfcast_shaders::translate::is_gpu_bake(name.trim_end_matches(".wgsl")) {
            if let Err(e) = validate_with(&name, text, BAKE_CAPABILITIES) {
                panic!("{name} fails:\n{e}");
            }
            println!("{name:<28} validates alone (a GPU bake)");
            continue;
        }
        // impostor.wgsl takes part in the impostor shaders (the exact method's files).
        if name == "impostor.wgsl" {
            for depth_output in [false, true] {
                let scene = hfcast::scene::Scene {
                    depth_output,
                    ..hfcast::scene::Scene::general(MethodKind::Exact, hfcast::Surface::Triangles)
                };
                let src = hfcast_shaders::impostor(&scene, Lang::Wgsl).expect("impostor");
                if let Err(e) = validate(&name, &src) {
                    panic!("{name} fails as part of an impostor shader:\n{e}");
                }
            }
            println!("{name:<28} validates in the impostor shaders");
            continue;
        }
        // field_int.wgsl takes part in every method's 16-bit-heights source.
        let int = name == "field_int.wgsl";
        let methods: Vec<MethodKind> = MethodKind::ALL
            .into_iter()
            .filter(|&m| int || parts(m).iter().any(|p| format!("{p}.wgsl") == name))
            .collect();
        assert!(!methods.is_empty(), "{name} is in no method");
        for &m in &methods {
            let src = if int {
                int_heights_source(m)
            } else {
                general_source(m)
            };
            if let Err(e) = validate(m.name(), &src) {
                panic!("{name} fails as part of {}:\n{e}", m.name());
            }
        }
        let names: Vec<&str> = methods.iter().map(|m| m.name()).collect();
        println!("{name:<28} validates in {}", names.join(", "));
    }
}

#[test]
fn overrides_and_bindings_are_one_line_and_fixed() {
    // name -> binding, over all files: a resource has one binding everywhere, and no
    // two resources share one (methods' `hf_params` excepted: one method per source).
    let mut seen: Vec<(String, u32, String)> = Vec::new();
    for (name, text) in wgsl_files() {
        for line in text.lines() {
            let l = line.trim();
            if l.starts_with("override ") {
                let scalar = l.contains(": u32 = ") || l.contains(": f32 = ");
                assert!(
                    l.ends_with(';') && scalar && line == l,
                    "{name}: an override must be one unindented line `override NAME: u32 = V;` \
                     (or f32): {line}"
                );
            }
            if let Some(rest) = l.strip_prefix("@group(") {
                assert!(
                    rest.starts_with("0) @binding("),
                    "{name}: group 0 only: {line}"
                );
                let rest = &rest["0) @binding(".len()..];
                let close = rest.find(')').expect("binding number");
                let b: u32 = rest[..close].parse().expect("literal binding number");
                let var = rest[close + 1..].trim();
                assert!(
                    var.starts_with("var") && var.ends_with(';'),
                    "{name}: one line: {line}"
                );
                let id = var
                    .split(['>', ' '])
                    .find(|w| w.starts_with("hf_"))
                    .expect("an hf_ name")
                    .trim_end_matches(':')
                    .to_string();
                let fixed = match id.as_str() {
                    "hf_heights" => wgsl_layout::HEIGHTS,
                    "hf_field" => wgsl_layout::FIELD,
                    "hf_params" => wgsl_layout::PARAMS,
                    "hf_pyramid" => wgsl_layout::PYRAMID,
                    "hf_maxmip" => wgsl_layout::MAXMIP,
                    "hf_safety_map" => wgsl_layout::SAFETY_MAP,
                    "hf_cone_map" => wgsl_layout::CONE_MAP,
                    "hf_qdm_map" => wgsl_layout::QDM_MAP,
                    "hf_relaxed_map" => wgsl_layout::RELAXED_MAP,
                    "hf_cc_map" => wgsl_layout::CC_MAP,
                    "hf_cc" => wgsl_layout::CC,
                    "hf_radius_map" => wgsl_layout::RADIUS_MAP,
                    "hf_world" => wgsl_layout::WORLD,
                    "hf_pyramid_out" => wgsl_layout::PYRAMID_OUT,
                    "hf_maxmip_pass" => wgsl_layout::MAXMIP_PASS,
                    "hf_nbuffer" => wgsl_layout::NBUFFER,
                    "hf_nbuffer_pass" => wgsl_layout::NBUFFER_PASS,
                    "hf_safety_scratch" => wgsl_layout::SAFETY_SCRATCH,
                    "hf_safety_out" => wgsl_layout::SAFETY_OUT,
                    "hf_safety_pass" => wgsl_layout::SAFETY_PASS,
                    "hf_field_ranges" => wgsl_layout::FIELD_RANGES,
                    "hf_impostor" => wgsl_layout::IMPOSTOR,
                    "hf_view_proj" => wgsl_layout::VIEW_PROJ,
                    "hf_occluders" => wgsl_layout::OCCLUDERS,
                    other => panic!("{name}: {other} is not in hfcast_shaders::wgsl_layout"),
                };
                assert_eq!(b, fixed, "{name}: {id} is not at its wgsl_layout binding");
                for (other, ob, of) in &seen {
                    if *other == id {
                        assert_eq!(*ob, b, "{id} has bindings {ob} ({of}) and {b} ({name})");
                    } else {
                        assert_ne!(*ob, b, "{id} ({name}) and {other} ({of}) share binding {b}");
                    }
                }
                seen.push((id, b, name.clone()));
            }
        }
    }
    println!("{} resource declarations checked", seen.len());
}

#[test]
fn glsl_directive_lines_are_mirrored() {
    let directives = |text: &str| -> Vec<String> {
        text.lines()
            .map(str::trim)
            .filter(|l| l.starts_with("//#"))
            // The WGSL files' language regions are the translation's, not the GLSL's.
            .filter(|l| !["//#wgsl", "//#glsl", "//#end"].contains(l))
            .map(String::from)
            .collect()
    };
    let mut checked = 0;
    for (name, text) in ported_wgsl_files() {
        let glsl_name = name.replace(".wgsl", ".glsl");
        let glsl = glsl_of(&name);
        assert_eq!(
            directives(glsl),
            directives(text),
            "the //# lines of {glsl_name} and {name} differ"
        );
        checked += directives(text).len();
    }
    println!("{checked} directive lines mirrored");
}

/// The functions a file defines at top level: GLSL `type name(...) {` lines (not
/// prototypes, which end in `);`), WGSL `fn name(` lines; but the entry points of the
/// GPU bakes (GLSL `main`, a WGSL `fn` after `@compute`).
fn defined_functions(text: &str, wgsl: bool) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let entry = |k: usize| k > 0 && lines[k - 1].starts_with("@compute");
    let mut names: Vec<String> = lines
        .iter()
        .enumerate()
        .filter(|&(k, l)| {
            !l.starts_with(' ')
                && !l.starts_with("//")
                && !l.trim_end().ends_with(");")
                && !entry(k)
        })
        .filter_map(|(_, l)| {
            let head = if wgsl {
                l.strip_prefix("fn ")?
            } else {
                let (ty, rest) = l.split_once(' ')?;
                if ["return", "uniform", "const", "struct"].contains(&ty) {
                    return None;
                }
                rest
            };
            let name = head.split_once('(')?.0;
            (name != "main" && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
                .then(|| name.to_string())
        })
        .collect();
    names.sort();
    names
}

#[test]
fn every_file_defines_the_functions_of_its_glsl_file() {
    let mut count = 0;
    for (name, text) in ported_wgsl_files() {
        let glsl_name = name.replace(".wgsl", ".glsl");
        let glsl = glsl_of(&name);
        let (g, w) = (
            defined_functions(glsl, false),
            defined_functions(text, true),
        );
        assert_eq!(g, w, "{glsl_name} and {name} define different functions");
        count += w.len();
    }
    println!("{count} functions defined under the same names in GLSL and WGSL");
}
