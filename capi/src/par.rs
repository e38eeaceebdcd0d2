//! The threaded bakes: bands of rows handed out to worker threads in turn; and the
//! buffer checks and scratches the safety and cylinder–cone bakes share.

use std::ops::Range;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

#[cfg(feature = "safety")]
use crate::hf_result::{self, *};
#[cfg(feature = "safety")]
use core::ptr::NonNull;

/// Thread count for `threads` (0: one per available core): at most the available
/// cores (more would only wait for them) and at most `units` (the bands or rows there
/// are to hand out), at least 1.
pub fn thread_count(threads: u32, units: u32) -> u32 {
    // One thread needs no core count: asking the system for it on every call (every
    // single-threaded batch trace) is a system call, and std's cache of how to ask is a
    // data race helgrind reports when several threads trace at once.
    if threads == 1 {
        return 1;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
    match threads {
        0 => cores,
        n => n.min(cores),
    }
    .clamp(1, units.max(1))
}

/// Runs `bake(rows, out_rows)` over `rows` rows of `row_len` elements of `out`, in
/// bands of `band` rows taken in turn by the calling thread and up to `threads − 1`
/// more ([`thread_count`] of the bands). Costly rows are uneven, hence many small
/// bands. A thread the system refuses to create is done without (the others take its
/// bands; the calling thread alone, at worst). Returns the first error.
pub fn bake_bands<T: Send, E: Send>(
    rows: u32,
    row_len: usize,
    band: u32,
    threads: u32,
    out: &mut [T],
    bake: impl Fn(Range<u32>, &mut [T]) -> Result<(), E> + Sync,
) -> Result<(), E> {
    let out = &mut out[..rows as usize * row_len];
    let band = band.max(1);
    let threads = thread_count(threads, rows.div_ceil(band));
    if threads <= 1 {
        return bake(0..rows, out);
    }
    let next = AtomicU32::new(0);
    let chunks: Vec<Mutex<&mut [T]>> = out
        .chunks_mut(band as usize * row_len)
        .map(Mutex::new)
        .collect();
    let work = || -> Result<(), E> {
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(chunk) = chunks.get(k as usize) else {
                return Ok(());
            };
            let r0 = k * band;
            let r1 = (r0 + band).min(rows);
            let mut chunk = chunk.lock().unwrap_or_else(|e| e.into_inner());
            bake(r0..r1, &mut chunk)?;
        }
    };
    std::thread::scope(|s| {
        let helpers: Vec<_> = (1..threads)
            .map_while(|_| {
                std::thread::Builder::new()
                    .spawn_scoped(s, || crate::detail::quietly(|_| work()))
                    .ok()
            })
            .collect();
        let mine = work();
        // A panicking helper re-panics here, caught by the export's panic boundary.
        helpers
            .into_iter()
            .map(|w| w.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .fold(mine, Result::and)
    })
}

/// `n` zeroed floats, allocated fallibly (`HF_ERR_OUT_OF_MEMORY`): a bake's scratch.
#[cfg(feature = "safety")]
pub fn zeroed(n: usize) -> Result<Vec<f32>, hf_result> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| HF_ERR_OUT_OF_MEMORY)?;
    v.resize(n, 0.0);
    Ok(v)
}

/// The whole-map bake of the safety and cylinder–cone exports: checks that `out` holds
/// `needed` bytes, runs `prepare` (the scratches), then bakes the `rows` rows of
/// `row_len` bytes with `bake(scratches, rows, out_rows)` in bands of 8 rows on
/// `threads` threads (0: one per available core).
#[cfg(feature = "safety")]
pub fn bake_map<S: Sync, E: Send>(
    rows: u32,
    row_len: usize,
    needed: usize,
    threads: u32,
    out: &mut [u8],
    prepare: impl FnOnce() -> Result<S, hf_result>,
    bake: impl Fn(&S, Range<u32>, &mut [u8]) -> Result<(), E> + Sync,
) -> Result<(), hf_result>
where
    hf_result: From<E>,
{
    if out.len() < needed {
        return Err(HF_ERR_BUFFER_TOO_SMALL);
    }
    let scratches = prepare()?;
    let scratches = &scratches;
    Ok(bake_bands(rows, row_len, 8, threads, out, |r, chunk| {
        bake(scratches, r, chunk)
    })?)
}

/// The map buffer of a row bake of the safety and cylinder–cone exports and the rows
/// `[begin, end)` the call bakes into it, checked for NULL first (before the options).
/// What [`RowsOut::rows`] hands out: the rows, their bytes, and the descriptor's
/// bytes for the call whose rows start at 0.
#[cfg(feature = "safety")]
pub type RowsSlices<'a> = (Range<u32>, &'a mut [u8], Option<&'a mut [u8]>);

#[cfg(feature = "safety")]
pub struct RowsOut {
    map: NonNull<u8>,
    map_len: usize,
    rows: Range<u32>,
}

#[cfg(feature = "safety")]
impl RowsOut {
    /// Checks `map` (`map_len` bytes) for NULL.
    pub fn new(map: *mut u8, map_len: usize, begin: u32, end: u32) -> Result<Self, hf_result> {
        let map = NonNull::new(map).ok_or(HF_ERR_NULL_POINTER)?;
        Ok(Self {
            map,
            map_len,
            rows: begin..end,
        })
    }

    /// The rows and their bytes, for a map of `texels` bytes in `height` rows of
    /// `row_len` bytes followed by its descriptor, and the descriptor's bytes when the
    /// rows start at 0: `HF_ERR_BUFFER_TOO_SMALL` when `map_len` cannot hold both,
    /// `HF_ERR_INVALID_ARGUMENT` unless `begin ≤ end ≤ height`. Only the rows baked
    /// become a slice, so concurrent calls never alias.
    ///
    /// # Safety
    /// The map is valid for writing `map_len` bytes, and the rows are this call's alone
    /// (the documented contract of the row bakes).
    pub unsafe fn rows<'a>(
        self,
        height: u32,
        row_len: usize,
        texels: usize,
    ) -> Result<RowsSlices<'a>, hf_result> {
        let desc = crate::mapdesc::HF_MAP_DESC_BYTES;
        if self.map_len < texels + desc {
            return Err(crate::detail::fail(
                HF_ERR_BUFFER_TOO_SMALL,
                format_args!(
                    "map_len: {} bytes, the map and its descriptor need {}",
                    self.map_len,
                    texels + desc
                ),
            ));
        }
        let Range { start, end } = self.rows;
        if start > end || end > height {
            return Err(HF_ERR_INVALID_ARGUMENT);
        }
        // SAFETY: inside the caller's buffer (`texels` bytes of `height` rows, length
        // checked), this call's alone (the caller's promise).
        let out = unsafe {
            crate::ptr::slice_mut(
                self.map.as_ptr().add(start as usize * row_len),
                (end - start) as usize * row_len,
            )
        }?;
        // SAFETY: the descriptor's bytes follow the texels (length checked); only the
        // call whose rows start at 0 takes them, so concurrent calls never alias.
        let slot = match start {
            0 => Some(unsafe { crate::ptr::slice_mut(self.map.as_ptr().add(texels), desc) }?),
            _ => None,
        };
        Ok((self.rows, out, slot))
    }
}
