//! Turning C pointers into references and slices, with the checks every export makes:
//! NULL, alignment, and a byte size that fits `isize`; each failed check records its
//! error detail (name the argument with [`Named::named`]).

use crate::detail::fail;
pub(crate) use crate::detail::Named;
use crate::hf_result::{self, *};
use core::ops::Range;
use core::ptr::NonNull;
use std::ffi::c_char;

/// Checks a pointer to `len` elements: non-NULL, aligned, and `len · size_of::<T>()`
/// within `isize::MAX` (what `slice::from_raw_parts` requires).
fn check<T>(p: *const T, len: usize) -> Result<(), hf_result> {
    if p.is_null() {
        return Err(fail(HF_ERR_NULL_POINTER, "pointer is NULL"));
    }
    if !p.is_aligned() {
        let align = align_of::<T>();
        return Err(fail(
            HF_ERR_MISALIGNED_POINTER,
            format_args!("pointer is not aligned to {align} bytes"),
        ));
    }
    match len.checked_mul(size_of::<T>()) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(()),
        _ => Err(fail(
            HF_ERR_INVALID_SIZE,
            format_args!(
                "{len} elements of {} bytes exceed isize::MAX",
                size_of::<T>()
            ),
        )),
    }
}

/// The byte range of `len` elements at `p` (after [`check`]).
fn bytes<T>(p: *const T, len: usize) -> Range<usize> {
    let start = p as usize;
    start..start.saturating_add(len * size_of::<T>())
}

/// A buffer argument checked as [`slice`] checks it, before any slice of it exists:
/// its bytes and its name, for [`apart`].
pub struct Span<'n> {
    bytes: Range<usize>,
    name: &'n str,
}

/// Checks `len` elements at `p` (the argument `name`) as [`slice`] does; its span.
pub fn span<T>(p: *const T, len: usize, name: &str) -> Result<Span<'_>, hf_result> {
    check(p, len).named(name)?;
    Ok(Span {
        bytes: bytes(p, len),
        name,
    })
}

/// `HF_ERR_INVALID_ARGUMENT` ("`out` overlaps `other`") when an output (`None`: a NULL
/// optional one) shares a byte with an input or an earlier output: checked before any
/// mutable slice of them exists.
pub fn apart(ins: &[&Span], outs: &[Option<&Span>]) -> Result<(), hf_result> {
    let outs: Vec<&Span> = outs.iter().flatten().copied().collect();
    for (k, o) in outs.iter().enumerate() {
        for other in ins.iter().chain(&outs[..k]) {
            if o.bytes.start < other.bytes.end && other.bytes.start < o.bytes.end {
                return Err(fail(
                    HF_ERR_INVALID_ARGUMENT,
                    format_args!("{} overlaps {}", o.name, other.name),
                ));
            }
        }
    }
    Ok(())
}

/// A shared slice of `len` elements at `p` (the argument `name`) and a mutable slice
/// of `out_len` elements at `out` (`out_name`), each checked as by [`slice`], then for
/// overlap: bytes in common are `HF_ERR_INVALID_ARGUMENT` ("`out_name` overlaps
/// `name`"), found before either slice exists.
///
/// # Safety
/// As [`slice`] for `p` and [`slice_mut`] for `out`.
pub unsafe fn slice_and_out<'a, T, U>(
    (p, len, name): (*const T, usize, &str),
    (out, out_len, out_name): (*mut U, usize, &str),
) -> Result<(&'a [T], &'a mut [U]), hf_result> {
    let (a, b) = (span(p, len, name)?, span(out, out_len, out_name)?);
    apart(&[&a], &[Some(&b)])?;
    // SAFETY: both checked as in `slice` and `slice_mut`, and disjoint (checked), so
    // the mutable slice is exclusive by the caller's promise.
    Ok(unsafe {
        (
            core::slice::from_raw_parts(p, len),
            core::slice::from_raw_parts_mut(out, out_len),
        )
    })
}

/// A shared slice of `len` elements at `p`.
///
/// # Safety
/// When `p` is non-NULL and aligned it must be valid for reading `len` elements of `T`,
/// not written by anyone while the slice lives.
pub unsafe fn slice<'a, T>(p: *const T, len: usize) -> Result<&'a [T], hf_result> {
    check(p, len)?;
    // SAFETY: non-NULL, aligned, size within isize::MAX (checked); validity and
    // the absence of writers are the caller's promise.
    Ok(unsafe { core::slice::from_raw_parts(p, len) })
}

