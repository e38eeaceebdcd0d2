//! The generated files `shaders/glsl/hfcast_shared.glsl` and
//! `shaders/wgsl/hfcast_shared.wgsl`: every constant and texture-layout number the
//! ports share with the Rust core and the C API, from one table rendered per language.

use crate::wgsl_layout as b;
use crate::Lang;
use hfcast::scene::{MethodKind, RayClasses};
use hfcast::{Flags, RayClass, Surface};
use std::fmt::Write as _;

/// Width of the `R32F` texture holding the maximum-mipmap pyramid buffer: pyramid
/// texel `k` is texel `(k % PYRAMID_TEX_WIDTH, k / PYRAMID_TEX_WIDTH)` (the C API's
/// `HF_PYRAMID_TEX_WIDTH`).
pub const PYRAMID_TEX_WIDTH: u32 = 4096;
/// Most levels of a maximum-mipmap pyramid (`hfcast::maxmip::MAX_LEVELS`).
pub const MAX_LEVELS: u32 = 25;
/// Texel segment widening of the safety bake (`hfcast::safety::SEG_PAD`).
pub const SAFETY_SEG_PAD: f32 = 0.0625;
/// Cylinder–cone slope code meaning "no cone" (`hfcast::safety::cc::NO_CONE`).
pub const CC_NO_CONE: u32 = 255;
/// How the ports encode `dda::Entry` (a Rust enum with data) in `Span::entry`:
/// `Entry::Start`.
pub const ENTRY_START: u32 = 0;
/// `Entry::Side`; the normal is in `Span::entry_normal`.
pub const ENTRY_SIDE: u32 = 1;
/// `Entry::Top`.
pub const ENTRY_TOP: u32 = 2;

/// The layout of a safety-distance map (`hfcast::safety::Variant`, the C API's
/// `hf_safety_variant`): the shaders' `HF_SAFETY_*` and `hf_safety_variant`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(u32)]
pub enum SafetyVariant {
    /// One distance per ray class (`R8UI`, W × 4H: texel `(i, 4j + class)`; a map
    /// holding `n` classes, `hf_safety_classes`: W × nH, texel `(i, nj + slot)`).
    #[default]
    Directional = 0,
    /// One distance per texel, the minimum over the classes (`R8UI`, W × H; valid for
    /// the classes of `hf_safety_classes` only).
    Isotropic = 1,
}

/// A scalar type of a shared constant.
#[derive(Clone, Copy)]
enum Ty {
    U32,
    I32,
    F32,
}

/// One line group of the shared file.
enum Line {
    /// A comment line (without `// `); an empty string is a blank line.
    Comment(String),
    /// A constant and its value.
    Const(String, Ty, String),
}

/// WGSL resource bindings of group 0 ([`crate::wgsl_layout`]): `(binding, name, type,
/// declared in)`.
const WGSL_BINDINGS: [(u32, &str, &str, &str); 21] = [
    (
        b::HEIGHTS,
        "hf_heights",
        "texture_2d<f32>, R32Float, W x H",
        "field.wgsl",
    ),
    (b::FIELD, "hf_field", "uniform FieldParams", "field.wgsl"),
    (
        b::PARAMS,
        "hf_params",
        "uniform, the method's step counts",
        "method_*.wgsl",
    ),
    (
        b::PYRAMID,
        "hf_pyramid",
        "texture_2d<f32>, R32Float",
        "maxmip.wgsl",
    ),
    (
        b::MAXMIP,
        "hf_maxmip",
        "uniform MaxMipParams",
        "maxmip.wgsl",
    ),
    (
        b::SAFETY_MAP,
        "hf_safety_map",
        "texture_2d<u32>, R8Uint",
        "safety.wgsl",
    ),
    (
        b::CONE_MAP,
        "hf_cone_map",
        "texture_2d<f32>, RG32Float",
        "cone.wgsl",
    ),
    (
        b::QDM_MAP,
        "hf_qdm_map",
        "texture_2d<f32>, RGBA32Float",
        "qdm.wgsl",
    ),
    (
        b::RELAXED_MAP,
        "hf_relaxed_map",
        "texture_2d<f32>, R32Float",
        "relaxed.wgsl",
    ),
    (
        b::CC_MAP,
        "hf_cc_map",
        "texture_2d<u32>, Rg8Uint",
        "cc.wgsl",
    ),
    (b::CC, "hf_cc", "uniform CcParams", "cc.wgsl"),
    (
        b::RADIUS_MAP,
        "hf_radius_map",
        "texture_2d<u32>, R8Uint",
        "radius.wgsl",
    ),
    (b::WORLD, "hf_world", "uniform WorldParams", "world.wgsl"),
    (
        b::PYRAMID_OUT,
        "hf_pyramid_out",
        "storage array<f32>, read_write",
        "bake_maxmip.wgsl",
    ),
    (
        b::MAXMIP_PASS,
        "hf_maxmip_pass",
        "uniform MaxMipPass",
        "bake_maxmip.wgsl",
    ),
    (
        b::NBUFFER,
        "hf_nbuffer",
        "storage array<f32>",
        "bake_nbuffer.wgsl, bake_safety.wgsl",
    ),
    (
        b::NBUFFER_PASS,
        "hf_nbuffer_pass",
        "uniform NbufferPass",
        "bake_nbuffer.wgsl",
    ),
    (
        b::SAFETY_SCRATCH,
        "hf_safety_scratch",
        "storage array<f32>, read_write",
        "bake_safety.wgsl",
    ),
    (
        b::SAFETY_OUT,
        "hf_safety_out",
        "storage array<u32>, read_write",
        "bake_safety.wgsl",
    ),
    (
        b::SAFETY_PASS,
        "hf_safety_pass",
        "uniform SafetyBakePass",
        "bake_safety.wgsl",
    ),
    (
        b::OCCLUDERS,
        "hf_occluders",
        "texture_2d<f32>, RGBA32Float, 3n x 1",
        "safety.wgsl",
    ),
];

