//! # hfcast C API
//!
//! The C ABI of the `hfcast` core, built as `libhfcast.a` and `libhfcast.so`; the
//! header `include/hfcast.h` is generated from this crate by cbindgen and checked for
//! drift by `tests/header.rs` (regenerate with `HFCAST_BLESS=1 cargo test -p hfcast-capi`).
//!
//! Conventions (as rustls-ffi and meshoptimizer): every symbol starts with `hf_`; every
//! function returns an [`hf_result`] (`HF_OK` = 0); enums cross the boundary as
//! `uint32_t` and are checked; every pointer is checked for NULL (and alignment);
//! every function runs behind a panic boundary; outputs come last, each buffer
//! followed by its length in elements; outputs are written only on success.
//!
//! Cargo features (`maxmip`, `safety`, `cone`, `qdm`, `relaxed`, `search`; default
//! `all-methods`) leave whole methods out: their functions are not built, the header
//! of that build (`cargo run -p hfcast-capi --no-default-features --features … --example
//! header`) does not declare them, [`hf_build_has_method`] says 0, and functions taking
//! a method number return `HF_ERR_NOT_BUILT` for them.
//!
//! `unsafe` is confined to turning C pointers into references and slices
//! (`ptr`) and to the owned samples of [`hf_field`]; each block says why it holds.

// The C names (`hf_field`, `hf_ray`, …) are the API.
#![allow(non_camel_case_types)]

pub mod bake;
pub mod camera;
pub mod detail;
#[cfg(all(test, feature = "all-methods"))]
mod extremes;
mod features;
pub mod field;
#[cfg(feature = "safety")]
pub mod gpu_bake;
pub mod impostor;
pub mod ktx2;
pub mod mapdesc;
pub mod maps;
#[cfg(feature = "maxmip")]
pub mod maxmip;
pub mod occluder;
mod par;
mod ptr;
pub mod scene;
pub mod shader;
pub mod trace;

use std::ffi::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

pub use field::hf_field;
use hfcore::scene::MethodKind;

/// Result code of every `hf_` function. `HF_OK` is 0; every other value is an error,
/// and a function that returns one has written nothing to its outputs.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_result {
    /// Success.
    HF_OK = 0,
    /// A pointer argument is NULL.
    HF_ERR_NULL_POINTER = 1,
    /// A pointer argument is not aligned for its element type.
    HF_ERR_MISALIGNED_POINTER = 2,
    /// A size is zero where it must not be (a mesh without triangles), out of range (a
    /// width, height or impostor side below 2 or above 2^24, a row stride below the
    /// width), or overflows `size_t`.
    HF_ERR_INVALID_SIZE = 3,
    /// An input buffer holds fewer elements than the other arguments require, or an
    /// output buffer is too small for the result (query the size first).
    HF_ERR_BUFFER_TOO_SMALL = 4,
    /// A height, a depth scale, a vertex position or an impostor layout's centre or half
    /// side is NaN or infinite.
    HF_ERR_NOT_FINITE = 5,
    /// A ray is invalid: NaN or infinite origin or direction, zero direction, `t_min`
    /// not finite, `t_max` NaN or −∞, or `t_min > t_max`.
    HF_ERR_INVALID_RAY = 6,
    /// An enum argument (surface, method, result code) has no such value.
    HF_ERR_INVALID_ENUM = 7,
    /// A rectangle is empty, reversed or reaches outside the field.
    HF_ERR_INVALID_RECT = 8,
    /// Another argument is out of range (a pyramid level or row range, a step count
    /// of zero, a vertex index past the vertices, a mesh without extent, an impostor
    /// face over 5 or apex not over 1, a singular matrix).
    HF_ERR_INVALID_ARGUMENT = 9,
    /// Memory could not be allocated.
    HF_ERR_OUT_OF_MEMORY = 10,
    /// The library panicked (a bug); the call had no effect on its outputs and printed
    /// nothing: the first `hf_` call installs a process-wide panic hook that is silent
    /// for the library's own panics and passes every other panic to the hook installed
    /// before it (`hf_last_error_detail` has the panic's message).
    HF_ERR_PANIC = 11,
    /// The method (or another part the call needs) was left out of this build of the
    /// library by its cargo features (see `hf_build_has_method`).
    HF_ERR_NOT_BUILT = 12,
    /// A baked map does not belong to the call: it is another method's map, was baked
    /// for a field of another size or other heights, with another cap or ray-class
    /// set, or carries no valid descriptor (see `HF_MAP_DESC_BYTES`).
    HF_ERR_MAP_MISMATCH = 13,
    /// A baked map was baked from heights the field had before an update
    /// (`hf_field_update_rect`): rebake it, or refresh a pyramid with
    /// `hf_maxmip_update_rect` over every updated rectangle.
    HF_ERR_STALE_MAP = 14,
}

