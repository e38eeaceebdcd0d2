//! The GLSL ports of the marches, as source text the caller compiles.

use crate::hf_result;
use crate::{guard, hf_method, method_of, ptr};
use std::ffi::c_char;

/// `(name, text)` of files of `shaders/glsl`, compiled in.
macro_rules! glsl_files {
    ($($name:literal),* $(,)?) => {
        [$(($name, include_str!(concat!("../../shaders/glsl/", $name)))),*]
    };
}

/// The files of `shaders/glsl`, in the order a method's source concatenates them.
pub(crate) const FILES: [(&str, &str); 22] = glsl_files![
    "hfcast_shared.glsl",
    "math.glsl",
    "ray.glsl",
    "field.glsl",
    "surface.glsl",
    "dda.glsl",
    "search.glsl",
    "maxmip.glsl",
    "safety.glsl",
    "cone.glsl",
    "qdm.glsl",
    "relaxed.glsl",
    "cc.glsl",
    "method_exact.glsl",
    "method_linear_binary.glsl",
    "method_linear_secant.glsl",
    "method_maxmip.glsl",
    "method_safety.glsl",
    "method_cone.glsl",
    "method_qdm.glsl",
    "method_relaxed.glsl",
    "method_cc.glsl",
];

/// The file names making up the source of `method`: the shared constants, the core
/// modules the march uses (in dependency order), and the method's `hf_trace`.
pub fn parts(method: hf_method) -> &'static [&'static str] {
    match method {
        hf_method::HF_METHOD_EXACT => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "method_exact.glsl",
        ],
        hf_method::HF_METHOD_LINEAR_BINARY => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "search.glsl",
            "method_linear_binary.glsl",
        ],
        hf_method::HF_METHOD_LINEAR_SECANT => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "search.glsl",
            "method_linear_secant.glsl",
        ],
        hf_method::HF_METHOD_MAXMIP => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "maxmip.glsl",
            "method_maxmip.glsl",
        ],
        hf_method::HF_METHOD_SAFETY => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "safety.glsl",
            "method_safety.glsl",
        ],
        hf_method::HF_METHOD_CONE => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "cone.glsl",
            "method_cone.glsl",
        ],
        hf_method::HF_METHOD_RELAXED => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "relaxed.glsl",
            "method_relaxed.glsl",
        ],
        hf_method::HF_METHOD_QDM => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "cone.glsl",
            "qdm.glsl",
            "method_qdm.glsl",
        ],
        hf_method::HF_METHOD_CC => &[
            "hfcast_shared.glsl",
            "math.glsl",
            "ray.glsl",
            "field.glsl",
            "surface.glsl",
            "dda.glsl",
            "safety.glsl",
            "cc.glsl",
            "method_cc.glsl",
        ],
    }
}

/// The GLSL source of `method`: its files concatenated (no `#version` line).
pub fn source(method: hf_method) -> String {
    let mut s = String::new();
    for name in parts(method) {
        let (_, text) = FILES.iter().find(|(n, _)| n == name).expect("listed file");
        s.push_str(&format!("// ---- {name}\n"));
        s.push_str(text);
        if !text.ends_with('\n') {
            s.push('\n');
        }
    }
    s
}

/// How the GLSL ports encode `dda::Entry` (a Rust enum with data): `Span::entry`.
pub(crate) const ENTRY_START: u32 = 0;
/// `Entry::Side`; the normal is in `Span::entry_normal`.
pub(crate) const ENTRY_SIDE: u32 = 1;
/// `Entry::Top`.
pub(crate) const ENTRY_TOP: u32 = 2;

