//! # hfcast-shaders
//!
//! The GLSL (`shaders/glsl`) and WGSL (`shaders/wgsl`) ports of hfcast's marches as
//! source text, and shader generation from a scene description (docs/DESIGN.md, "Leave
//! out what a scene does not need"):
//!
//! - [`general`]: a method's general shader, its files concatenated: every surface and
//!   option is a runtime choice (`hf_surface`, `hf_safety_variant`, and the ray classes
//!   the safety-distance and cylinder–cone maps hold, `hf_safety_classes`,
//!   `hf_cc_classes`, `HF_RAYS_*` bits defaulting to all four).
//! - [`generate`]: the shader of one [`Scene`]: one surface, one method, the scene's
//!   options; the specialisation markers ([`FLAGS`]) drop the branches it never takes,
//!   then a tree shaker keeps only the top-level items reachable from the entry points, so
//!   unused functions, uniforms and textures go too, and the scene's choices become
//!   constants.
//! - [`all_methods`]: every method in one shader with a runtime `hf_method` switch,
//!   the size comparison at the other end.
//! - [`wgsl_layout`]: the fixed `@group(0)` binding numbers of the WGSL resources.
//! - [`impostor`]: the library of six-field impostors (`hfcast::impostor`) for a scene
//!   of the exact method: `hf_trace_impostor` on six projective fields stacked in one
//!   texture, and the fragment's depth when the scene asks for it.
//!
//! Every shader has three entry points: `hf_trace` (a ray in grid space, the marches'
//! frame), `hf_trace_world` (`world.glsl` / `world.wgsl`, after the marches: a ray in
//! world units converted by the field's transform, `hfcast::world::WorldTransform`, the
//! hit converted back) and `hf_trace_projective` (`projective.wgsl`, last: a world ray
//! through a projective map given by rows, `hfcast::projective`). The world file is always included, not only for scenes that
//! ask: it is small, a scene has no notion of a transform, and it costs a caller of
//! `hf_trace` nothing (shader compilers drop the unused function, an unused GLSL uniform
//! is inactive, and a WGSL binding is needed only by an entry point that uses it).
//!
//! The marches are written once, in WGSL: [`translate`] generates the GLSL of every
//! file [`translate::is_translated`] names (committed, drift-checked by `tests/validate.rs`,
//! regenerated with `HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate`);
//! only the files whose resources differ by language (`field`, `field_int`, `world`, the
//! `method_*` files) are written in both.
//!
//! The markers are comments, the same in both languages (WGSL has no preprocessor):
//! `//#if a|b`, `//#else`, `//#endif`, nestable; the general shader sets every flag,
//! so it is exactly the files with the marker lines removed. The WGSL sources also hold
//! language regions for the translation (`//#wgsl` … `//#end`, `//#glsl` … `//#end`),
//! which the WGSL shaders drop.
//!
//! GPU bakes (`bake_*.wgsl`, compute shaders of their own, WGSL only for now): the
//! maximum mipmap, whole and by sub-rectangle, byte for byte the CPU bake's; the
//! module `bake` (feature `maxmip`) gives their passes.

#[cfg(any(feature = "maxmip", feature = "safety"))]
pub mod bake;
mod directive;
mod shake;
mod shared;
pub mod translate;
pub mod wgsl_layout;

pub use shared::{
    glsl_shared, wgsl_shared, SafetyVariant, CC_NO_CONE, ENTRY_SIDE, ENTRY_START, ENTRY_TOP,
    MAX_LEVELS, PYRAMID_TEX_WIDTH, SAFETY_SEG_PAD,
};

use hfcast::scene::{HeightFormat, MethodKind, RayClasses, Scene, SceneError, Shadows};
use hfcast::Surface;
use shake::{Item, Kind, Seg};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

include!(concat!(env!("OUT_DIR"), "/files.rs"));

/// A shading language.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Lang {
    /// GLSL 3.30 core (no `#version` line: the caller puts it first).
    Glsl,
    /// WGSL.
    Wgsl,
}

impl Lang {
    /// Both languages.
    pub const ALL: [Lang; 2] = [Lang::Glsl, Lang::Wgsl];

    /// The file extension without the dot: `glsl`, `wgsl`; also the name the CLI uses.
    pub fn ext(self) -> &'static str {
        match self {
            Lang::Glsl => "glsl",
            Lang::Wgsl => "wgsl",
        }
    }

    /// The language named `glsl` or `wgsl`.
    pub fn from_name(name: &str) -> Option<Lang> {
        Lang::ALL.into_iter().find(|l| l.ext() == name)
    }

    /// The embedded files of this language.
    fn files(self) -> &'static [(&'static str, &'static str)] {
        match self {
            Lang::Glsl => GLSL_FILES,
            Lang::Wgsl => WGSL_FILES,
        }
    }
}