use hf_result::*;

/// Every result code, in value order.
const RESULTS: [hf_result; 15] = [
    HF_OK,
    HF_ERR_NULL_POINTER,
    HF_ERR_MISALIGNED_POINTER,
    HF_ERR_INVALID_SIZE,
    HF_ERR_BUFFER_TOO_SMALL,
    HF_ERR_NOT_FINITE,
    HF_ERR_INVALID_RAY,
    HF_ERR_INVALID_ENUM,
    HF_ERR_INVALID_RECT,
    HF_ERR_INVALID_ARGUMENT,
    HF_ERR_OUT_OF_MEMORY,
    HF_ERR_PANIC,
    HF_ERR_NOT_BUILT,
    HF_ERR_MAP_MISMATCH,
    HF_ERR_STALE_MAP,
];

impl hf_result {
    /// The code with value `v`, if any.
    pub fn from_u32(v: u32) -> Option<hf_result> {
        RESULTS.get(v as usize).copied()
    }

    /// A short English description (ASCII, no trailing period).
    pub fn message(self) -> &'static str {
        match self {
            HF_OK => "success",
            HF_ERR_NULL_POINTER => "a pointer argument is NULL",
            HF_ERR_MISALIGNED_POINTER => "a pointer argument is misaligned for its type",
            HF_ERR_INVALID_SIZE => "a size is zero, out of range or overflows",
            HF_ERR_BUFFER_TOO_SMALL => "a buffer is too small",
            HF_ERR_NOT_FINITE => {
                "a height, depth scale, position or layout value is NaN or infinite"
            }
            HF_ERR_INVALID_RAY => {
                "invalid ray: NaN or infinite origin or direction, zero direction, or bad t range"
            }
            HF_ERR_INVALID_ENUM => "an enum argument has an unknown value",
            HF_ERR_INVALID_RECT => "a rectangle is empty, reversed or outside the field",
            HF_ERR_INVALID_ARGUMENT => "an argument is out of range",
            HF_ERR_OUT_OF_MEMORY => "out of memory",
            HF_ERR_PANIC => "internal error: the library panicked",
            HF_ERR_NOT_BUILT => "this build of the library leaves that method out",
            HF_ERR_MAP_MISMATCH => {
                "the map belongs to another field, method, size, cap or class set"
            }
            HF_ERR_STALE_MAP => "the map was baked before the field's last update",
        }
    }
}

impl From<hfcore::FieldError> for hf_result {
    fn from(e: hfcore::FieldError) -> Self {
        use hfcore::FieldError as E;
        let index = match e {
            E::NotFinite { index } => Some(index),
            _ => None,
        };
        let code = match e {
            E::TooSmall | E::TooLarge | E::StrideTooSmall | E::SizeOverflow => HF_ERR_INVALID_SIZE,
            E::SliceTooShort { .. } | E::OutputTooShort { .. } => HF_ERR_BUFFER_TOO_SMALL,
            E::NotFinite { .. } => HF_ERR_NOT_FINITE,
            E::BadRect => HF_ERR_INVALID_RECT,
        };
        detail::fail_at(code, index, e)
    }
}

impl From<hfcore::RayError> for hf_result {
    fn from(e: hfcore::RayError) -> Self {
        detail::fail(HF_ERR_INVALID_RAY, e)
    }
}

impl From<hfcore::buffer::BufferError> for hf_result {
    fn from(e: hfcore::buffer::BufferError) -> Self {
        use hfcore::buffer::BufferError as E;
        let code = match e {
            E::TooShort { .. } => HF_ERR_BUFFER_TOO_SMALL,
            E::BadRows => HF_ERR_INVALID_ARGUMENT,
            E::BadRect => HF_ERR_INVALID_RECT,
        };
        detail::fail(code, e)
    }
}

/// The panic boundary every export runs behind: `Ok` → `HF_OK`, `Err(code)` → `code`,
/// a panic → `HF_ERR_PANIC`, printed by no panic hook (`detail::quietly`). The
/// outermost boundary of a thread starts a fresh error detail; an error that recorded
/// none gets its code's message, a panic its message.
pub(crate) fn guard(f: impl FnOnce() -> Result<(), hf_result>) -> hf_result {
    detail::quietly(|outermost| {
        if outermost {
            detail::clear();
        }
        match catch_unwind(AssertUnwindSafe(f)) {
            Ok(Ok(())) => HF_OK,
            Ok(Err(code)) if detail::is_set() => code,
            Ok(Err(code)) => detail::fail(code, code.message()),
            Err(payload) => {
                let text = (payload.downcast_ref::<&str>().copied())
                    .or(payload.downcast_ref::<String>().map(String::as_str))
                    .unwrap_or("");
                detail::fail(
                    HF_ERR_PANIC,
                    format_args!("{}: {text}", HF_ERR_PANIC.message()),
                )
            }
        }
    })
}