/// The text of `shaders/glsl/hfcast_shared.glsl`: every constant and texture-layout
/// number the GLSL ports share with the Rust core and the C API, generated from the
/// Rust values (the unit test `glsl_shared_is_current` fails when the committed file
/// differs; `HFCAST_BLESS=1 cargo test -p hfcast-capi` rewrites it).
pub fn glsl_shared() -> String {
    use hfcore::{Flags, RayClass, Surface};
    let upper = |s: &str| s.to_uppercase().replace('-', "_");
    let mut s = String::from(
        "// hfcast_shared.glsl: the constants and texture layouts the GLSL ports share with\n\
         // the Rust core and the C API. Generated from Rust by glsl_shared() in\n\
         // capi/src/shader.rs: do not edit; regenerate with\n\
         // HFCAST_BLESS=1 cargo test -p hfcast-capi (a test fails when this file drifts).\n",
    );
    s.push_str("\n// Surfaces (hfcast::Surface, hf_surface).\n");
    for surface in Surface::ALL {
        let name = upper(surface.name());
        s.push_str(&format!(
            "const uint HF_SURFACE_{name} = {}u;\n",
            surface as u32
        ));
    }
    s.push_str("\n// Hit and trace flags (hfcast::Flags, HF_FLAG_*).\n");
    for (name, flag) in [
        ("ORIGIN_INSIDE", Flags::ORIGIN_INSIDE),
        ("SIDE", Flags::SIDE),
        ("WALL", Flags::WALL),
        ("BUDGET_EXHAUSTED", Flags::BUDGET_EXHAUSTED),
    ] {
        s.push_str(&format!("const uint HF_FLAG_{name} = {}u;\n", flag.0));
    }
    s.push_str("\n// Ray classes (hfcast::RayClass).\n");
    for (name, class) in [
        ("X_POS", RayClass::XPos),
        ("X_NEG", RayClass::XNeg),
        ("Y_POS", RayClass::YPos),
        ("Y_NEG", RayClass::YNeg),
    ] {
        s.push_str(&format!(
            "const uint HF_RAY_CLASS_{name} = {}u;\n",
            class as u8
        ));
    }
    s.push_str("\n// Methods (hf_method).\n");
    for m in crate::METHODS {
        let name = upper(m.name());
        s.push_str(&format!("const uint HF_METHOD_{name} = {}u;\n", m as u32));
    }
    s.push_str("\n// Safety-distance map layouts (hf_safety_variant, hfcast::safety::Variant).\n");
    for (name, v) in [
        (
            "DIRECTIONAL",
            crate::safety::hf_safety_variant::HF_SAFETY_DIRECTIONAL,
        ),
        (
            "ISOTROPIC",
            crate::safety::hf_safety_variant::HF_SAFETY_ISOTROPIC,
        ),
    ] {
        s.push_str(&format!("const uint HF_SAFETY_{name} = {}u;\n", v as u32));
    }
    s.push_str(&format!(
        "// Texel segment widening of the bake (hfcast::safety::SEG_PAD).\n\
         const float HF_SAFETY_SEG_PAD = {:?};\n",
        hfcore::safety::SEG_PAD as f32
    ));
    s.push_str(&format!(
        "// Cylinder-cone slope code meaning \"no cone\" (hfcast::safety::cc::NO_CONE).\n\
         const uint HF_CC_NO_CONE = {}u;\n",
        hfcore::safety::cc::NO_CONE
    ));
    s.push_str("\n// How a traced span begins (hfcast::dda::Entry): Span.entry.\n");
    for (name, v) in [
        ("START", ENTRY_START),
        ("SIDE", ENTRY_SIDE),
        ("TOP", ENTRY_TOP),
    ] {
        s.push_str(&format!("const uint HF_ENTRY_{name} = {v}u;\n"));
    }
    s.push_str("\n// Sizes and texture layouts.\n");
    s.push_str(&format!(
        "// Largest width or height of a field (hfcast::field::MAX_SIDE).\n\
         const uint HF_MAX_SIDE = {}u;\n",
        hfcore::field::MAX_SIDE
    ));
    s.push_str(&format!(
        "// Most levels of a maximum-mipmap pyramid (hfcast::maxmip::MAX_LEVELS).\n\
         const int HF_MAX_LEVELS = {};\n",
        hfcore::maxmip::MAX_LEVELS
    ));
    s.push_str(&format!(
        "// Width of the R32F texture holding the pyramid buffer: texel k at\n\
         // (k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH).\n\
         const int HF_PYRAMID_TEX_WIDTH = {};\n",
        crate::HF_PYRAMID_TEX_WIDTH
    ));
    s
}

