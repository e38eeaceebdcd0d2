//! The error detail of the last failing call on each thread (which argument, which
//! limit, which element), and the panic hook that keeps the library's caught panics
//! off stderr.

use crate::hf_result;
use crate::{guard_keeping_detail, ptr};
use std::cell::{Cell, RefCell};
use std::ffi::c_char;
use std::fmt::{Display, Write};
use std::sync::Once;

/// Longest detail text in bytes (the NUL makes 256).
const MAX_LEN: usize = 255;

/// What was wrong in the last failing call on a thread.
#[derive(Clone)]
struct Detail {
    /// ASCII text, at most [`MAX_LEN`] bytes.
    text: String,
    /// The first bad element of an array argument (a ray of a batch, a sample).
    index: Option<usize>,
}

thread_local! {
    /// The detail of this thread's last failing call, `None` after a call that set none.
    static DETAIL: RefCell<Option<Detail>> = const { RefCell::new(None) };
    /// How many panic boundaries (or quiet worker bodies) this thread is inside.
    static DEPTH: Cell<u32> = const { Cell::new(0) };
}

/// Records `what` (and `index`) as the detail of the failing call and returns `code`.
pub(crate) fn fail_at(code: hf_result, index: Option<usize>, what: impl Display) -> hf_result {
    let mut text = String::new();
    let _ = write!(text, "{what}");
    let mut text: String = text
        .chars()
        .map(|c| if c.is_ascii() { c } else { '?' })
        .collect();
    text.truncate(MAX_LEN);
    DETAIL.with(|d| *d.borrow_mut() = Some(Detail { text, index }));
    code
}

/// Records `what` as the detail of the failing call and returns `code`.
pub(crate) fn fail(code: hf_result, what: impl Display) -> hf_result {
    fail_at(code, None, what)
}

/// Whether a detail has been recorded since the last [`clear`].
pub(crate) fn is_set() -> bool {
    DETAIL.with(|d| d.borrow().is_some())
}

/// Forgets the detail (a new call begins).
pub(crate) fn clear() {
    DETAIL.with(|d| *d.borrow_mut() = None);
}

/// Runs `f` and puts back the detail it found, whatever `f` recorded (the queries of
/// the detail never change it, even when they fail).
pub(crate) fn keeping<R>(f: impl FnOnce() -> R) -> R {
    let saved = DETAIL.with(|d| d.borrow().clone());
    let r = f();
    DETAIL.with(|d| *d.borrow_mut() = saved);
    r
}

/// Names the argument an error is about: the detail becomes `"{arg}: {detail}"`.
pub(crate) trait Named {
    /// `self`, with the detail of an error prefixed by `arg`.
    fn named(self, arg: &str) -> Self;
}

impl<T> Named for Result<T, hf_result> {
    fn named(self, arg: &str) -> Self {
        self.map_err(|code| {
            let (what, index) = DETAIL.with(|d| match d.borrow_mut().take() {
                Some(Detail { text, index }) => (text, index),
                None => (code.message().to_owned(), None),
            });
            fail_at(code, index, format_args!("{arg}: {what}"))
        })
    }
}

/// Runs `f` marked as inside the library: a panic in it is not printed by the hook.
/// The panic boundary uses it, and so do the worker threads of the threaded bakes.
/// Returns `f`'s result and whether this is the outermost such call on the thread.
pub(crate) fn quietly<R>(f: impl FnOnce(bool) -> R) -> R {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if DEPTH.try_with(Cell::get).unwrap_or(0) == 0 {
                previous(info);
            }
        }));
    });
    let depth = DEPTH.with(|d| d.replace(d.get() + 1));
    /// Leaves the quiet section, also when `f` unwinds.
    struct Leave;
    impl Drop for Leave {
        fn drop(&mut self) {
            DEPTH.with(|d| d.set(d.get() - 1));
        }
    }
    let _leave = Leave;
    f(depth == 0)
}

/// Writes what was wrong in the last failing `hf_` call on the calling thread into
/// `buf` as a NUL-terminated ASCII string, and its length without the NUL into
/// `*out_written`: the argument and the limit, e.g. `rays[17]: ray direction is zero`,
/// `out_hits overlaps rays`, `field: pointer is NULL`, `surface: 9 is not an
/// hf_surface`. 256 bytes always suffice; a shorter `buf` is `HF_ERR_BUFFER_TOO_SMALL`.
/// Meaningful after a call returned an error, until the next `hf_` call on the thread
/// (each call but this one and `hf_last_error_index` starts afresh; a successful call
/// may leave an empty string or the text of an earlier error). Neither this function
/// nor `hf_last_error_index` changes the detail, even when it fails. Thread safe (the
/// detail is per thread).
///
/// # Safety
/// `buf` is NULL (an error) or valid for writing `buf_len` bytes; `out_written` is NULL
/// (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_last_error_detail(
    buf: *mut c_char,
    buf_len: usize,
    out_written: *mut usize,
) -> hf_result {
    let text = || {
        Ok(DETAIL
            .with(|d| d.borrow().clone())
            .map_or(String::new(), |d| d.text))
    };
    // SAFETY: the caller's promises, passed on.
    guard_keeping_detail(|| unsafe { ptr::write_text(buf, buf_len, out_written, text) })
}

/// Writes to `*out` the index of the first bad element of an array argument in the
/// last failing `hf_` call on the calling thread: the first invalid ray of a batch
/// (`HF_ERR_INVALID_RAY`), the first NaN or infinite height of a field creation
/// (`HF_ERR_NOT_FINITE`); `SIZE_MAX` when that error named no element. Meaningful
/// when `hf_last_error_detail` is (the text then says the same index). Thread safe.
///
/// # Safety
/// `out` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_last_error_index(out: *mut usize) -> hf_result {
    guard_keeping_detail(|| {
        let out = ptr::out(out)?;
        let index = DETAIL.with(|d| d.borrow().as_ref().and_then(|d| d.index));
        // SAFETY: the caller promises `out` is writable.
        unsafe { out.set(index.unwrap_or(usize::MAX)) };
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hf_result::*;

    #[test]
    fn named_prefixes_and_keeps_the_index() {
        clear();
        let r: Result<(), hf_result> = Err(fail_at(HF_ERR_INVALID_RAY, Some(3), "bad ray"));
        assert_eq!(r.named("rays[3]"), Err(HF_ERR_INVALID_RAY));
        DETAIL.with(|d| {
            let d = d.borrow();
            let d = d.as_ref().unwrap();
            assert_eq!((d.text.as_str(), d.index), ("rays[3]: bad ray", Some(3)));
        });
        fail(HF_ERR_INVALID_ARGUMENT, "\u{e9}".repeat(400));
        DETAIL.with(|d| assert_eq!(d.borrow().as_ref().unwrap().text, "?".repeat(MAX_LEN)));
    }
}
