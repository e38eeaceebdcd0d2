//! The traversal benchmark behind `hfcast bench`: rays per second on 1 and more
//! threads (median of repetitions), texture fetches per ray and hit rate.

use crate::trace::Tracer;
use crate::{par_chunks, MethodSpec, Rng};
use hfcast::{HeightField, Query, Surface, Trace};
use std::fmt::Write;
use std::time::Instant;

/// `n` rays with origins uniform in the field's bounding box
/// `[0, W−1] × [0, H−1] × [min, max height]` and directions uniform on the sphere;
/// `t` in `[0, ∞)`. Deterministic for a given `seed`.
pub fn random_rays(hf: &HeightField, n: usize, seed: u64) -> Vec<Query<f32>> {
    let mut rng = Rng::new(seed);
    let (w, h) = (f64::from(hf.width() - 1), f64::from(hf.height() - 1));
    let (zmin, zmax) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    (0..n)
        .map(|_| {
            let o = [rng.range(0.0, w), rng.range(0.0, h), rng.range(zmin, zmax)];
            let d = rng.direction();
            Query::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .expect("finite, non-zero")
        })
        .collect()
}

/// One benchmark line.
#[derive(Clone, Debug)]
pub struct BenchResult {
    /// What the rays are.
    pub name: String,
    /// Number of rays.
    pub rays: usize,
    /// Fraction of rays that hit.
    pub hit_rate: f64,
    /// Mean texture fetches per ray.
    pub fetch_mean: f64,
    /// 99th percentile of fetches per ray.
    pub fetch_p99: u32,
    /// Most fetches of one ray.
    pub fetch_max: u32,
    /// `(threads, median rays per second)` for each thread count measured.
    pub rays_per_s: Vec<(usize, f64)>,
}

/// How the benchmark hands its rays to the march.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Order {
    /// One ray after another ([`Tracer::trace_each`]).
    Scalar,
    /// In SIMD lanes where the method has them and the CPU can
    /// ([`Tracer::trace_all`]).
    #[default]
    Lanes,
}

/// Traces `rays` with `tracer` `reps` times on each thread count in `threads` and
/// measures them.
pub fn bench_rays(
    tracer: &Tracer,
    name: &str,
    rays: &[Query<f32>],
    threads: &[usize],
    reps: usize,
    order: Order,
) -> BenchResult {
    let mut out = vec![Trace::MISS; rays.len()];
    let rays_per_s = threads
        .iter()
        .map(|&t| {
            let mut rates: Vec<f64> = (0..reps.max(1))
                .map(|_| {
                    let start = Instant::now();
                    par_chunks(&mut out, 1024, t, |first, chunk| {
                        let rays = &rays[first..first + chunk.len()];
                        match order {
                            Order::Scalar => tracer.trace_each(rays, chunk),
                            Order::Lanes => tracer.trace_all(rays, chunk),
                        }
                    });
                    rays.len() as f64 / start.elapsed().as_secs_f64()
                })
                .collect();
            rates.sort_by(f64::total_cmp);
            (t, rates[rates.len() / 2])
        })
        .collect();
    let mut fetches: Vec<u32> = out.iter().map(|o| o.fetches).collect();
    fetches.sort_unstable();
    let n = rays.len().max(1);
    BenchResult {
        name: name.into(),
        rays: rays.len(),
        hit_rate: out.iter().filter(|o| o.hit.is_some()).count() as f64 / n as f64,
        fetch_mean: fetches.iter().map(|&f| f64::from(f)).sum::<f64>() / n as f64,
        fetch_p99: fetches.get((n - 1) * 99 / 100).copied().unwrap_or(0),
        fetch_max: fetches.last().copied().unwrap_or(0),
        rays_per_s,
    }
}

/// The results as a Markdown table, headed by the method and surface.
pub fn markdown_table(method: MethodSpec, surface: Surface, results: &[BenchResult]) -> String {
    let mut s = String::new();
    let threads: Vec<usize> = results
        .first()
        .map(|r| r.rays_per_s.iter().map(|&(t, _)| t).collect())
        .unwrap_or_default();
    let _ = write!(
        s,
        "method `{}`, surface `{}`\n\n| rays | count | hit rate | fetches mean | p99 | max |",
        method.name(),
        surface.name()
    );
    for t in &threads {
        let _ = write!(s, " Mrays/s {t} thr |");
    }
    s.push_str(" ns/ray 1 thr |\n|---|---:|---:|---:|---:|---:|");
    s.push_str(&"---:|".repeat(threads.len() + 1));
    s.push('\n');
    for r in results {
        let _ = write!(
            s,
            "| {} | {} | {:.1}% | {:.1} | {} | {} |",
            r.name,
            r.rays,
            100.0 * r.hit_rate,
            r.fetch_mean,
            r.fetch_p99,
            r.fetch_max
        );
        for &(_, rate) in &r.rays_per_s {
            let _ = write!(s, " {:.2} |", rate / 1e6);
        }
        let single = r.rays_per_s.iter().find(|&&(t, _)| t == 1);
        match single {
            Some(&(_, rate)) => {
                let _ = writeln!(s, " {:.0} |", 1e9 / rate);
            }
            None => s.push_str(" – |\n"),
        }
    }
    s
}