/// The text of file `stem` (`math`, `method_cc`, …) of `lang`, if the port has it.
pub fn file(lang: Lang, stem: &str) -> Option<&'static str> {
    lang.files().iter().find(|(n, _)| *n == stem).map(|f| f.1)
}

/// The specialisation flags of the markers, with what each says. A generated shader
/// sets those of its scene and `one_field`, an [`impostor`] shader its own; the general
/// shaders set them all.
pub const FLAGS: [(&str, &str); 18] = [
    ("triangles", "the surface is the triangle surface"),
    ("bilinear", "the surface is bilinear"),
    ("height_planes", "the surface is height planes"),
    ("corner_planes", "the surface is corner planes"),
    ("view_linear", "the surface is view-linear"),
    (
        "qu_triangles",
        "the surface is Qu et al.'s fixed-diagonal triangles",
    ),
    (
        "any_surface",
        "the surface is the runtime uniform hf_surface (general shaders): the tests that dispatch on it",
    ),
    ("directional", "safety distances are per ray class"),
    ("isotropic", "safety distances are isotropic"),
    (
        "any_variant",
        "the safety-map layout is the runtime uniform hf_safety_variant (general shaders)",
    ),
    (
        "upward",
        "rays may point upward: shadow rays, or a view angle over 90 degrees",
    ),
    ("heights_f32", "heights are an R32F texture in grid units"),
    (
        "heights_u16",
        "heights are an R16UI texture of samples times hf_height_step",
    ),
    (
        "heights_u8",
        "heights are an R8UI texture of samples times hf_height_step",
    ),
    (
        "lod",
        "level-of-detail marching (maximum mipmaps; no port yet)",
    ),
    (
        "occluders",
        "the safety-shape maps are baked over static occluders: the guard checks rays against them",
    ),
    (
        "one_field",
        "the shader reads one height field: every shader but an impostor's, which reads six stacked (hf_field_slot)",
    ),
    (
        "depth_output",
        "an impostor shader has hf_impostor_depth, the hit's depth for the fragment",
    ),
];

/// Why a shader cannot be generated.
#[derive(Clone, Debug, PartialEq)]
pub enum GenError {
    /// The method does not trace the surface ([`supports`]): the safety-shape methods
    /// (safety, cc, radius) trace the triangle and view-linear surfaces only, the cone
    /// family (cone, qdm, relaxed) the triangle surface only.
    SurfaceNotSupported {
        /// The method.
        method: MethodKind,
        /// The surface asked for.
        surface: Surface,
    },
    /// A file the shader needs is not in this language's port (yet).
    MissingFile {
        /// The language.
        lang: Lang,
        /// The file's stem.
        file: &'static str,
    },
    /// The scene is invalid (no ray class, an angle outside (0, 180]) or asks for
    /// something no port does (LOD marching).
    Scene(&'static str),
    /// The sources are malformed (a marker or declaration the generator cannot read).
    Source(String),
}

impl fmt::Display for GenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GenError::SurfaceNotSupported { method, surface } => write!(
                f,
                "method {} traces {} only, not {}",
                method.name(),
                if supports(*method, Surface::ViewLinear) {
                    "the view-linear and the triangle surface"
                } else {
                    "the triangle surface"
                },
                surface.name()
            ),
            GenError::MissingFile { lang, file } => {
                write!(f, "the {} port has no {file}.{}", lang.ext(), lang.ext())
            }
            GenError::Scene(why) => write!(f, "scene: {why}"),
            GenError::Source(why) => write!(f, "shader source: {why}"),
        }
    }
}

impl std::error::Error for GenError {}

/// The files (stems, in dependency order) of `method`'s general shader: the shared
/// constants, the core modules every march uses, the method's own files (the registry's,
/// `MethodInfo::shader`, the last defining `hf_trace`), then [`WORLD`] defining
/// `hf_trace_world` and [`PROJECTIVE`] defining `hf_trace_projective` on it.
pub fn parts(method: MethodKind) -> Vec<&'static str> {
    let own = method.info().shader;
    BASE.iter().chain(own).copied().chain(LAST).collect()
}

/// The files every march shares, in dependency order.
const BASE: [&str; 6] = ["hfcast_shared", "math", "ray", "field", "surface", "dda"];

/// The file of world units (`world.glsl`, `world.wgsl`: `hf_trace_world`), after the
/// marches in every shader since it calls `hf_trace`.
pub const WORLD: &str = "world";

/// The file of projective height fields (`projective.wgsl`, its GLSL generated:
/// `hf_trace_projective`), last in every shader: it calls `hf_trace` too.
pub const PROJECTIVE: &str = "projective";

/// The files after the marches, in order: their entry points call `hf_trace`.
const LAST: [&str; 2] = [WORLD, PROJECTIVE];