/// A mutable slice of `len` elements at `p`.
///
/// # Safety
/// When `p` is non-NULL and aligned it must be valid for reading and writing `len`
/// elements of `T`, with no other access while the slice lives.
pub unsafe fn slice_mut<'a, T>(p: *mut T, len: usize) -> Result<&'a mut [T], hf_result> {
    check(p, len)?;
    // SAFETY: as in `slice`, plus exclusivity, which is the caller's promise.
    Ok(unsafe { core::slice::from_raw_parts_mut(p, len) })
}

/// A shared reference to one `T` at `p`.
///
/// # Safety
/// When `p` is non-NULL and aligned it must point to a valid `T`, not written while the
/// reference lives.
pub unsafe fn get<'a, T>(p: *const T) -> Result<&'a T, hf_result> {
    check(p, 1)?;
    // SAFETY: non-NULL and aligned (checked); validity is the caller's promise.
    Ok(unsafe { &*p })
}

/// An exclusive reference to one `T` at `p` (a handle the call may change).
///
/// # Safety
/// When `p` is non-NULL and aligned it must point to a valid `T` that nothing else
/// reads or writes while the reference lives.
pub unsafe fn get_mut<'a, T>(p: *mut T) -> Result<&'a mut T, hf_result> {
    check(p, 1)?;
    // SAFETY: non-NULL and aligned (checked); validity and exclusivity are the
    // caller's promise.
    Ok(unsafe { &mut *p })
}

/// A place to write one `T` to, written only by [`Out::set`] (so only on success).
pub struct Out<T>(NonNull<T>);

/// Checks an output pointer.
pub fn out<T>(p: *mut T) -> Result<Out<T>, hf_result> {
    check(p, 1)?;
    NonNull::new(p).map(Out).ok_or(HF_ERR_NULL_POINTER)
}

impl<T> Out<T> {
    /// Writes `v` (without reading or dropping the old contents).
    ///
    /// # Safety
    /// The pointer given to [`out`] must be valid for writing one `T`.
    pub unsafe fn set(self, v: T) {
        // SAFETY: non-NULL and aligned (checked by `out`); writable by the caller's promise.
        unsafe { self.0.as_ptr().write(v) }
    }
}

/// The body of an export that answers one value, behind the panic boundary: `input()`
/// (the checks of the inputs, whose errors come first), then `out` checked, then the
/// input's `value` written to `*out` (only on success).
///
/// # Safety
/// `out` is NULL (an error) or valid for writing one `O`.
pub unsafe fn answer<I, O>(
    input: impl FnOnce() -> Result<I, hf_result>,
    out: *mut O,
    value: impl FnOnce(I) -> Result<O, hf_result>,
) -> hf_result {
    crate::guard(|| {
        let i = input()?;
        let o = self::out(out)?;
        let v = value(i)?;
        // SAFETY: the caller promises `out` is writable.
        unsafe { o.set(v) };
        Ok(())
    })
}

/// Checks `buf` (`buf_len` bytes) and `out_written`, then writes `text()` into `buf` as
/// a NUL-terminated string and its length without the NUL to `*out_written`.
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` NULL
/// (an error) or valid for writing one `size_t`.
pub unsafe fn write_text(
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
    text: impl FnOnce() -> Result<String, hf_result>,
) -> Result<(), hf_result> {
    // SAFETY: the caller promises `buf` is writable for `buf_len` bytes.
    let buf = unsafe { slice_mut(buf, buf_len) }?;
    let written = out(out_written)?;
    let text = text()?;
    // SAFETY: the caller promises `out_written` is writable.
    unsafe { write_c_string(&text, buf, written) }
}

/// Writes `s` and a NUL into `buf` and the length of `s` to `written`.
///
/// # Safety
/// `written` must be valid for writing one `size_t`.
pub unsafe fn write_c_string(
    s: &str,
    buf: &mut [c_char],
    written: Out<usize>,
) -> Result<(), hf_result> {
    if buf.len() <= s.len() {
        return Err(fail(
            HF_ERR_BUFFER_TOO_SMALL,
            format_args!("buf: {} bytes, {} needed", buf.len(), s.len() + 1),
        ));
    }
    for (o, &b) in buf.iter_mut().zip(s.as_bytes()) {
        *o = b as c_char;
    }
    buf[s.len()] = 0;
    // SAFETY: the caller's promise.
    unsafe { written.set(s.len()) };
    Ok(())
}