/// The ray classes by the names of their constants (`HF_RAY_CLASS_*`, `HF_RAYS_*`).
const RAY_CLASSES: [(&str, RayClass); 4] = [
    ("X_POS", RayClass::XPos),
    ("X_NEG", RayClass::XNeg),
    ("Y_POS", RayClass::YPos),
    ("Y_NEG", RayClass::YNeg),
];

/// A `u32` constant.
fn uint(name: String, v: u32) -> Line {
    Line::Const(name, Ty::U32, format!("{v}u"))
}

/// `(NAME, value)` pairs of a group of constants.
fn named<const N: usize>(consts: [(&str, u32); N]) -> Vec<(String, u32)> {
    consts.map(|(name, v)| (name.to_string(), v)).to_vec()
}

/// The shared constants, in file order.
fn table() -> Vec<Line> {
    let upper = |s: &str| s.to_uppercase().replace('-', "_");
    let c = |s: &str| Line::Comment(s.to_string());
    let seg_pad = format!("{SAFETY_SEG_PAD:?}");
    // Groups of `u32` constants `{prefix}_{NAME}`, each after a blank line and its
    // title, then the lines that follow the group.
    let groups = [
        (
            "Surfaces (hfcast::Surface, hf_surface).",
            "HF_SURFACE",
            Surface::ALL.map(|s| (upper(s.name()), s as u32)).to_vec(),
            vec![],
        ),
        (
            "Hit and trace flags (hfcast::Flags, HF_FLAG_*).",
            "HF_FLAG",
            named([
                ("ORIGIN_INSIDE", Flags::ORIGIN_INSIDE.0),
                ("SIDE", Flags::SIDE.0),
                ("WALL", Flags::WALL.0),
                ("BUDGET_EXHAUSTED", Flags::BUDGET_EXHAUSTED.0),
            ]),
            vec![],
        ),
        (
            "Ray classes (hfcast::RayClass).",
            "HF_RAY_CLASS",
            named(RAY_CLASSES.map(|(name, class)| (name, class as u32))),
            vec![],
        ),
        (
            "Ray-class sets (hfcast::scene::RayClasses, the C API's HF_RAYS_*): bit 1 << class;\n\
             the classes a safety-distance or cylinder-cone map holds (hf_safety_classes,\n\
             hf_cc_classes): n of them, texel (i, j) of a class at row n j + its slot.",
            "HF_RAYS",
            RAY_CLASSES
                .map(|(name, class)| (name.to_string(), 1 << class as u32))
                .into_iter()
                .chain([("ALL".to_string(), u32::from(RayClasses::ALL.0))])
                .collect(),
            vec![],
        ),
        (
            "Methods (hf_method).",
            "HF_METHOD",
            MethodKind::ALL
                .map(|m| (upper(m.name()), m as u32))
                .to_vec(),
            vec![],
        ),
        (
            "Safety-distance map layouts (hf_safety_variant, hfcast::safety::Variant).",
            "HF_SAFETY",
            named([
                ("DIRECTIONAL", SafetyVariant::Directional as u32),
                ("ISOTROPIC", SafetyVariant::Isotropic as u32),
            ]),
            vec![
                c("Texel segment widening of the bake (hfcast::safety::SEG_PAD)."),
                Line::Const("HF_SAFETY_SEG_PAD".into(), Ty::F32, seg_pad),
                c("Cylinder-cone slope code meaning \"no cone\" (hfcast::safety::cc::NO_CONE)."),
                uint("HF_CC_NO_CONE".into(), CC_NO_CONE),
            ],
        ),
        (
            "How a traced span begins (hfcast::dda::Entry): Span.entry.",
            "HF_ENTRY",
            named([
                ("START", ENTRY_START),
                ("SIDE", ENTRY_SIDE),
                ("TOP", ENTRY_TOP),
            ]),
            vec![],
        ),
    ];
    let mut t = Vec::new();
    for (title, prefix, consts, after) in groups {
        t.push(c(""));
        t.extend(title.lines().map(c));
        t.extend(
            consts
                .into_iter()
                .map(|(name, v)| uint(format!("{prefix}_{name}"), v)),
        );
        t.extend(after);
    }
    t.extend([
        c(""),
        c("Sizes and texture layouts."),
        c("Largest width or height of a field (hfcast::field::MAX_SIDE)."),
        uint("HF_MAX_SIDE".into(), hfcast::field::MAX_SIDE),
        c("Most levels of a maximum-mipmap pyramid (hfcast::maxmip::MAX_LEVELS)."),
        Line::Const("HF_MAX_LEVELS".into(), Ty::I32, MAX_LEVELS.to_string()),
        c("Width of the R32F texture holding the pyramid buffer: texel k at"),
        c("(k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH)."),
        Line::Const(
            "HF_PYRAMID_TEX_WIDTH".into(),
            Ty::I32,
            PYRAMID_TEX_WIDTH.to_string(),
        ),
    ]);
    t
}