/// Writes the length in bytes of `hf_shader_source(method)`, including its NUL
/// terminator, to `*out_len`: the buffer size to pass. Thread safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_source_len(method: u32, out_len: *mut usize) -> hf_result {
    guard(|| {
        let out = ptr::out(out_len)?;
        let m = method_of(method)?;
        // SAFETY: the caller promises `out_len` is writable.
        unsafe { out.set(source(m).len() + 1) };
        Ok(())
    })
}

/// Writes the GLSL 3.30 source of `method` (an `hf_method`) into `buf` as a
/// NUL-terminated string and its length without the NUL to `*out_written`; `buf_len`
/// must be at least `hf_shader_source_len`. The source has no `#version` line: put
/// `#version 330 core` (or later) first, then this, then your `main`, which calls
/// `Trace hf_trace(Query q)` (a ray in grid space, as `hf_ray`; `Trace` mirrors
/// `hf_hit`). The functions mirror the Rust core one for one (`dda::trace` is
/// `dda_trace`, …) and give the same answers bit for bit on the rays tested. The
/// uniforms it declares: `hf_heights` (`R32F`, W × H, texel (i, j) = sample (i, j), read
/// with `texelFetch` only), `hf_size` = (W, H), `hf_height_range` = (min, max) from
/// `hf_field_get_info`; `hf_surface` (exact, search and maxmip methods; the others
/// trace the triangle surface); `hf_linear_steps`, `hf_binary_steps` (search
/// methods); cone and QDM: `hf_max_iter`, `hf_cone_map` (`RG32F`) or `hf_qdm_map`
/// (`RGBA32F`), (W − 1) × (H − 1) texels; relaxed: `hf_cone_steps`,
/// `hf_binary_steps`, `hf_relaxed_map` (`R32F`, W × H); maxmip: `hf_pyramid` (`R32F`, the
/// `hf_maxmip_bake` buffer in rows of `HF_PYRAMID_TEX_WIDTH` texels), `hf_levels`,
/// `hf_level_dims[]`, `hf_level_offset[]` (from `hf_maxmip_levels`); safety:
/// `hf_safety_map` (`RGBA8UI` directional or `R8UI` isotropic, W × H),
/// `hf_safety_variant`; cylinder–cone: `hf_cc_map` (`RGBA8UI`, 4W × H), `hf_cc_cap`,
/// `hf_cc_zmin`, `hf_cc_zstep`, `hf_cc_zspan` (from `hf_cc_frame`). Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_shader_source(
    method: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `buf` is writable for `buf_len` bytes.
        let buf = unsafe { ptr::slice_mut(buf, buf_len) }?;
        let written = ptr::out(out_written)?;
        let m = method_of(method)?;
        // SAFETY: the caller promises `out_written` is writable.
        unsafe { ptr::write_c_string(&source(m), buf, written) }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glsl_shared_is_current() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shaders/glsl/hfcast_shared.glsl"
        );
        let fresh = glsl_shared();
        if std::env::var_os("HFCAST_BLESS").is_some() {
            std::fs::write(path, &fresh).expect("write hfcast_shared.glsl");
            return;
        }
        let committed = std::fs::read_to_string(path).unwrap_or_default();
        assert!(
            committed == fresh,
            "shaders/glsl/hfcast_shared.glsl is out of date: regenerate it with \
             `HFCAST_BLESS=1 cargo test -p hfcast-capi` and commit it"
        );
        // The compiled-in copy is the committed one.
        assert_eq!(FILES[0].1, committed);
    }

    #[test]
    fn every_method_has_a_source_with_hf_trace() {
        for m in crate::METHODS {
            let s = source(m);
            assert_eq!(
                s.matches("Trace hf_trace(Query q)").count(),
                1,
                "{}",
                m.name()
            );
            assert!(!s.contains("#version"));
        }
    }
}