/// The panic boundary alone, leaving the error detail as it is (the detail queries).
pub(crate) fn guard_keeping_detail(f: impl FnOnce() -> Result<(), hf_result>) -> hf_result {
    detail::keeping(|| {
        detail::quietly(|_| match catch_unwind(AssertUnwindSafe(f)) {
            Ok(Ok(())) => HF_OK,
            Ok(Err(code)) => code,
            Err(_) => HF_ERR_PANIC,
        })
    })
}

/// Checks a field size given to a size query: 2 to `HF_MAX_SIDE` on both sides.
pub(crate) fn check_size(width: u32, height: u32) -> Result<(), hf_result> {
    let ok = |n: u32| (2..=HF_MAX_SIDE).contains(&n);
    if !ok(width) || !ok(height) {
        return Err(detail::fail(
            HF_ERR_INVALID_SIZE,
            format_args!("width {width}, height {height}: each must be 2 to {HF_MAX_SIDE}"),
        ));
    }
    Ok(())
}

/// How many methods there are: the `hf_method` values are 0 to `HF_METHOD_COUNT − 1`.
pub const HF_METHOD_COUNT: u32 = 11;
const _: () = assert!(HF_METHOD_COUNT as usize == hfcore::scene::MethodKind::ALL.len());

/// How many surfaces there are: the `hf_surface` values are 0 to `HF_SURFACE_COUNT − 1`.
pub const HF_SURFACE_COUNT: u32 = 6;
const _: () = assert!(HF_SURFACE_COUNT as usize == hfcore::Surface::ALL.len());

/// Checks a surface passed as `uint32_t`.
pub(crate) fn surface_of(v: u32) -> Result<hfcore::Surface, hf_result> {
    hfcore::Surface::ALL
        .get(v as usize)
        .copied()
        .ok_or_else(|| {
            detail::fail(
                HF_ERR_INVALID_ENUM,
                format_args!("surface: {v} is not an hf_surface"),
            )
        })
}

/// Checks a method passed as `uint32_t` (an `hf_method`, the registry's number).
pub(crate) fn method_of(v: u32) -> Result<MethodKind, hf_result> {
    MethodKind::from_u32(v).ok_or_else(|| {
        detail::fail(
            HF_ERR_INVALID_ENUM,
            format_args!("method: {v} is not an hf_method"),
        )
    })
}

/// Whether this build of the library has `method` (its cargo feature, the registry's,
/// was on in the C API).
pub(crate) fn built(method: MethodKind) -> bool {
    let feature = method.info().feature;
    feature.is_none_or(|f| features::feature_on(f) == Some(true))
}

/// Checks a method passed as `uint32_t` and that this build has it: an unknown value
/// is `HF_ERR_INVALID_ENUM`, a method left out of the build `HF_ERR_NOT_BUILT`.
pub(crate) fn built_method_of(v: u32) -> Result<MethodKind, hf_result> {
    let m = method_of(v)?;
    if built(m) {
        Ok(m)
    } else {
        Err(detail::fail(
            HF_ERR_NOT_BUILT,
            format_args!("method: {} is not in this build", m.name()),
        ))
    }
}

/// Writes 1 to `*out` when this build of the library has `method` (an `hf_method`),
/// else 0: cargo features leave whole methods out (`--no-default-features --features
/// cone`), their functions are then not exported and not declared in the header of
/// that build, and the functions that take a method number answer
/// `HF_ERR_NOT_BUILT` for it. An unknown method is `HF_ERR_INVALID_ENUM`. Thread safe.
///
/// # Safety
/// `out` is NULL (an error) or valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_build_has_method(method: u32, out: *mut u32) -> hf_result {
    guard(|| {
        let out = ptr::out(out)?;
        let m = method_of(method)?;
        // SAFETY: the caller promises `out` is writable.
        unsafe { out.set(u32::from(built(m))) };
        Ok(())
    })
}

