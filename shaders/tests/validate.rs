//! Every shader the generator can make, compiled: GLSL with glslangValidator (CI
//! installs glslang-tools; the test fails without it), WGSL with naga
//! (`ValidationFlags::all()`); and properties of the generated text.

use hfcast::scene::{HeightFormat, MethodKind, RayClasses, Scene, Shadows};
use hfcast::Surface;
use hfcast_shaders::{
    all_methods, general, generate, generate_with, impostor, parts, supports, GenError, Lang,
    Options, SafetyVariant,
};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::Command;

/// Every scene worth a distinct shader, with its options: method × supported surface ×
/// shadows × view angle × height format × safety layout, plus the ray classes (the
/// class-set constants of the safety-shape maps) and choices that change no shader code
/// (outside-only, depth output).
fn scenes() -> Vec<(Scene, Options)> {
    let mut out = Vec::new();
    for method in MethodKind::ALL {
        for surface in Surface::ALL {
            if !supports(method, surface) {
                continue;
            }
            for shadows in Shadows::ALL {
                for angle in [180.0, 80.0] {
                    for heights in [HeightFormat::F32, HeightFormat::U16, HeightFormat::U8] {
                        for variant in [SafetyVariant::Directional, SafetyVariant::Isotropic] {
                            if variant == SafetyVariant::Isotropic && method != MethodKind::Safety {
                                continue;
                            }
                            let scene = Scene {
                                shadows,
                                max_view_angle_deg: angle,
                                heights,
                                outside_only: shadows != Shadows::FromSurface,
                                ray_classes: if shadows.traced() {
                                    RayClasses::ALL
                                } else {
                                    RayClasses(0b0101)
                                },
                                depth_output: shadows.traced(),
                                ..Scene::general(method, surface)
                            };
                            out.push((
                                scene,
                                Options {
                                    safety_variant: variant,
                                },
                            ));
                        }
                    }
                }
            }
        }
    }
    out
}

/// `(label, text)` of every distinct shader of `lang` (shaders that differ only in
/// their header comment count once): generated, general, all-methods.
fn shaders(lang: Lang) -> BTreeMap<String, String> {
    // Code (comments dropped) -> (label, text).
    let mut by_code: BTreeMap<String, (String, String)> = BTreeMap::new();
    let mut generated = 0;
    for (scene, opts) in scenes() {
        let label = format!(
            "{}_{}_{:?}_{}_{:?}_{:?}",
            scene.method.name(),
            scene.surface.name(),
            scene.shadows,
            scene.max_view_angle_deg,
            scene.heights,
            opts.safety_variant
        );
        match generate_with(&scene, lang, &opts) {
            Ok(text) => {
                generated += 1;
                by_code.entry(code(&text)).or_insert((label, text));
            }
            // The WGSL port has no 16/8-bit height file.
            Err(GenError::MissingFile { .. }) if scene.heights != HeightFormat::F32 => {}
            Err(e) => panic!("{label}: {e}"),
        }
    }
    eprintln!(
        "{}: {generated} scenes generated, {} distinct shaders",
        lang.ext(),
        by_code.len()
    );
    for m in MethodKind::ALL {
        let text = general(m, lang).unwrap();
        by_code.insert(code(&text), (format!("general_{}", m.name()), text));
    }
    let text = all_methods(lang).unwrap();
    by_code.insert(code(&text), ("all_methods".into(), text));
    by_code.into_values().collect()
}

fn tmp_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A fragment shader around `src`: the version line and a main that traces one ray in
/// grid space and one in world units.
fn glsl_fragment(src: &str) -> String {
    format!(
        "#version 330 core\n{src}\nout vec4 hf_out;\nvoid main() {{\n    \
         Trace tr = hf_trace(Query(vec3(gl_FragCoord.xy, 100.0), vec3(0.3, 0.2, -1.0), 0.0, 1e30));\n    \
         Trace tw = hf_trace_world(Query(vec3(gl_FragCoord.xy, 100.0), vec3(0.3, 0.2, -1.0), 0.0, 1e30));\n    \
         hf_out = vec4(tr.hit.point + tw.hit.normal, tr.has_hit ? tr.hit.t : -1.0);\n}}\n"
    )
}

