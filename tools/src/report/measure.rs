//! Judging and timing: every setting against the `f64` exact oracle on the same rays.

use super::methods::{Caster, Out, Setting};
use super::scenes::RaySet;
use crate::par_chunks;
use hfcast::{dda, judge, Flags, HeightField, Query, Surface};
use std::time::Instant;

pub use hfcast::judge::{tolerance, F32_ULPS, WRONG};

/// The oracle's answer to one ray.
#[derive(Clone, Copy, Debug, Default)]
pub struct Oracle {
    /// Hit point, `f64`.
    pub hit: Option<[f64; 3]>,
    /// Whether the ray is ambiguous ([`hfcast::judge::ambiguous`]).
    pub ambiguous: bool,
    /// Hit flags.
    pub flags: u32,
}

/// Traces every ray with `dda::trace` on `q.cast::<f64>()` and judges whether it is
/// ambiguous (all `threads`).
pub fn oracle(
    hf: &HeightField,
    surface: Surface,
    rays: &[Query<f32>],
    threads: usize,
) -> Vec<Oracle> {
    let mut out = vec![Oracle::default(); rays.len()];
    par_chunks(&mut out, 256, threads, |first, chunk| {
        for (o, q) in chunk.iter_mut().zip(&rays[first..]) {
            let q = q.cast::<f64>();
            let t = dda::trace(hf, surface, &q);
            *o = Oracle {
                hit: t.hit.map(|h| h.point.to_array()),
                ambiguous: judge::ambiguous(hf, surface, &q, &t),
                flags: t.hit.map_or(0, |h| h.flags.0),
            };
        }
    });
    out
}

/// Counts of one setting on one ray set (or summed over a scene).
#[derive(Clone, Debug, Default)]
pub struct Counts {
    /// Rays traced.
    pub rays: u64,
    /// Rays the oracle calls ambiguous (never counted as right).
    pub ambiguous: u64,
    /// Ambiguous rays on which the setting differs from the oracle.
    pub ambiguous_differ: u64,
    /// Wrong rays among the others.
    pub wrong: u64,
    /// Of those, hit/miss differs.
    pub wrong_hit_miss: u64,
    /// Wrong rays the oracle starts under the surface or enters through a side wall
    /// (semantics that parry3d does not share).
    pub wrong_solid: u64,
    /// Wrong rays that are camera pixels.
    pub wrong_pixels: u64,
    /// Pixels (camera rays).
    pub pixels: u64,
    /// Rays where both hit (non-ambiguous): the position error statistics.
    pub both_hit: u64,
    /// Sum of position errors (texels).
    pub err_sum: f64,
    /// Largest position error (texels).
    pub err_max: f64,
    /// Rays that ran out of their step budget.
    pub budget: u64,
    /// Texture fetches of every ray.
    pub fetches: Vec<u32>,
    /// Indices (in the ray set) of the wrong rays.
    pub wrong_ids: Vec<u32>,
}

impl Counts {
    /// Adds another count.
    pub fn absorb(&mut self, o: &Counts) {
        self.rays += o.rays;
        self.ambiguous += o.ambiguous;
        self.ambiguous_differ += o.ambiguous_differ;
        self.wrong += o.wrong;
        self.wrong_hit_miss += o.wrong_hit_miss;
        self.wrong_solid += o.wrong_solid;
        self.wrong_pixels += o.wrong_pixels;
        self.pixels += o.pixels;
        self.both_hit += o.both_hit;
        self.err_sum += o.err_sum;
        self.err_max = self.err_max.max(o.err_max);
        self.budget += o.budget;
        self.fetches.extend_from_slice(&o.fetches);
        self.wrong_ids.extend_from_slice(&o.wrong_ids);
    }

    /// Wrong rays per non-ambiguous ray.
    pub fn wrong_rate(&self) -> f64 {
        self.wrong as f64 / (self.rays - self.ambiguous).max(1) as f64
    }

    /// Mean position error of the rays where both hit.
    pub fn err_mean(&self) -> f64 {
        self.err_sum / self.both_hit.max(1) as f64
    }

    /// Mean fetches per ray.
    pub fn fetch_mean(&self) -> f64 {
        self.fetches.iter().map(|&f| f64::from(f)).sum::<f64>() / self.fetches.len().max(1) as f64
    }

    /// 99th percentile of fetches per ray (element `⌊(n − 1) · 0.99⌋` of the sorted
    /// counts, as `hfcast bench` reports it).
    pub fn fetch_p99(&self) -> u32 {
        let mut f = self.fetches.clone();
        f.sort_unstable();
        f.get(f.len().saturating_sub(1) * 99 / 100)
            .copied()
            .unwrap_or(0)
    }
}

