//! `hfcast shader`: the shader generated for a scene described on the command line.

use crate::Args;
use hfcast::scene::{HeightFormat, MethodKind, RayClasses, Scene, Shadows};
use hfcast::Surface;
use hfcast_shaders::{all_methods, generate_with, Lang, Options, SafetyVariant};
use std::path::PathBuf;

/// The boolean options of the subcommand.
pub const FLAGS: [&str; 7] = [
    "no-shadows",
    "occluders",
    "shadows-from-light",
    "outside-only",
    "no-depth",
    "lod",
    "all-methods",
];

/// The ray-class set of `--rays`: `x+,x-,y+,y-` names.
fn parse_rays(list: &str) -> Result<RayClasses, String> {
    let mut set = RayClasses(0);
    for word in list.split(',').map(str::trim) {
        let bit = ["x+", "x-", "y+", "y-"]
            .iter()
            .position(|n| *n == word)
            .ok_or(format!("--rays: unknown class {word:?} (x+, x-, y+, y-)"))?;
        set = RayClasses(set.0 | 1 << bit);
    }
    Ok(set)
}

/// Runs `hfcast shader`.
pub fn cmd_shader(mut args: Args) -> Result<bool, String> {
    let name = args.opt("method").unwrap_or("exact".into());
    let method = MethodKind::ALL
        .into_iter()
        .find(|m| m.name() == name)
        .ok_or(format!("unknown method {name:?}"))?;
    let name = args.opt("surface").unwrap_or("triangles".into());
    let surface = Surface::from_name(&name).ok_or(format!("unknown surface {name:?}"))?;
    let name = args.opt("lang").unwrap_or("glsl".into());
    let lang = Lang::from_name(&name).ok_or(format!("--lang: {name:?} is not glsl or wgsl"))?;
    let ray_classes = match args.opt("rays") {
        Some(list) => parse_rays(&list)?,
        None => RayClasses::ALL,
    };
    let heights = match args.opt("heights").as_deref() {
        None | Some("f32") => HeightFormat::F32,
        Some("u16") => HeightFormat::U16,
        Some("u8") => HeightFormat::U8,
        Some(other) => return Err(format!("--heights: {other:?} is not f32, u16 or u8")),
    };
    let safety_variant = match args.opt("safety-variant").as_deref() {
        None | Some("directional") => SafetyVariant::Directional,
        Some("isotropic") => SafetyVariant::Isotropic,
        Some(other) => return Err(format!("--safety-variant: unknown layout {other:?}")),
    };
    let shadows = match (
        args.get("no-shadows", false)?,
        args.get("shadows-from-light", false)?,
    ) {
        (true, true) => {
            return Err("--no-shadows and --shadows-from-light exclude each other".into())
        }
        (true, false) => Shadows::None,
        (false, true) => Shadows::FromLight,
        (false, false) => Shadows::FromSurface,
    };
    let scene = Scene {
        ray_classes,
        outside_only: args.get("outside-only", false)?,
        max_view_angle_deg: args.get("max-view-angle", 180.0)?,
        shadows,
        lod: args.get("lod", false)?,
        depth_output: !args.get("no-depth", false)?,
        heights,
        occluders: args.get("occluders", false)?,
        ..Scene::general(method, surface)
    };
    let every = args.get("all-methods", false)?;
    let out = args.opt("out").map(PathBuf::from);
    args.finish()?;
    if let Some(p) = args.positional.first() {
        return Err(format!("shader: unexpected argument {p:?}"));
    }
    let text = if every {
        all_methods(lang)
    } else {
        generate_with(&scene, lang, &Options { safety_variant })
    }
    .map_err(|e| e.to_string())?;
    match out {
        Some(path) => {
            std::fs::write(&path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!("wrote {} ({} lines)", path.display(), text.lines().count());
        }
        None => print!("{text}"),
    }
    Ok(true)
}
