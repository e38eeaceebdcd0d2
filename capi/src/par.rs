//! The threaded bakes: bands of rows handed out to worker threads in turn.

use std::ops::Range;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

/// Thread count for `threads` (0: one per available core), at most `rows`, at least 1.
pub fn thread_count(threads: u32, rows: u32) -> u32 {
    match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get() as u32),
        n => n,
    }
    .clamp(1, rows.max(1))
}

/// Runs `bake(rows, out_rows)` over `rows` rows of `row_len` elements of `out`, in
/// bands of `band` rows taken in turn by `threads` threads (the calling thread alone
/// when `threads` is 1). Costly rows are uneven, hence many small bands. Returns the
/// first error.
pub fn bake_bands<T: Send, E: Send>(
    rows: u32,
    row_len: usize,
    band: u32,
    threads: u32,
    out: &mut [T],
    bake: impl Fn(Range<u32>, &mut [T]) -> Result<(), E> + Sync,
) -> Result<(), E> {
    let out = &mut out[..rows as usize * row_len];
    if threads <= 1 || rows <= band {
        return bake(0..rows, out);
    }
    let next = AtomicU32::new(0);
    let chunks: Vec<Mutex<&mut [T]>> = out
        .chunks_mut(band as usize * row_len)
        .map(Mutex::new)
        .collect();
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| -> Result<(), E> {
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
                })
            })
            .collect();
        // A panicking worker re-panics here, caught by the export's panic boundary.
        workers
            .into_iter()
            .map(|w| w.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect::<Result<Vec<()>, E>>()
            .map(|_| ())
    })
}