/// The file of six-field impostors (`impostor.wgsl`, its GLSL generated:
/// `hf_trace_impostor`, on [`PROJECTIVE`]'s `hf_trace_projective`), in the shaders of
/// [`impostor`] only.
pub const IMPOSTOR: &str = "impostor";

/// The flag every shader but an impostor's sets: it reads one height field (an
/// impostor's reads six stacked in one texture, `field`'s `hf_field_slot`).
const ONE_FIELD: &str = "one_field";

/// The file of `method` defining `hf_trace`: its last part before [`WORLD`].
fn method_file(method: MethodKind) -> &'static str {
    method.info().shader.last().copied().unwrap_or(WORLD)
}

/// Whether `method` traces `surface`: the exact, search and maxmip methods trace
/// every surface; the safety-shape methods (safety, cylinder–cone, radius) the
/// triangle and view-linear surfaces (their maps are baked for the triangles and bound
/// the view-linear surface too: `hfcast::safety::MarchSurface`); the cone family
/// (cone, qdm, relaxed) the triangle surface only.
///
/// In a general shader `hf_surface` is a runtime choice: a safety-shape march given a
/// surface it does not trace falls back to the triangle surface
/// (`safety_march_surface`).
pub fn supports(method: MethodKind, surface: Surface) -> bool {
    method.info().surfaces.contains(&surface)
}

/// The file of 16- and 8-bit heights, used instead of `field`'s `F32` texture.
const FIELD_INT: &str = "field_int";

/// The flag of `surface`.
fn surface_flag(surface: Surface) -> &'static str {
    match surface {
        Surface::Triangles => "triangles",
        Surface::Bilinear => "bilinear",
        Surface::HeightPlanes => "height_planes",
        Surface::CornerPlanes => "corner_planes",
        Surface::ViewLinear => "view_linear",
        Surface::QuTriangles => "qu_triangles",
    }
}

/// The safety-map layout [`generate`] assumes for `scene`: the one its bake plan
/// ([`Scene::bake_plan`]) bakes, isotropic when the scene has a single ray class (the
/// byte then holds that class's distances exactly), directional otherwise.
pub fn default_safety_variant(scene: &Scene) -> SafetyVariant {
    if scene.bake_plan().isotropic {
        SafetyVariant::Isotropic
    } else {
        SafetyVariant::Directional
    }
}

/// The ray classes (`HF_RAYS_*` bits) the safety-distance and cylinder–cone maps of
/// `scene` hold: its `ray_classes`, the set its bake plan bakes
/// (`BakePlan::classes` for those methods); a shader [`generate`]d for the scene has
/// them as the constants `hf_safety_classes` and `hf_cc_classes`, and reads the maps
/// as `hfcast::safety::SafetyMap::with_classes` and `CcMap::with_classes` do (a map of
/// `n` classes is a texture of W × nH texels; a ray of a class the set leaves out reads
/// a zero jump without a fetch).
pub fn map_classes(scene: &Scene) -> u32 {
    u32::from(scene.ray_classes.0 & RayClasses::ALL.0)
}

/// Options of [`generate_with`] that a [`Scene`] does not state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// The safety-distance map layout (safety method only).
    pub safety_variant: SafetyVariant,
}

/// The flags a generated shader of `scene` sets, after checking the scene.
pub fn scene_flags(scene: &Scene, opts: &Options) -> Result<Vec<&'static str>, GenError> {
    scene.validate().map_err(|e| {
        GenError::Scene(match e {
            SceneError::RayClasses => "the ray-class set is empty or unknown",
            SceneError::ViewAngle => "max_view_angle_deg is outside (0, 180]",
        })
    })?;
    let angle = scene.max_view_angle_deg;
    if scene.lod {
        return Err(GenError::Scene(if scene.method == MethodKind::MaxMip {
            "LOD marching has no shader port"
        } else {
            "LOD marching is for maximum mipmaps only"
        }));
    }
    if !supports(scene.method, scene.surface) {
        return Err(GenError::SurfaceNotSupported {
            method: scene.method,
            surface: scene.surface,
        });
    }
    let mut flags = vec![surface_flag(scene.surface)];
    flags.push(match opts.safety_variant {
        SafetyVariant::Directional => "directional",
        SafetyVariant::Isotropic => "isotropic",
    });
    if scene.shadows == Shadows::FromSurface || angle > 90.0 {
        flags.push("upward");
    }
    flags.push(match scene.heights {
        HeightFormat::F32 => "heights_f32",
        HeightFormat::U16 => "heights_u16",
        HeightFormat::U8 => "heights_u8",
    });
    if scene.occluders {
        flags.push("occluders");
    }
    Ok(flags)
}