/// The shared file of `lang`.
fn render(lang: Lang) -> String {
    let ext = lang.ext();
    let lang_name = match lang {
        Lang::Glsl => "GLSL",
        Lang::Wgsl => "WGSL",
    };
    let mut s = format!(
        "// hfcast_shared.{ext}: the constants and texture layouts the {lang_name} ports share with\n\
         // the Rust core and the C API. Generated from Rust by {ext}_shared() in\n\
         // shaders/src/shared.rs: do not edit; regenerate with\n\
         // HFCAST_BLESS=1 cargo test -p hfcast-shaders (a test fails when this file drifts).\n"
    );
    if lang == Lang::Wgsl {
        s.push_str(
            "//\n// Resource bindings, all in @group(0), fixed so that any set of files composes:\n",
        );
        writeln!(
            s,
            "//   {:<8} {:<15} {:<37} declared in",
            "binding", "name", "type"
        )
        .unwrap();
        for (b, name, ty, file) in WGSL_BINDINGS {
            writeln!(s, "//   {b:<8} {name:<15} {ty:<38} {file}").unwrap();
        }
        let (impostor, last) = ((b::FIELD_RANGES, b::VIEW_PROJ), b::RESERVED_UP_TO);
        let reserved = format!(
            "Bindings {} to {} (the impostor shaders') and the others up\n\
             // to {last} of group 0 are",
            impostor.0, impostor.1
        );
        s.push_str(&format!(
            "// {reserved} reserved; a caller's own resources go in group 1\n\
             // or later. Textures are read with textureLoad only (never sampled). Scene-level\n\
             // choices are override constants: hf_surface, hf_safety_variant,\n\
             // hf_safety_classes, hf_cc_classes, hf_rays_exterior, hf_rays_max_view_angle,\n\
             // hf_occluder_count.\n"
        ));
    }
    for line in table() {
        match line {
            Line::Comment(c) if c.is_empty() => s.push('\n'),
            Line::Comment(c) => writeln!(s, "// {c}").unwrap(),
            Line::Const(name, ty, v) => {
                let t = match (lang, ty) {
                    (Lang::Glsl, Ty::U32) => "uint",
                    (Lang::Glsl, Ty::I32) => "int",
                    (Lang::Glsl, Ty::F32) => "float",
                    (Lang::Wgsl, Ty::U32) => "u32",
                    (Lang::Wgsl, Ty::I32) => "i32",
                    (Lang::Wgsl, Ty::F32) => "f32",
                };
                match lang {
                    Lang::Glsl => writeln!(s, "const {t} {name} = {v};").unwrap(),
                    Lang::Wgsl => writeln!(s, "const {name}: {t} = {v};").unwrap(),
                }
            }
        }
    }
    s
}

/// The text of `shaders/glsl/hfcast_shared.glsl`, generated from the Rust values (the
/// test `shared_files_are_current` fails when the committed file differs;
/// `HFCAST_BLESS=1 cargo test -p hfcast-shaders` rewrites it).
pub fn glsl_shared() -> String {
    render(Lang::Glsl)
}

/// The text of `shaders/wgsl/hfcast_shared.wgsl`, with the table of the fixed
/// resource bindings; checked and blessed as [`glsl_shared`].
pub fn wgsl_shared() -> String {
    render(Lang::Wgsl)
}