/// Judges `got` against `oracle` for the rays of `set`.
pub fn judge(set: &RaySet, oracle: &[Oracle], got: &[Out], f64_method: bool) -> Counts {
    let mut c = Counts {
        rays: set.rays.len() as u64,
        pixels: if set.pixels { set.rays.len() as u64 } else { 0 },
        fetches: got.iter().map(|o| o.fetches).collect(),
        ..Counts::default()
    };
    for (k, ((q, or), g)) in set.rays.iter().zip(oracle).zip(got).enumerate() {
        if g.flags & Flags::BUDGET_EXHAUSTED.0 != 0 {
            c.budget += 1;
        }
        let (wrong, hit_miss, err) = match (or.hit, g.hit) {
            (None, None) => (false, false, None),
            (Some(p), Some(h)) => {
                let e = ((0..3).map(|k| (p[k] - h[k]).powi(2)).sum::<f64>()).sqrt();
                (
                    e > tolerance(f64_method, q.origin().map(f64::from), p),
                    false,
                    Some(e),
                )
            }
            _ => (true, true, None),
        };
        if or.ambiguous {
            c.ambiguous += 1;
            c.ambiguous_differ += u64::from(wrong);
            continue;
        }
        if let Some(e) = err {
            c.both_hit += 1;
            c.err_sum += e;
            c.err_max = c.err_max.max(e);
        }
        if wrong {
            c.wrong += 1;
            c.wrong_ids.push(k as u32);
            c.wrong_hit_miss += u64::from(hit_miss);
            c.wrong_pixels += u64::from(set.pixels);
            let solid = Flags::ORIGIN_INSIDE.0 | Flags::SIDE.0;
            c.wrong_solid += u64::from(or.flags & solid != 0);
        }
    }
    c
}

/// One setting measured on one scene.
#[derive(Clone, Debug)]
pub struct Measured {
    /// Index into the settings list.
    pub setting: usize,
    /// Counts per ray set, in set order.
    pub per_set: Vec<Counts>,
    /// Counts over all sets.
    pub total: Counts,
    /// Median single-thread seconds per set.
    pub seconds: Vec<f64>,
    /// Median single-thread nanoseconds per ray over all sets.
    pub ns_per_ray: f64,
    /// Median bake seconds.
    pub bake_s: f64,
    /// Baked bytes.
    pub bytes: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Bakes `setting` for `hf` (median of `reps` bakes; one when a bake takes over a
/// second), traces every set once (untimed, judged) and `reps` more times single-threaded
/// (timed, median).
#[allow(clippy::too_many_arguments)]
pub fn measure(
    index: usize,
    setting: &Setting,
    hf: &HeightField,
    surface: Surface,
    sets: &[RaySet],
    oracles: &[Vec<Oracle>],
    reps: usize,
) -> Measured {
    let mut bakes = Vec::new();
    let mut caster: Option<Box<dyn Caster + '_>> = None;
    for _ in 0..reps.max(1) {
        let start = Instant::now();
        let c = (setting.bake)(hf, surface);
        bakes.push(start.elapsed().as_secs_f64());
        caster = Some(c);
        if bakes[0] > 1.0 {
            break;
        }
    }
    let caster = caster.expect("baked at least once");
    let mut per_set = Vec::new();
    let mut total = Counts::default();
    let mut times = vec![Vec::new(); sets.len()];
    for (k, (set, oracle)) in sets.iter().zip(oracles).enumerate() {
        let mut out = vec![Out::default(); set.rays.len()];
        caster.trace_all(&set.rays, &mut out);
        caster.fill_fetches(&set.rays, &mut out);
        let c = judge(set, oracle, &out, setting.f64);
        total.absorb(&c);
        per_set.push(c);
        for _ in 0..reps.max(1) {
            let start = Instant::now();
            caster.trace_all(std::hint::black_box(&set.rays), &mut out);
            std::hint::black_box(&out);
            times[k].push(start.elapsed().as_secs_f64());
        }
    }
    let seconds: Vec<f64> = times.iter().map(|t| median(t.clone())).collect();
    let reps_n = reps.max(1);
    let ns_total = median(
        (0..reps_n)
            .map(|r| times.iter().map(|t| t[r]).sum::<f64>())
            .collect(),
    );
    let n: usize = sets.iter().map(|s| s.rays.len()).sum();
    Measured {
        setting: index,
        per_set,
        total,
        seconds,
        ns_per_ray: ns_total * 1e9 / n.max(1) as f64,
        bake_s: caster.bake_seconds().unwrap_or_else(|| median(bakes)),
        bytes: caster.baked_bytes(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(n: usize) -> RaySet {
        let q =
            Query::from_arrays([0.5f32, 0.5, 5.0], [0.0, 0.0, -1.0], 0.0, f32::INFINITY).unwrap();
        RaySet {
            name: "test".into(),
            pixels: true,
            rays: vec![q; n],
        }
    }

    #[test]
    fn judge_counts_ambiguous_apart() {
        let s = set(4);
        let hit = |z: f64, ambiguous: bool| Oracle {
            hit: Some([0.5, 0.5, z]),
            ambiguous,
            flags: 0,
        };
        // Right, wrong by position, wrong by hit/miss, ambiguous (and different).
        let oracle = [
            hit(1.0, false),
            hit(1.0, false),
            hit(1.0, false),
            hit(1.0, true),
        ];
        let got = [
            Out {
                hit: Some([0.5, 0.5, 1.0 + 1e-4]),
                fetches: 4,
                flags: 0,
            },
            Out {
                hit: Some([0.5, 0.5, 1.1]),
                fetches: 8,
                flags: 0,
            },
            Out::default(),
            Out::default(),
        ];
        let c = judge(&s, &oracle, &got, false);
        assert_eq!((c.rays, c.ambiguous, c.ambiguous_differ), (4, 1, 1));
        assert_eq!((c.wrong, c.wrong_hit_miss, c.wrong_pixels), (2, 1, 2));
        assert_eq!(c.both_hit, 2);
        assert!((c.err_max - 0.1).abs() < 1e-9);
        assert!((c.wrong_rate() - 2.0 / 3.0).abs() < 1e-12);
        // Sorted 0, 0, 4, 8: element ⌊3 · 0.99⌋ = 2.
        assert_eq!(c.fetch_p99(), 4);
    }
}