/// The files `stems` of `lang` with the markers evaluated for `flags`.
fn load(
    lang: Lang,
    stems: &[&'static str],
    flags: &dyn Fn(&str) -> bool,
) -> Result<Vec<(&'static str, String)>, GenError> {
    stems
        .iter()
        .map(|&stem| {
            let text = file(lang, stem).ok_or(GenError::MissingFile { lang, file: stem })?;
            let name = format!("{stem}.{}", lang.ext());
            directive::evaluate(text, &name, flags)
                .map(|t| (stem, t))
                .map_err(GenError::Source)
        })
        .collect()
}

/// The file separator line of the composed sources.
fn separator(stem: &str, lang: Lang) -> String {
    format!("// ---- {stem}.{}\n", lang.ext())
}

/// The general shader of `method`: its files concatenated, every marker flag set (so
/// every surface and option is a runtime choice), marker lines removed. GLSL: the
/// source `hf_shader_source` returns.
pub fn general(method: MethodKind, lang: Lang) -> Result<String, GenError> {
    let mut s = String::new();
    for (stem, text) in load(lang, &parts(method), &|_| true)? {
        s.push_str(&separator(stem, lang));
        s.push_str(&text);
    }
    Ok(s)
}

/// Parses evaluated files into segments.
fn parse_all(lang: Lang, files: &[(&'static str, String)]) -> Result<Vec<Vec<Seg>>, GenError> {
    files
        .iter()
        .map(|(stem, text)| {
            shake::parse(text, &format!("{stem}.{}", lang.ext())).map_err(GenError::Source)
        })
        .collect()
}

/// Turns the input `name` (a GLSL uniform or WGSL override) into a constant of value
/// `value` (an expression).
fn make_const(lang: Lang, item: &mut Item, value: &str) -> Result<(), GenError> {
    let code = item.text.trim();
    let bad = || GenError::Source(format!("cannot make a constant of {code:?}"));
    let text = match lang {
        // `uniform T name;` or `uniform T name = default;` -> `const T name = value;`
        Lang::Glsl => {
            let decl = code.strip_prefix("uniform ").ok_or_else(bad)?;
            let decl = decl.strip_suffix(';').ok_or_else(bad)?;
            let decl = decl.split('=').next().ok_or_else(bad)?.trim();
            format!("const {decl} = {value};\n")
        }
        // `override name: T = default;` -> `const name: T = value;`
        Lang::Wgsl => {
            let decl = code.strip_prefix("override ").ok_or_else(bad)?;
            let decl = decl.split('=').next().ok_or_else(bad)?;
            let decl = decl.trim().trim_end_matches(';');
            format!("const {decl} = {value};\n")
        }
    };
    item.text = text;
    item.kind = Kind::Const;
    item.refs = shake::identifiers(&item.text);
    Ok(())
}

/// The shader of `scene` in `lang` with the default [`Options`]: see
/// [`generate_with`].
pub fn generate(scene: &Scene, lang: Lang) -> Result<String, GenError> {
    generate_with(
        scene,
        lang,
        &Options {
            safety_variant: default_safety_variant(scene),
        },
    )
}

/// The shader of `scene` in `lang`: only the code the scene uses. The markers are
/// evaluated for the scene's flags ([`scene_flags`]) and `one_field`; `hf_surface`,
/// `hf_safety_variant` and the class sets of the safety-distance and cylinder–cone
/// maps, `hf_safety_classes` and `hf_cc_classes` (the scene's `ray_classes`, the
/// classes its bake plan bakes and its maps hold: [`map_classes`]), and the ray set
/// those maps are baked for, `hf_rays_exterior` and `hf_rays_max_view_angle` (the bake
/// plan's `rays`), become constants;
/// then only the top-level items reachable from the entry points
/// `Trace hf_trace(Query q)` and `Trace hf_trace_world(Query world)` stay (and
/// `Query query_walked_back(Query q)`, `Query::walked_back`, when the scene traces
/// [`Shadows::FromLight`]: the light's ray to a point from its shadow ray). A header
/// comment names the scene and lists the inputs (uniforms, textures, bindings) left for
/// the caller to set.
pub fn generate_with(scene: &Scene, lang: Lang, opts: &Options) -> Result<String, GenError> {
    let flags = scene_flags(scene, opts)?;
    let mut stems: Vec<&'static str> = parts(scene.method);
    if scene.heights != HeightFormat::F32 {
        // Before `field`, whose functions read the heights through `field_at`.
        let at = stems.iter().position(|s| *s == "field").unwrap_or(0);
        stems.insert(at, FIELD_INT);
    }
    // A scene tracing shadows from the light keeps the function that makes its rays.
    let mut roots = vec!["hf_trace", "hf_trace_world", "hf_trace_projective"];
    if scene.shadows == Shadows::FromLight {
        roots.push("query_walked_back");
    }
    let set = |f: &str| f == ONE_FIELD || flags.contains(&f);
    let (body, inputs) = compose(scene, lang, opts, &stems, &set, &roots)?;
    let classes: Vec<&str> = ["x+", "x-", "y+", "y-"]
        .into_iter()
        .enumerate()
        .filter(|(k, _)| scene.ray_classes.0 & (1 << k) != 0)
        .map(|(_, n)| n)
        .collect();
    let mut head = format!(
        "// hfcast shader generated for one scene by hfcast-shaders (shaders/src/lib.rs).\n\
         // Scene: method {}, surface {}, rays {}, {}, view angle <= {} deg, {}, {}, heights {:?}{}.\n\
         // Flags: {}.\n",
        scene.method.name(),
        scene.surface.name(),
        classes.join(","),
        if scene.outside_only {
            "viewpoints outside the box"
        } else {
            "viewpoints anywhere"
        },
        scene.max_view_angle_deg,
        match scene.shadows {
            Shadows::None => "no shadows",
            Shadows::FromSurface => "shadows from the surface",
            Shadows::FromLight => "shadows from the light",
        },
        if scene.depth_output {
            "depth output"
        } else {
            "no depth output"
        },
        scene.heights,
        if scene.method == MethodKind::Safety {
            format!(", safety map {:?}", opts.safety_variant)
        } else {
            String::new()
        },
        flags.join(" "),
    );
    head.push_str(&format!(
        "// Entry points: Trace hf_trace(Query q) (grid space), Trace hf_trace_world(Query \
         world) (world units). Inputs to set: {}.\n",
        inputs.join(", ")
    ));
    Ok(head + &body)
}

/// The files `stems` of `lang` with the markers evaluated for the flags `set` holds,
/// `scene`'s choices made constants (see [`generate_with`]), and only the items
/// reachable from `roots` kept: the text, and the inputs left for the caller to set.
fn compose(
    scene: &Scene,
    lang: Lang,
    opts: &Options,
    stems: &[&'static str],
    set: &dyn Fn(&str) -> bool,
    roots: &[&str],
) -> Result<(String, Vec<String>), GenError> {
    let files = load(lang, stems, set)?;
    let mut segs = parse_all(lang, &files)?;
    let surface_const = format!("HF_SURFACE_{}", surface_flag(scene.surface).to_uppercase());
    let variant_const = match opts.safety_variant {
        SafetyVariant::Directional => "HF_SAFETY_DIRECTIONAL",
        SafetyVariant::Isotropic => "HF_SAFETY_ISOTROPIC",
    };
    let classes_const = format!("{}u", map_classes(scene));
    // The ray set the scene's safety-shape map is baked for (its bake plan's).
    let rays = scene.bake_plan().rays;
    let exterior_const = if rays.exterior { "1u" } else { "0u" };
    let angle_const = format!("{:?}", rays.max_view_angle_deg);
    for seg in segs.iter_mut().flatten() {
        if let Seg::Item(it) = seg {
            match (it.kind, it.name.as_str()) {
                (Kind::Input, "hf_surface") => make_const(lang, it, &surface_const)?,
                (Kind::Input, "hf_safety_variant") => make_const(lang, it, variant_const)?,
                (Kind::Input, "hf_safety_classes" | "hf_cc_classes") => {
                    make_const(lang, it, &classes_const)?
                }
                (Kind::Input, "hf_rays_exterior") => make_const(lang, it, exterior_const)?,
                (Kind::Input, "hf_rays_max_view_angle") => make_const(lang, it, &angle_const)?,
                _ => {}
            }
        }
    }
    let keep = shake::reachable(&segs, roots);
    let mut inputs = Vec::new();
    let body = shake::emit(
        &segs,
        |f, k, it| {
            keep.contains(&(f, k)).then(|| {
                if it.kind == Kind::Input {
                    inputs.push(it.name.clone());
                }
                it.text.clone()
            })
        },
        |f| separator(files[f].0, lang),
    );
    Ok((body, inputs))
}

/// The impostor shader of `scene` in `lang`: the library a caller's shader calls to
/// trace six-field impostors (`hfcast::impostor`; the header of `impostor.wgsl` says
/// what the host sets), `hf_trace_impostor` (`Impostor::trace` with the exact march on
/// the scene's surface, a constant) and, when the scene has `depth_output`,
/// `hf_impostor_depth` (the hit's depth for the fragment, under the uniform
/// `hf_view_proj`), and the constants `HF_IMPOSTOR_INTERSECTION`,
/// `HF_IMPOSTOR_FACING_FIELD` (`combine`) and `HF_IMPOSTOR_NO_FACE`. The files of the exact method's shader and [`IMPOSTOR`], the
/// markers evaluated for the scene's flags with `upward` (a face's grid rays go every
/// way) and `depth_output` as the scene says, but not `one_field` (the six fields are
/// stacked in one texture), then only the items those entry points reach. A header
/// comment names the scene, the entry points and the inputs left for the caller to set.
///
/// Errors: a method other than [`MethodKind::Exact`], heights other than
/// [`HeightFormat::F32`] ([`GenError::Scene`]), and what [`scene_flags`] refuses.
pub fn impostor(scene: &Scene, lang: Lang) -> Result<String, GenError> {
    if scene.method != MethodKind::Exact {
        return Err(GenError::Scene(
            "an impostor shader traces its fields with the exact method only",
        ));
    }
    if scene.heights != HeightFormat::F32 {
        return Err(GenError::Scene("an impostor's fields are 32-bit heights"));
    }
    let opts = Options::default();
    scene_flags(scene, &opts)?;
    let mut flags = vec![surface_flag(scene.surface), "upward", "heights_f32"];
    // The entry points and the constants a caller names.
    let mut roots = vec![
        "hf_trace_impostor",
        "HF_IMPOSTOR_INTERSECTION",
        "HF_IMPOSTOR_FACING_FIELD",
        "HF_IMPOSTOR_NO_FACE",
    ];
    if scene.depth_output {
        flags.push("depth_output");
        roots.push("hf_impostor_depth");
    }
    let mut stems = parts(MethodKind::Exact);
    stems.push(IMPOSTOR);
    let set = |f: &str| flags.contains(&f);
    let (body, inputs) = compose(scene, lang, &opts, &stems, &set, &roots)?;
    let entries = match lang {
        Lang::Glsl => [
            "ImpostorTrace hf_trace_impostor(Query world, uint combine)",
            "float hf_impostor_depth(vec3 p)",
        ],
        Lang::Wgsl => [
            "fn hf_trace_impostor(world: Query, combine: u32) -> ImpostorTrace",
            "fn hf_impostor_depth(p: vec3<f32>) -> f32",
        ],
    };
    let head = format!(
        "// hfcast impostor shader generated by hfcast-shaders (shaders/src/lib.rs): six-field\n\
         // impostors traced by the exact method on the surface {}, {}.\n\
         // Flags: {}.\n\
         // Entry points: {}. Inputs to set: {}.\n",
        scene.surface.name(),
        if scene.depth_output {
            "depth output"
        } else {
            "no depth output"
        },
        flags.join(" "),
        entries[..1 + usize::from(scene.depth_output)].join(", "),
        inputs.join(", ")
    );
    Ok(head + &body)
}

/// The suffix of `method`'s names in the all-methods shader: `linear_binary`, …
fn suffix(method: MethodKind) -> String {
    method.name().replace('-', "_")
}

/// Every method in one shader: each method's `hf_trace` becomes `hf_trace_<method>`
/// (in the shader: `hf_trace_linear_binary`, …), and so does every function that depends on code
/// the method's file defines (the closures of the shared marches: `cone_march`,
/// `safety_march`, …), so that the cone and safety marches appear once per method that
/// uses them; everything else appears once. `Trace hf_trace(Query q)` dispatches on
/// the runtime `hf_method` (a GLSL uniform, a WGSL override), every marker flag set;
/// [`WORLD`]'s `hf_trace_world` and [`PROJECTIVE`]'s `hf_trace_projective` follow the
/// dispatch, on the dispatching `hf_trace`.
pub fn all_methods(lang: Lang) -> Result<String, GenError> {
    let file_order = file_order();
    let files = load(lang, &file_order, &|_| true)?;
    let segs = parse_all(lang, &files)?;
    let item = |&(f, k): &(usize, usize)| match &segs[f][k] {
        Seg::Item(it) => Some(it),
        _ => None,
    };
    let index = |stem: &str| file_order.iter().position(|f| *f == stem);
    // Names the method files declare, with their texts: an input declared differently
    // by several of them (WGSL's `hf_params` at binding 2) becomes one struct with a
    // member per method.
    let mut texts: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    for m in MethodKind::ALL {
        let f = index(method_file(m)).unwrap_or_default();
        for seg in &segs[f] {
            if let Seg::Item(it) = seg {
                texts.entry(&it.name).or_default().insert(&it.text);
            }
        }
    }
    let merged = |it: &Item| {
        it.kind == Kind::Input && texts.get(it.name.as_str()).is_some_and(|t| t.len() > 1)
    };
    // Merged input name -> (its declaration up to the type, [(member, type)]).
    let mut merged_inputs: BTreeMap<String, (String, Vec<(String, String)>)> = BTreeMap::new();
    // Per item: the methods that reach it, each with whether it renames it.
    let mut used: BTreeMap<(usize, usize), Vec<(usize, bool)>> = BTreeMap::new();
    let mut renames: Vec<BTreeMap<String, String>> = Vec::new();
    for (mi, m) in MethodKind::ALL.into_iter().enumerate() {
        let own: BTreeSet<usize> = parts(m).iter().filter_map(|p| index(p)).collect();
        let visible: Vec<Vec<Seg>> = segs
            .iter()
            .enumerate()
            .map(|(f, s)| {
                if own.contains(&f) {
                    s.clone()
                } else {
                    Vec::new()
                }
            })
            .collect();
        // `HF_METHOD_<M>`: the dispatch's test.
        let id = format!("HF_METHOD_{}", suffix(m).to_uppercase());
        // `query_walked_back` too: the shadow rays' entry, and `dda_slab` for the
        // projective file appended after the dispatch.
        let keep = shake::reachable(&visible, &["hf_trace", &id, "query_walked_back"]);
        let method_file = index(method_file(m)).unwrap_or_default();
        let is_fn = |it: &&Item| matches!(it.kind, Kind::Function | Kind::Prototype);
        // The method file's functions and conflicting names, then every function
        // that refers to one of them.
        let mut dep: BTreeSet<String> = keep
            .iter()
            .filter(|(f, _)| *f == method_file)
            .filter_map(item)
            .filter(is_fn)
            .map(|it| it.name.clone())
            .collect();
        loop {
            let more: Vec<String> = keep
                .iter()
                .filter_map(item)
                .filter(is_fn)
                .filter(|it| !dep.contains(&it.name) && it.refs.iter().any(|r| dep.contains(r)))
                .map(|it| it.name.clone())
                .collect();
            if more.is_empty() {
                break;
            }
            dep.extend(more);
        }
        for at in &keep {
            let renamed = item(at).is_some_and(|it| dep.contains(&it.name));
            used.entry(*at).or_default().push((mi, renamed));
        }
        let sfx = suffix(m);
        let mut names: BTreeMap<String, String> = dep
            .into_iter()
            .map(|n| (n.clone(), format!("{n}_{sfx}")))
            .collect();
        for &at in &keep {
            if let Some(it) = item(&at).filter(|it| merged(it)) {
                names.insert(it.name.clone(), format!("{}.{sfx}", it.name));
                let (head, ty) = it
                    .text
                    .trim()
                    .rsplit_once(':')
                    .ok_or_else(|| GenError::Source(format!("cannot merge {:?}", it.text)))?;
                let ty = ty.trim().trim_end_matches(';').to_string();
                merged_inputs
                    .entry(it.name.clone())
                    .or_insert_with(|| (head.to_string(), Vec::new()))
                    .1
                    .push((sfx.clone(), ty));
            }
        }
        renames.push(names);
    }
    // Items every method shares appear once (identical declarations by several method
    // files, such as `hf_surface`, once too); renamed ones once per method.
    let mut emitted: BTreeSet<String> = BTreeSet::new();
    let mut body = shake::emit(
        &segs,
        |f, k, it| {
            let users = used.get(&(f, k)).filter(|_| !merged(it))?;
            let mut text = String::new();
            if users.iter().any(|u| !u.1) && emitted.insert(it.text.clone()) {
                text.push_str(&it.text);
            }
            for &(mi, renamed) in users {
                if renamed {
                    text.push_str(&shake::rename(&it.text, &renames[mi]));
                }
            }
            (!text.is_empty()).then_some(text)
        },
        |f| separator(file_order[f], lang),
    );
    for (name, (head, members)) in &merged_inputs {
        if lang == Lang::Glsl {
            return Err(GenError::Source(format!(
                "{name} is declared differently by two methods"
            )));
        }
        let ty = format!("AllMethods_{name}");
        body.push_str(&format!(
            "\n// ---- {name} of every method, one binding (generated)\nstruct {ty} {{\n"
        ));
        for (member, mty) in members {
            body.push_str(&format!("    @align(16) {member}: {mty},\n"));
        }
        body.push_str(&format!("}}\n\n{head}: {ty};\n"));
    }
    body.push_str(&dispatch(lang));
    // `hf_trace_world` and `hf_trace_projective` on the dispatch (the method files'
    // `hf_trace`s do not reach them).
    for (stem, text) in load(lang, &LAST, &|_| true)? {
        body.push('\n');
        body.push_str(&separator(stem, lang));
        body.push_str(&text);
    }
    Ok(format!(
        "// hfcast all-methods shader generated by hfcast-shaders (shaders/src/lib.rs): every\n\
         // method, selected at run time by hf_method (HF_METHOD_*); every surface and option\n\
         // a runtime choice as in the general shaders.\n{body}"
    ))
}

/// The order of the files in a composed shader ([`WORLD`] and [`PROJECTIVE`] follow
/// them): the files
/// every march shares, the methods' own modules (each once, in registry order, a
/// method's in its dependency order), then the methods' files defining `hf_trace`.
fn file_order() -> Vec<&'static str> {
    let mut order: Vec<&'static str> = BASE.to_vec();
    let own = MethodKind::ALL
        .iter()
        .flat_map(|m| m.info().shader.iter().copied());
    let (methods, modules): (Vec<_>, Vec<_>) = own.partition(|f| f.starts_with("method_"));
    for f in modules.into_iter().chain(methods) {
        if !order.contains(&f) {
            order.push(f);
        }
    }
    order
}

/// The `hf_method` input and the dispatching `hf_trace` of the all-methods shader.
fn dispatch(lang: Lang) -> String {
    // The input and the entry point's head differ by language; the body is the same.
    let head = match lang {
        Lang::Glsl => "uniform uint hf_method;\n\nTrace hf_trace(Query q) {\n",
        Lang::Wgsl => "override hf_method: u32 = 0u;\n\nfn hf_trace(q: Query) -> Trace {\n",
    };
    let mut s = format!("\n// ---- all-methods dispatch (generated)\n{head}");
    let (last, rest) = MethodKind::ALL.split_last().expect("there are methods");
    for &m in rest {
        s.push_str(&format!(
            "    if (hf_method == HF_METHOD_{}) {{\n        return hf_trace_{}(q);\n    }}\n",
            suffix(m).to_uppercase(),
            suffix(m)
        ));
    }
    s.push_str(&format!("    return hf_trace_{}(q);\n}}\n", suffix(*last)));
    s
}

/// The check of a committed generated file (the GLSL ports, the shared files, the C
/// header) in the test that keeps it current: `fresh`, generated now, must be the file
/// at `path`; with `HFCAST_BLESS` set the test writes it there instead. Returns whether
/// it checked (false: it wrote).
///
/// # Panics
///
/// When the committed file differs, with `stale` (what is out of date) and the command
/// `regenerate` that rewrites it; when blessing cannot write the file.
pub fn check_generated(path: &std::path::Path, fresh: &str, stale: &str, regenerate: &str) -> bool {
    if std::env::var_os("HFCAST_BLESS").is_some() {
        std::fs::write(path, fresh).unwrap_or_else(|e| panic!("write {}: {e}", path.display()));
        return false;
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == fresh,
        "{stale}: regenerate it with `{regenerate}` and commit it"
    );
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Compares a generated shared file with the committed one (`HFCAST_BLESS=1`
    /// rewrites it).
    fn check_shared(lang: Lang, fresh: &str) {
        let path = format!(
            "{}/{}/hfcast_shared.{}",
            env!("CARGO_MANIFEST_DIR"),
            lang.ext(),
            lang.ext()
        );
        let stale = format!("{path} is out of date");
        if check_generated(
            path.as_ref(),
            fresh,
            &stale,
            "HFCAST_BLESS=1 cargo test -p hfcast-shaders",
        ) {
            // The compiled-in copy is the committed one.
            assert_eq!(file(lang, "hfcast_shared"), Some(fresh));
        }
    }

    #[test]
    fn shared_files_are_current() {
        check_shared(Lang::Glsl, &glsl_shared());
        check_shared(Lang::Wgsl, &wgsl_shared());
    }

    #[test]
    fn shared_numbers_are_the_cores() {
        assert_eq!(MAX_LEVELS, hfcast::maxmip::MAX_LEVELS as u32);
        assert_eq!(SAFETY_SEG_PAD, hfcast::safety::SEG_PAD as f32);
        assert_eq!(CC_NO_CONE, u32::from(hfcast::safety::cc::NO_CONE));
        assert_eq!(
            SafetyVariant::Isotropic as usize,
            hfcast::safety::Variant::Isotropic as usize
        );
    }

    #[test]
    fn safety_shape_surfaces_are_the_cores() {
        use hfcast::safety::MarchSurface;
        for surface in Surface::ALL {
            for m in [MethodKind::Safety, MethodKind::Cc, MethodKind::Radius] {
                assert_eq!(
                    supports(m, surface),
                    MarchSurface::of(surface).is_some(),
                    "{} {}",
                    m.name(),
                    surface.name()
                );
            }
            for m in [MethodKind::Cone, MethodKind::Qdm, MethodKind::Relaxed] {
                assert_eq!(supports(m, surface), surface == Surface::Triangles);
            }
        }
    }

    #[test]
    fn every_method_has_one_hf_trace_and_no_version_line() {
        for m in MethodKind::ALL {
            let s = general(m, Lang::Glsl).unwrap();
            assert_eq!(
                s.matches("Trace hf_trace(Query q)").count(),
                1,
                "{}",
                m.name()
            );
            assert!(!s.contains("#version") && !s.contains("//#"));
        }
    }
}