/// Writes the short lower-case name of `method` (an `hf_method`: `exact`,
/// `linear-binary`, `linear-secant`, `maxmip`, `safety`, `cone`, `relaxed`, `qdm`,
/// `cc`, `radius`, as the CLI and the report spell them) into `buf` as a
/// NUL-terminated ASCII string and its length without the NUL into `*out_written`;
/// 32 bytes always suffice. Methods left out of this build have names too. An unknown
/// method is `HF_ERR_INVALID_ENUM`. Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` is NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_method_name(
    method: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { write_name(|| Ok(method_of(method)?.name()), buf, buf_len, out_written) }
}

/// Writes the short lower-case name of `surface` (an `hf_surface`: `triangles`,
/// `bilinear`, `height-planes`, `corner-planes`, `view-linear`, `qu-triangles`) as
/// `hf_method_name`
/// does. Thread safe.
///
/// # Safety
/// As `hf_method_name`.
#[no_mangle]
pub unsafe extern "C" fn hf_surface_name(
    surface: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe {
        write_name(
            || Ok(surface_of(surface)?.name()),
            buf,
            buf_len,
            out_written,
        )
    }
}

/// Shared body of the name queries: `name()` (its error first), written as a C string.
///
/// # Safety
/// As `hf_method_name`.
unsafe fn write_name(
    name: impl FnOnce() -> Result<&'static str, hf_result>,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    guard(|| {
        let name = name()?;
        // SAFETY: the caller promises `buf` is valid for `buf_len` bytes.
        let buf = unsafe { ptr::slice_mut(buf, buf_len) }?;
        let written = ptr::out(out_written)?;
        // SAFETY: the caller promises `out_written` is valid for one `size_t`.
        unsafe { ptr::write_c_string(name, buf, written) }
    })
}

/// Hit flag: the ray starts under the surface; the hit is at `t_min`.
pub const HF_FLAG_ORIGIN_INSIDE: u32 = 1;
/// Hit flag: the ray enters the footprint through a side wall below the surface.
pub const HF_FLAG_SIDE: u32 = 2;
/// Hit flag: the hit is on a vertical step of a discontinuous surface.
pub const HF_FLAG_WALL: u32 = 4;
/// Trace flag: an approximate method ran out of its step budget.
pub const HF_FLAG_BUDGET_EXHAUSTED: u32 = 8;

/// Largest width or height of a field (2^24: grid coordinates stay exact in `float`).
pub const HF_MAX_SIDE: u32 = 16777216;
#[cfg(feature = "maxmip")]
/// Most levels a maximum-mipmap pyramid has.
pub const HF_MAX_LEVELS: u32 = 25;
#[cfg(feature = "maxmip")]
/// Width of the 2D `R32F` texture the GLSL maxmip port reads the pyramid from: pyramid
/// texel `k` (the index into the pyramid `hf_bake` fills) is texel
/// `(k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH)`; the last row is padded.
pub const HF_PYRAMID_TEX_WIDTH: u32 = 4096;

/// Writes the library version. The same numbers as the `HFCAST_VERSION_*` macros of
/// the header the caller compiled against; compare them to detect a mismatched
/// library. Thread safe.
///
/// # Safety
/// Each pointer is NULL (an error) or valid for writing one `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_version(
    out_major: *mut u32,
    out_minor: *mut u32,
    out_patch: *mut u32,
) -> hf_result {
    guard(|| {
        let (major, minor, patch) = (
            ptr::out(out_major)?,
            ptr::out(out_minor)?,
            ptr::out(out_patch)?,
        );
        let v = |s: &str| s.parse::<u32>().unwrap_or(0);
        // SAFETY: the caller promises each pointer is valid for one `uint32_t`.
        unsafe {
            major.set(v(env!("CARGO_PKG_VERSION_MAJOR")));
            minor.set(v(env!("CARGO_PKG_VERSION_MINOR")));
            patch.set(v(env!("CARGO_PKG_VERSION_PATCH")));
        }
        Ok(())
    })
}