#[test]
fn every_generated_glsl_shader_compiles_with_glslang() {
    let dir = tmp_dir("glsl");
    let all = shaders(Lang::Glsl);
    let mut failed = Vec::new();
    for (label, text) in &all {
        let path = dir.join(format!("{label}.frag"));
        std::fs::write(&path, glsl_fragment(text)).unwrap();
        let out = Command::new("glslangValidator")
            .arg(&path)
            .output()
            .expect("glslangValidator must be installed (apt-get install glslang-tools)");
        if !out.status.success() {
            failed.push(format!("{label}: {}", String::from_utf8_lossy(&out.stdout)));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    eprintln!("glslang: {} distinct GLSL shaders compile", all.len());
    assert!(all.len() > 50, "only {} shaders", all.len());
}

/// The GPU bakes' GLSL (whole GLSL 4.30 compute shaders, translated from their WGSL)
/// compile as compute shaders.
#[test]
fn gpu_bakes_compile_as_glsl_compute_shaders() {
    let dir = tmp_dir("glsl_bakes");
    let glsl_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("glsl");
    let mut stems: Vec<String> = std::fs::read_dir(glsl_dir)
        .expect("glsl/")
        .filter_map(|e| {
            Some(
                e.ok()?
                    .file_name()
                    .to_str()?
                    .strip_suffix(".glsl")?
                    .to_string(),
            )
        })
        .filter(|s| hfcast_shaders::translate::is_gpu_bake(s))
        .collect();
    stems.sort();
    for stem in &stems {
        let text = hfcast_shaders::file(Lang::Glsl, stem).unwrap_or_else(|| panic!("{stem}.glsl"));
        let path = dir.join(format!("{stem}.comp"));
        std::fs::write(&path, text).unwrap();
        let out = Command::new("glslangValidator")
            .arg(&path)
            .output()
            .expect("glslangValidator must be installed (apt-get install glslang-tools)");
        assert!(
            out.status.success(),
            "{stem}.glsl: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    assert_eq!(stems, ["bake_maxmip", "bake_nbuffer", "bake_safety"]);
    // The cylinder–cone bake: bake_safety with HF_CC_BAKE defined.
    #[cfg(feature = "safety")]
    {
        let cc = hfcast_shaders::bake::cc_bake_source(Lang::Glsl).expect("the cc bake");
        assert!(cc.contains("#define HF_CC_BAKE"));
        let path = dir.join("bake_cc.comp");
        std::fs::write(&path, cc).unwrap();
        let out = Command::new("glslangValidator")
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "bake_cc: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
}

#[test]
fn every_generated_wgsl_shader_validates_with_naga() {
    if parts(MethodKind::Cc)
        .iter()
        .any(|p| hfcast_shaders::file(Lang::Wgsl, p).is_none())
    {
        panic!("the WGSL port is incomplete");
    }
    let all = shaders(Lang::Wgsl);
    let mut failed = Vec::new();
    for (label, text) in &all {
        // An entry point that calls hf_trace and hf_trace_world, so that everything is
        // validated as used.
        let src = format!(
            "{text}\n@fragment\nfn hf_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {{\n    \
             let tr = hf_trace(Query(vec3<f32>(pos.xy, 100.0), vec3<f32>(0.3, 0.2, -1.0), 0.0, 1e30));\n    \
             let tw = hf_trace_world(Query(vec3<f32>(pos.xy, 100.0), vec3<f32>(0.3, 0.2, -1.0), 0.0, 1e30));\n    \
             return vec4<f32>(tr.hit.point + tw.hit.normal, tr.hit.t);\n}}\n"
        );
        let module = match naga::front::wgsl::parse_str(&src) {
            Ok(m) => m,
            Err(e) => {
                failed.push(format!("{label}: {}", e.emit_to_string(&src)));
                continue;
            }
        };
        let mut v = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        );
        if let Err(e) = v.validate(&module) {
            failed.push(format!("{label}: {}", e.emit_to_string(&src)));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    eprintln!("naga: {} distinct WGSL shaders validate", all.len());
}

/// The general shader with the markers' lines removed by a separate reading: drop the
/// marker lines and the `//#else` branches (the general shader sets every flag).
fn marker_free(method: MethodKind, lang: Lang) -> String {
    let mut s = String::new();
    for stem in parts(method) {
        let text = hfcast_shaders::file(lang, stem).unwrap();
        s.push_str(&format!("// ---- {stem}.{}\n", lang.ext()));
        let mut skipping: Vec<bool> = Vec::new();
        let mut glsl_only = false;
        for line in text.lines() {
            match line.trim() {
                "//#glsl" => glsl_only = true,
                "//#end" => glsl_only = false,
                "//#wgsl" => {}
                _ if glsl_only => {}
                t if t.starts_with("//#if") => skipping.push(false),
                "//#else" => *skipping.last_mut().unwrap() = true,
                "//#endif" => {
                    skipping.pop();
                }
                _ if skipping.iter().any(|s| *s) => {}
                _ => {
                    s.push_str(line);
                    s.push('\n');
                }
            }
        }
    }
    s
}

#[test]
fn general_shaders_are_the_files_without_markers() {
    for lang in Lang::ALL {
        for m in MethodKind::ALL {
            assert!(
                general(m, lang).unwrap() == marker_free(m, lang),
                "{}",
                m.name()
            );
        }
    }
}

/// The lines of `s` that are not comments.
fn code(s: &str) -> String {
    s.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .map(|l| format!("{l}\n"))
        .collect()
}

/// The declaration in `lang` of the `u32` `name`: a constant, or with `input` a GLSL
/// uniform or WGSL override; up to the name without a `value`, else whole.
fn u32_decl(lang: Lang, input: bool, name: &str, value: Option<&str>) -> String {
    let keyword = match (lang, input) {
        (_, false) => "const",
        (Lang::Glsl, true) => "uniform",
        (Lang::Wgsl, true) => "override",
    };
    match (lang, value) {
        (Lang::Glsl, None) => format!("{keyword} uint {name}"),
        (Lang::Glsl, Some(v)) => format!("{keyword} uint {name} = {v};"),
        (Lang::Wgsl, None) => format!("{keyword} {name}"),
        (Lang::Wgsl, Some(v)) => format!("{keyword} {name}: u32 = {v};"),
    }
}

/// The head of the entry point `name` of `lang`, its query parameter named `param`.
fn entry_head(lang: Lang, name: &str, param: &str) -> String {
    match lang {
        Lang::Glsl => format!("Trace {name}(Query {param})"),
        Lang::Wgsl => format!("fn {name}({param}: Query) -> Trace"),
    }
}

fn lines(s: &str) -> usize {
    s.lines().count()
}

#[test]
fn a_minimal_shader_leaves_out_what_its_scene_does_not_use() {
    let scene = Scene {
        shadows: Shadows::None,
        max_view_angle_deg: 80.0,
        ..Scene::general(MethodKind::Exact, Surface::Triangles)
    };
    for lang in Lang::ALL {
        let uniform = u32_decl(lang, true, "hf_surface", None);
        let constant = u32_decl(lang, false, "hf_surface", Some("HF_SURFACE_TRIANGLES"));
        let min = code(&generate(&scene, lang).unwrap());
        let gen = code(&general(MethodKind::Exact, lang).unwrap());
        // Each is in the general shader and not in the minimal one.
        for absent in [
            "surface_bilinear",
            "HF_SURFACE_BILINEAR",
            "HF_SURFACE_CORNER_PLANES",
            "surface_height_planes_segment",
            "surface_qu_triangles_segment",
            "surface_is_continuous",
            uniform.as_str(),
            "d[2] > 0.0",
        ] {
            assert!(!min.contains(absent), "{absent} in\n{min}");
            assert!(gen.contains(absent), "{absent} not in the general shader");
        }
        for absent in ["hf_pyramid", "hf_safety_map", "search_", "hf_method"] {
            assert!(!min.contains(absent), "{absent} in\n{min}");
        }
        assert!(min.contains(&constant), "{min}");
        assert!(min.contains("surface_triangles_segment"));
        assert!(
            lines(&min) * 3 < lines(&gen) * 2,
            "{} vs {}",
            lines(&min),
            lines(&gen)
        );
        let all = all_methods(lang).unwrap();
        assert!(lines(&gen) < lines(&all));
        // With shadows the upward branch stays; another surface keeps only its own.
        let shadowed =
            generate(&Scene::general(MethodKind::Exact, Surface::Bilinear), lang).unwrap();
        assert!(shadowed.contains("d[2] > 0.0") && shadowed.contains("surface_bilinear_segment"));
        assert!(!shadowed.contains("surface_triangles_segment"));
    }
}

#[test]
fn generated_shaders_keep_only_their_method_inputs() {
    let cc = generate(
        &Scene::general(MethodKind::Cc, Surface::Triangles),
        Lang::Glsl,
    )
    .unwrap();
    assert!(cc.contains("uniform usampler2D hf_cc_map;"));
    assert!(!cc.contains("uniform usampler2D hf_safety_map") && !cc.contains("hf_safety_variant;"));
    // The class set of the maps is the scene's ray classes, a constant.
    assert!(
        cc.contains("const uint hf_cc_classes = 15u;") && !cc.contains("uint hf_safety_classes")
    );
    let cc_subset = Scene {
        ray_classes: RayClasses(0b1001),
        ..Scene::general(MethodKind::Cc, Surface::Triangles)
    };
    for lang in Lang::ALL {
        let text = generate(&cc_subset, lang).unwrap();
        let constant = u32_decl(lang, false, "hf_cc_classes", Some("9u"));
        assert!(text.contains(&constant), "{text}");
        assert!(
            !text.contains("uniform uint hf_cc_classes")
                && !text.contains("override hf_cc_classes")
        );
        let input = u32_decl(lang, true, "hf_cc_classes", Some("15u"));
        assert!(general(MethodKind::Cc, lang).unwrap().contains(&input));
    }
    let sd = |v| {
        let scene = Scene::general(MethodKind::Safety, Surface::Triangles);
        generate_with(&scene, Lang::Glsl, &Options { safety_variant: v }).unwrap()
    };
    let dir = sd(SafetyVariant::Directional);
    assert!(dir.contains(
        "texelFetch(hf_safety_map, ivec2(i, safety_class_row(hf_safety_classes, ray_class, j)), 0).r;"
    ));
    assert!(dir.contains("const uint hf_safety_classes = 15u;"));
    assert!(!dir.contains("texelFetch(hf_safety_map, ivec2(i, j), 0)"));
    // The bake plan's layout: isotropic for one ray class.
    let one_class = Scene {
        ray_classes: RayClasses(0b0001),
        ..Scene::general(MethodKind::Safety, Surface::Triangles)
    };
    let iso_fetch = "texelFetch(hf_safety_map, ivec2(i, j), 0).r;";
    let one = generate(&one_class, Lang::Glsl).unwrap();
    assert!(one.contains(iso_fetch) && one.contains("const uint hf_safety_classes = 1u;"));
    assert!(sd(SafetyVariant::Isotropic).contains(iso_fetch));
    assert!(!sd(SafetyVariant::Isotropic).contains("safety_class_row"));
    let u16 = Scene {
        heights: HeightFormat::U16,
        ..Scene::general(MethodKind::MaxMip, Surface::HeightPlanes)
    };
    let text = generate(&u16, Lang::Glsl).unwrap();
    assert!(text.contains("uniform usampler2D hf_heights;") && text.contains("hf_height_step"));
    assert!(!text.contains("uniform sampler2D hf_heights;"));
}

#[test]
fn safety_shape_shaders_finish_on_the_view_linear_surface() {
    for lang in Lang::ALL {
        let constant = u32_decl(lang, false, "hf_surface", Some("HF_SURFACE_VIEW_LINEAR"));
        let uniform = u32_decl(lang, true, "hf_surface", None);
        for m in [MethodKind::Safety, MethodKind::Cc, MethodKind::Radius] {
            let text = code(&generate(&Scene::general(m, Surface::ViewLinear), lang).unwrap());
            assert!(text.contains(&constant), "{}: {text}", m.name());
            assert!(
                !text.contains("surface_triangles_segment")
                    && !text.contains("HF_SURFACE_BILINEAR"),
                "{}: {text}",
                m.name()
            );
            // The general shader: the runtime surface, with the fallback to triangles.
            let gen = general(m, lang).unwrap();
            assert!(gen.contains(&uniform) && gen.contains("safety_march_surface(march_surface)"));
            let tri = code(&generate(&Scene::general(m, Surface::Triangles), lang).unwrap());
            assert!(
                tri.contains("surface_triangles_segment")
                    && !tri.contains("HF_SURFACE_VIEW_LINEAR"),
                "{}: {tri}",
                m.name()
            );
        }
    }
}

#[test]
fn unsupported_scenes_are_errors() {
    let bad = Scene::general(MethodKind::Cc, Surface::Bilinear);
    assert!(matches!(
        generate(&bad, Lang::Glsl),
        Err(GenError::SurfaceNotSupported { .. })
    ));
    for (m, s) in [
        (MethodKind::Safety, Surface::HeightPlanes),
        (MethodKind::Radius, Surface::CornerPlanes),
        (MethodKind::Cone, Surface::ViewLinear),
        (MethodKind::Qdm, Surface::ViewLinear),
        (MethodKind::Relaxed, Surface::ViewLinear),
    ] {
        let e = generate(&Scene::general(m, s), Lang::Wgsl).unwrap_err();
        assert!(matches!(e, GenError::SurfaceNotSupported { .. }), "{e}");
    }
    for (m, why) in [
        (
            MethodKind::Safety,
            "method safety traces the view-linear and the triangle surface only, not bilinear",
        ),
        (
            MethodKind::Cone,
            "method cone traces the triangle surface only, not bilinear",
        ),
    ] {
        let e = generate(&Scene::general(m, Surface::Bilinear), Lang::Glsl).unwrap_err();
        assert_eq!(e.to_string(), why);
    }
    let lod = Scene {
        lod: true,
        ..Scene::general(MethodKind::MaxMip, Surface::Triangles)
    };
    assert!(matches!(
        generate(&lod, Lang::Glsl),
        Err(GenError::Scene(_))
    ));
    let none = Scene {
        ray_classes: RayClasses(0),
        ..Scene::general(MethodKind::Exact, Surface::Triangles)
    };
    assert!(matches!(
        generate(&none, Lang::Glsl),
        Err(GenError::Scene(_))
    ));
}

#[test]
fn every_shader_has_one_world_entry_after_hf_trace() {
    for lang in Lang::ALL {
        let world = entry_head(lang, "hf_trace_world", "world");
        let inputs = match lang {
            Lang::Glsl => "hf_world_offset, hf_world_scale.",
            Lang::Wgsl => "hf_world.",
        };
        let mut texts: Vec<(String, String)> = MethodKind::ALL
            .into_iter()
            .flat_map(|m| {
                let scene = Scene::general(m, Surface::Triangles);
                [
                    (format!("general {}", m.name()), general(m, lang).unwrap()),
                    (
                        format!("generated {}", m.name()),
                        generate(&scene, lang).unwrap(),
                    ),
                ]
            })
            .collect();
        texts.push(("all methods".into(), all_methods(lang).unwrap()));
        for (label, text) in &texts {
            let text = &code(text);
            assert_eq!(text.matches(&world).count(), 1, "{label}");
            // Last: it calls the (dispatching) hf_trace, which comes before it.
            let trace = entry_head(lang, "hf_trace", "q");
            assert!(text.rfind(&trace) < text.find(&world), "{label}");
            assert!(text.trim_end().ends_with('}'), "{label}");
        }
        // A generated shader names the transform among its inputs (last: the world file
        // is last).
        let gen = generate(&Scene::general(MethodKind::Exact, Surface::Triangles), lang).unwrap();
        let head = gen.lines().find(|l| l.contains("Inputs to set")).unwrap();
        assert!(head.ends_with(inputs), "{head}");
    }
}

/// The GLSL of every translated file is the translation of its WGSL
/// (`hfcast_shaders::translate`), committed; `HFCAST_BLESS=1` rewrites it.
#[test]
fn glsl_ports_are_generated_from_the_wgsl() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut stems: Vec<String> = std::fs::read_dir(dir.join("wgsl"))
        .expect("wgsl/")
        .filter_map(|e| {
            e.ok()?
                .file_name()
                .to_str()?
                .strip_suffix(".wgsl")
                .map(String::from)
        })
        .filter(|s| hfcast_shaders::translate::is_translated(s))
        .collect();
    stems.sort();
    assert!(stems.len() >= 12, "the translated files: {stems:?}");
    for stem in stems {
        let wgsl = std::fs::read_to_string(dir.join(format!("wgsl/{stem}.wgsl"))).expect("wgsl");
        let glsl = hfcast_shaders::translate::glsl_from_wgsl(&wgsl, &stem)
            .unwrap_or_else(|e| panic!("{e}"));
        hfcast_shaders::check_generated(
            &dir.join(format!("glsl/{stem}.glsl")),
            &glsl,
            &format!("glsl/{stem}.glsl is not the translation of wgsl/{stem}.wgsl"),
            "HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate",
        );
    }
}

/// The impostor scene of `surface`: the exact method, with or without depth output.
fn impostor_scene(surface: Surface, depth_output: bool) -> Scene {
    Scene {
        depth_output,
        ..Scene::general(MethodKind::Exact, surface)
    }
}

/// Compiles `src` with glslangValidator as `file`; the error is its output.
fn glslang(dir: &std::path::Path, file: &str, src: &str) -> Result<(), String> {
    let path = dir.join(file);
    std::fs::write(&path, src).unwrap();
    let out = Command::new("glslangValidator")
        .arg(&path)
        .output()
        .expect("glslangValidator must be installed (apt-get install glslang-tools)");
    if out.status.success() {
        Ok(())
    } else {
        Err(format!("{file}: {}", String::from_utf8_lossy(&out.stdout)))
    }
}

/// Parses and validates the WGSL `src` with naga (every flag, every capability).
fn naga_validates(label: &str, src: &str) -> Result<(), String> {
    let module = naga::front::wgsl::parse_str(src)
        .map_err(|e| format!("{label}: {}", e.emit_to_string(src)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("{label}: {}", e.emit_to_string(src)))?;
    Ok(())
}

/// Every impostor shader (each surface, depth output on and off) is used from a plain
/// fragment shader's main as the OpenGL renderer does: GLSL 3.30 and 4.30 with
/// glslang, WGSL (a `@fragment` entry point, `frag_depth` with depth output) with naga.
#[test]
fn impostor_shaders_compile_in_a_fragment_shader() {
    let dir = tmp_dir("impostor");
    let mut failed = Vec::new();
    let mut count = 0;
    for surface in Surface::ALL {
        for depth in [false, true] {
            let label = format!(
                "impostor_{}_{}",
                surface.name(),
                if depth { "depth" } else { "nodepth" }
            );
            let glsl = impostor(&impostor_scene(surface, depth), Lang::Glsl).unwrap();
            let depth_line = if depth {
                "gl_FragDepth = hf_impostor_depth(a.trace.hit.point);\n    "
            } else {
                ""
            };
            for version in ["330 core", "430 core"] {
                let src = format!(
                    "#version {version}\n{glsl}\nuniform vec3 eye;\nout vec4 hf_out;\nvoid main() {{\n    \
                     Query world = Query(eye, vec3(gl_FragCoord.xy, -100.0) - eye, 0.0, 1e30);\n    \
                     ImpostorTrace a = hf_trace_impostor(world, HF_IMPOSTOR_INTERSECTION);\n    \
                     ImpostorTrace b = hf_trace_impostor(world, HF_IMPOSTOR_FACING_FIELD);\n    \
                     if (!a.trace.has_hit) {{\n        discard;\n    }}\n    {depth_line}\
                     hf_out = vec4(a.trace.hit.normal, float(a.face + b.face + a.traces));\n}}\n"
                );
                let file = format!("{label}_{}.frag", &version[..3]);
                failed.extend(glslang(&dir, &file, &src).err());
                count += 1;
            }
            let wgsl = impostor(&impostor_scene(surface, depth), Lang::Wgsl).unwrap();
            let (out, ret) = if depth {
                (
                    "ImpostorOut",
                    "return ImpostorOut(vec4<f32>(a.trace.hit.normal, f32(a.face)), \
                     hf_impostor_depth(a.trace.hit.point));",
                )
            } else {
                (
                    "@location(0) vec4<f32>",
                    "return vec4<f32>(a.trace.hit.normal, f32(a.face + b.face + a.traces));",
                )
            };
            let src = format!(
                "{wgsl}\nstruct ImpostorOut {{\n    @location(0) color: vec4<f32>,\n    \
                 @builtin(frag_depth) depth: f32,\n}}\n\n\
                 @fragment\nfn hf_main(@builtin(position) pos: vec4<f32>) -> {out} {{\n    \
                 let eye: vec3<f32> = vec3<f32>(0.3, 0.2, 4.0);\n    \
                 let world: Query = Query(eye, vec3<f32>(pos.xy, -100.0) - eye, 0.0, 1e30);\n    \
                 let a: ImpostorTrace = hf_trace_impostor(world, HF_IMPOSTOR_INTERSECTION);\n    \
                 let b: ImpostorTrace = hf_trace_impostor(world, HF_IMPOSTOR_FACING_FIELD);\n    \
                 {ret}\n}}\n"
            );
            failed.extend(naga_validates(&label, &src).err());
            count += 1;
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    eprintln!("{count} impostor shaders compile (glslang, naga)");
}

/// An impostor shader keeps what its scene uses: with depth output the depth helper
/// and its matrix, without it neither; the six fields' slot and ranges, the maps, the
/// exact march on the scene's surface as a constant; not the world entry, the
/// one-field ranges nor another surface. The header lists the inputs. Other methods and
/// integer heights are refused.
#[test]
fn impostor_shaders_keep_what_their_scene_uses() {
    for lang in Lang::ALL {
        let with = impostor(&impostor_scene(Surface::Triangles, true), lang).unwrap();
        let without = impostor(&impostor_scene(Surface::Triangles, false), lang).unwrap();
        assert_ne!(with, without);
        for text in [&with, &without] {
            assert!(!text.contains("//#"), "{text}");
            let code = code(text);
            for present in [
                "hf_trace_impostor",
                "hf_field_slot",
                "hf_field_ranges",
                "projective_to_world",
                "surface_triangles_segment",
            ] {
                assert!(code.contains(present), "{present} not in\n{text}");
            }
            for absent in [
                "hf_trace_world",
                "hf_height_range",
                "surface_bilinear_segment",
                "query_walked_back",
                u32_decl(lang, true, "hf_surface", None).as_str(),
            ] {
                assert!(!code.contains(absent), "{absent} in\n{text}");
            }
            assert!(code.contains(&u32_decl(
                lang,
                false,
                "hf_surface",
                Some("HF_SURFACE_TRIANGLES")
            )));
        }
        for name in ["hf_impostor_depth", "hf_view_proj"] {
            assert!(
                code(&with).contains(name) && !code(&without).contains(name),
                "{name}"
            );
        }
        let inputs = |text: &str| {
            let head = text.lines().find(|l| l.contains("Inputs to set")).unwrap();
            head.split("Inputs to set: ").nth(1).unwrap().to_string()
        };
        let want = match lang {
            Lang::Glsl => {
                "hf_heights, hf_size, hf_field_ranges, hf_impostor_maps, \
                           hf_impostor_inverses, hf_impostor_cube"
            }
            Lang::Wgsl => "hf_heights, hf_field, hf_field_ranges, hf_impostor",
        };
        assert_eq!(inputs(&without), format!("{want}."));
        assert_eq!(inputs(&with), format!("{want}, hf_view_proj."));
        for bad in [
            Scene::general(MethodKind::MaxMip, Surface::Triangles),
            Scene {
                heights: HeightFormat::U16,
                ..impostor_scene(Surface::Triangles, false)
            },
        ] {
            assert!(matches!(impostor(&bad, lang), Err(GenError::Scene(_))));
        }
    }
}

/// The impostor file's constants are the core's: the combinations, the pass cap, the
/// face of a miss (one past the last face) and the solids' floor.
#[test]
fn impostor_constants_are_the_cores() {
    use hfcast::impostor::{Combine, FACES, MAX_ROUNDS};
    let text = hfcast_shaders::file(Lang::Wgsl, hfcast_shaders::IMPOSTOR).unwrap();
    for (name, value) in [
        ("HF_IMPOSTOR_INTERSECTION", Combine::Intersection as u32),
        ("HF_IMPOSTOR_FACING_FIELD", Combine::FacingField as u32),
        ("HF_IMPOSTOR_MAX_ROUNDS", MAX_ROUNDS),
        ("HF_IMPOSTOR_NO_FACE", FACES.len() as u32),
    ] {
        let decl = format!("const {name}: u32 = {value}u;");
        assert!(text.contains(&decl), "impostor.wgsl lacks {decl}");
    }
    let floor = format!(
        "const HF_IMPOSTOR_FLOOR: f32 = {:?};",
        hfcast::impostor::FLOOR
    );
    assert!(text.contains(&floor), "impostor.wgsl lacks {floor}");
}
