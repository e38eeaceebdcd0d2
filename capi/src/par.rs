//! The threaded bakes and batch traces: bands of rows handed out to worker threads in
//! turn; and the scratch a whole bake allocates.

use std::ops::Range;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

use crate::hf_result::{self, *};

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
    // A helper the system refuses leaves its bands to the others.
    let (mine, helpers) = with_helpers(threads as usize - 1, |_| work(), work);
    helpers.into_iter().flatten().fold(mine, Result::and)
}

/// `mine()` on the calling thread while `n` more threads run `helper(0)` …
/// `helper(n − 1)`, in the library's quiet section; the helpers' results in order,
/// `None` for one the system refused to create. A panicking helper re-panics here,
/// caught by the export's panic boundary.
fn with_helpers<T: Send>(
    n: usize,
    helper: impl Fn(usize) -> T + Sync,
    mine: impl FnOnce() -> T,
) -> (T, Vec<Option<T>>) {
    let helper = &helper;
    std::thread::scope(|s| {
        let spawned: Vec<_> = (0..n)
            .map(|i| {
                std::thread::Builder::new()
                    .spawn_scoped(s, move || crate::detail::quietly(|_| helper(i)))
                    .ok()
            })
            .collect();
        let mine = mine();
        let joined = spawned
            .into_iter()
            .map(|h| h.map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p))));
        (mine, joined.collect())
    })
}

/// `work(part)` for each part of `0..units` cut into [`thread_count`] ranges, run by the
/// calling thread and up to `threads − 1` more, the results in the parts' order. A
/// thread the system refuses to create leaves its part to the calling thread.
pub fn split<T: Send>(units: u32, threads: u32, work: impl Fn(Range<u32>) -> T + Sync) -> Vec<T> {
    let n = thread_count(threads, units);
    let per = units.div_ceil(n.max(1)).max(1);
    let parts: Vec<Range<u32>> = (0..n)
        .map(|k| (k * per).min(units)..((k + 1) * per).min(units))
        .collect();
    if n <= 1 {
        return parts.into_iter().map(&work).collect();
    }
    let rest = &parts[1..];
    let (mine, helpers) = with_helpers(
        rest.len(),
        |i| work(rest[i].clone()),
        || work(parts[0].clone()),
    );
    core::iter::once(mine)
        .chain(
            helpers
                .into_iter()
                .zip(rest)
                .map(|(h, r)| h.unwrap_or_else(|| work(r.clone()))),
        )
        .collect()
}

/// `n` zeroed floats, allocated fallibly (`HF_ERR_OUT_OF_MEMORY`): a bake's scratch.
pub fn zeroed(n: usize) -> Result<Vec<f32>, hf_result> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| HF_ERR_OUT_OF_MEMORY)?;
    v.resize(n, 0.0);
    Ok(v)
}