/// Writes the message of result code `code` into `buf` as a NUL-terminated ASCII
/// string and its length without the NUL into `*out_written`. `buf_len` (bytes) must
/// be at least the length plus one: 128 bytes always suffice. An unknown `code` is
/// `HF_ERR_INVALID_ENUM`. Thread safe.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` is NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_error_message(
    code: u32,
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    let message = || {
        Ok(hf_result::from_u32(code)
            .ok_or(HF_ERR_INVALID_ENUM)?
            .message())
    };
    // SAFETY: the caller's promises, passed on.
    unsafe { write_name(message, buf, buf_len, out_written) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_dense_and_have_messages() {
        for (i, code) in RESULTS.iter().enumerate() {
            assert_eq!(*code as u32, i as u32);
            assert_eq!(hf_result::from_u32(i as u32), Some(*code));
            assert!(code.message().len() < 128 && code.message().is_ascii());
        }
        assert_eq!(hf_result::from_u32(RESULTS.len() as u32), None);
    }

    #[test]
    fn enums_match_the_core() {
        for (i, s) in hfcore::Surface::ALL.iter().enumerate() {
            assert_eq!(*s as u32, i as u32);
            assert_eq!(surface_of(i as u32), Ok(*s));
        }
        assert_eq!(surface_of(HF_SURFACE_COUNT), Err(HF_ERR_INVALID_ENUM));
        use hfcore::Flags;
        assert_eq!(HF_FLAG_ORIGIN_INSIDE, Flags::ORIGIN_INSIDE.0);
        assert_eq!(HF_FLAG_SIDE, Flags::SIDE.0);
        assert_eq!(HF_FLAG_WALL, Flags::WALL.0);
        assert_eq!(HF_FLAG_BUDGET_EXHAUSTED, Flags::BUDGET_EXHAUSTED.0);
        assert_eq!(HF_MAX_SIDE, hfcore::field::MAX_SIDE);
        #[cfg(feature = "maxmip")]
        assert_eq!(HF_MAX_LEVELS as usize, hfcore::maxmip::MAX_LEVELS);
    }

    #[test]
    fn build_has_the_methods_of_its_features() {
        for m in MethodKind::ALL {
            let mut out = 7;
            // SAFETY: a valid out pointer.
            assert_eq!(unsafe { hf_build_has_method(m as u32, &mut out) }, HF_OK);
            assert_eq!(out, u32::from(built(m)));
            let expect = if built(m) {
                Ok(m)
            } else {
                Err(HF_ERR_NOT_BUILT)
            };
            assert_eq!(built_method_of(m as u32), expect);
        }
        assert!(built(MethodKind::Exact));
        assert_eq!(built(MethodKind::Cc), cfg!(feature = "safety"));
        let mut out = 0;
        // SAFETY: a valid out pointer; the method is unknown.
        let r = unsafe { hf_build_has_method(HF_METHOD_COUNT, &mut out) };
        assert_eq!(r, HF_ERR_INVALID_ENUM);
        // SAFETY: NULL is reported.
        let r = unsafe { hf_build_has_method(0, std::ptr::null_mut()) };
        assert_eq!(r, HF_ERR_NULL_POINTER);
    }

    /// Panics caught by the boundary print nothing (on the calling thread and on a
    /// bake's helper thread) and leave their message in the detail; a panic outside
    /// the library still reaches the previous hook. Run in a child process, whose
    /// stderr is read.
    #[test]
    fn caught_panics_print_nothing() {
        if std::env::var_os("HFCAST_PANIC_CHILD").is_some() {
            assert_eq!(guard(|| panic!("boom in guard")), HF_ERR_PANIC);
            let (mut buf, mut n) = ([0 as c_char; 256], 0);
            // SAFETY: a 256-byte buffer and a valid out pointer.
            let r = unsafe { detail::hf_last_error_detail(buf.as_mut_ptr(), 256, &mut n) };
            assert_eq!(r, HF_OK);
            let text: Vec<u8> = buf[..n].iter().map(|&c| c as u8).collect();
            assert_eq!(text, b"internal error: the library panicked: boom in guard");
            #[cfg(any(feature = "maxmip", feature = "safety", feature = "cone"))]
            {
                let mut out = [0u8; 64];
                let r = guard(|| {
                    par::bake_bands(64, 1, 1, 64, &mut out, |rows, _| {
                        if rows.start % 2 == 1 {
                            panic!("boom in a band");
                        }
                        Ok(())
                    })
                });
                assert_eq!(r, HF_ERR_PANIC);
            }
            let _ = std::panic::catch_unwind(|| panic!("outside the library"));
            return;
        }
        let exe = std::env::current_exe().unwrap();
        let out = std::process::Command::new(exe)
            .args([
                "--exact",
                "tests::caught_panics_print_nothing",
                "--nocapture",
            ])
            .env("HFCAST_PANIC_CHILD", "1")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        assert!(!err.contains("boom"), "{err}");
        assert!(err.contains("outside the library"), "{err}");
    }

    #[test]
    fn version_is_the_package_version() {
        let (mut a, mut b, mut c) = (9, 9, 9);
        // SAFETY: three valid out pointers.
        let r = unsafe { hf_version(&mut a, &mut b, &mut c) };
        assert_eq!(r, HF_OK);
        assert_eq!(format!("{a}.{b}.{c}"), env!("CARGO_PKG_VERSION"));
    }
}
