//! # hfcast-tools — the std side of hfcast
//!
//! The library behind the `hfcast` command-line tool, shared with its tests and later
//! report tools: loading the real height maps ([`maps`]), a pinhole camera and a
//! shaded, shadowed renderer ([`render`]), the traversal benchmark ([`bench`](mod@bench)), the
//! error-against-time report ([`report`]) and the text format of `hfcast trace`
//! ([`trace`]).

use hfcast::{Method, SearchSteps};
use std::sync::Mutex;

pub mod bench;
pub mod maps;
pub mod render;
pub mod report;
pub mod trace;

/// Parses a method name: `exact`, `linear-binary:N:M` (N linear steps, M bisections) or
/// `secant:N` (N linear steps, then one secant step).
pub fn parse_method(name: &str) -> Result<Method, String> {
    let mut parts = name.split(':');
    let kind = parts.next().unwrap_or("");
    let mut num = |what: &str| -> Result<u32, String> {
        let s = parts
            .next()
            .ok_or_else(|| format!("method {name:?}: missing {what}"))?;
        s.parse()
            .map_err(|_| format!("method {name:?}: bad {what} {s:?}"))
    };
    let method = match kind {
        "exact" => Method::Exact,
        "linear-binary" => Method::LinearBinary(SearchSteps {
            linear: num("linear step count")?,
            binary: num("binary step count")?,
        }),
        "secant" => Method::LinearSecant(num("linear step count")?),
        _ => {
            return Err(format!(
                "unknown method {name:?} (exact | linear-binary:N:M | secant:N)"
            ))
        }
    };
    match parts.next() {
        Some(extra) => Err(format!("method {name:?}: unexpected {extra:?}")),
        None => Ok(method),
    }
}

/// The name [`parse_method`] reads back.
pub fn method_name(method: Method) -> String {
    match method {
        Method::Exact => "exact".into(),
        Method::LinearBinary(s) => format!("linear-binary:{}:{}", s.linear, s.binary),
        Method::LinearSecant(n) => format!("secant:{n}"),
    }
}

/// The machine's available parallelism (1 when unknown).
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Runs `f(first_index, chunk)` over `data` cut into chunks of `chunk` elements, on
/// `threads` scoped threads that take chunks in order as they become free (so uneven
/// work balances). Returns when every chunk is done.
pub fn par_chunks<T: Send>(
    data: &mut [T],
    chunk: usize,
    threads: usize,
    f: impl Fn(usize, &mut [T]) + Sync,
) {
    let chunk = chunk.max(1);
    let next = Mutex::new(data.chunks_mut(chunk).enumerate());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let item = next.lock().expect("a worker panicked").next();
                let Some((k, c)) = item else { break };
                f(k * chunk, c);
            });
        }
    });
}

/// A small deterministic random generator (SplitMix64), enough for test and benchmark
/// rays; no dependency.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// A direction uniform on the unit sphere.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn method_names_round_trip() {
        for name in ["exact", "linear-binary:32:8", "secant:16"] {
            assert_eq!(method_name(parse_method(name).unwrap()), name);
        }
        for bad in [
            "",
            "exact:1",
            "secant",
            "secant:x",
            "linear-binary:4",
            "dda",
        ] {
            assert!(parse_method(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn par_chunks_visits_everything_once() {
        let mut v = vec![0usize; 1001];
        par_chunks(&mut v, 7, 3, |start, c| {
            for (k, x) in c.iter_mut().enumerate() {
                *x += start + k;
            }
        });
        assert!(v.iter().enumerate().all(|(k, &x)| k == x));
    }
}
