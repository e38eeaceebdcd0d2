//! Relaxed cone stepping (Policarpo & Oliveira, GPU Gems 3, ch. 18): the published
//! preprocess and march, side by side. **Approximate**: a relaxed cone lets a ray
//! cross the surface once, so the final binary search can pick the wrong crossing or
//! miss a thin peak altogether; the tests measure how often.
//!
//! **Bake** (the book's listing, one texel per sample, ratio = horizontal/vertical).
//! For sample T and each destination sample D, the ray from the top of the field above
//! T (`z = max`, raised by a hair so that it is never horizontal) through D's surface
//! point is continued past D in [`SEARCH_STEPS`] equal steps down to the field's
//! bottom while it stays under the surface; the first point E out of it bounds the
//! ratio by `|E − T| / (z_E − h_T)` when E is above T. The ratio is the minimum over D.
//! The book loops over every D (Θ(N⁴)); here the max pyramid skips whole regions whose
//! bound `dist(T, node) / (max − h_T)` cannot lower the ratio (E lies beyond D and not
//! above it), which gives the same result ([`bake_brute`] is the oracle).
//!
//! **March** ([`trace`]): cone steps `Δt = Δh / (|d_xy| / r + |d_z|)` with `Δh` the
//! ray's height over the surface at its point and `r` the ratio of the nearest sample,
//! until the ray is under the surface (or the step budget runs out), then a binary
//! search between the last two points.

// `!(x > 0)` is meant: it is true for NaN too, which must not step.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use core::ops::Range;

use crate::cone::{bnb, check, f32_down, BakeError, RATIO_MAX};
use crate::dda::clip;
use crate::field::HeightField;
use crate::math::Real;
use crate::maxmip::MaxMip;
use crate::ray::{Flags, Hit, Query, Trace};
use crate::surface::Surface;

const TRI: Surface = Surface::Triangles;

/// Steps of the bake's search past each destination (the book's `search_steps`).
pub const SEARCH_STEPS: u32 = 128;

/// Length of a relaxed cone map (one ratio per sample).
pub fn map_len(width: u32, height: u32) -> usize {
    width as usize * height as usize
}

/// Length of the bake scratch (the max pyramid).
pub fn scratch_len(width: u32, height: u32) -> usize {
    crate::cone::scratch_len(width, height)
}

/// The ratio bound destination sample `dst` puts on source sample `src`.
pub fn pair_ratio(hf: &HeightField, src: [u32; 2], dst: [u32; 2]) -> f64 {
    let ht = hf.at(src[0], src[1]) as f64;
    let hd = hf.at(dst[0], dst[1]) as f64;
    if hd <= ht || src == dst {
        return f64::INFINITY;
    }
    let (zmin, zmax) = (hf.min_height() as f64, hf.max_height() as f64);
    let top = zmax + 1e-3 * (zmax - zmin) + 1e-6;
    let t = [src[0] as f64, src[1] as f64];
    let dpt = [dst[0] as f64, dst[1] as f64, hd];
    // Ray from (T, top) through D, scaled to reach the bottom from D.
    let v = [dpt[0] - t[0], dpt[1] - t[1], hd - top];
    let scale = (hd - zmin) / (top - hd) / SEARCH_STEPS as f64;
    let step = [v[0] * scale, v[1] * scale, v[2] * scale];
    let mut p = [dpt[0] + step[0], dpt[1] + step[1], dpt[2] + step[2]];
    for _ in 1..SEARCH_STEPS {
        if TRI.height_at(hf, p[0], p[1]) >= p[2] {
            p = [p[0] + step[0], p[1] + step[1], p[2] + step[2]];
        } else {
            break;
        }
    }
    if p[2] <= ht {
        return f64::INFINITY;
    }
    let (dx, dy) = (p[0] - t[0], p[1] - t[1]);
    libm::sqrt(dx * dx + dy * dy) / (p[2] - ht)
}

/// The ratio of sample `s`, searched over the pyramid.
pub fn texel_ratio(hf: &HeightField, mip: &MaxMip, s: [u32; 2]) -> f64 {
    let ht = hf.at(s[0], s[1]);
    let (w, h) = (hf.width(), hf.height());
    let src = [s[0] as f64, s[0] as f64, s[1] as f64, s[1] as f64];
    let mut best = RATIO_MAX as f64;
    bnb(mip, src, |d, m, leaf| {
        if m <= ht || d >= best * (m as f64 - ht as f64) {
            return false;
        }
        if let Some([ci, cj]) = leaf {
            // Each cell owns its low corner, and the far ones on the last row/column.
            for (a, b) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (x, y) = (ci + a, cj + b);
                if (a == 1 && x != w - 1) || (b == 1 && y != h - 1) {
                    continue;
                }
                best = best.min(pair_ratio(hf, s, [x, y]));
            }
        }
        true
    });
    best
}

/// Bakes sample rows `rows` into `out` (`rows.len() × W` ratios) from the pyramid in
/// `scratch` ([`crate::cone::prepare`]). Rows are independent.
pub fn bake_rows(
    hf: &HeightField,
    scratch: &[f32],
    rows: Range<u32>,
    out: &mut [f32],
) -> Result<(), BakeError> {
    let mip = MaxMip::new(hf, scratch).map_err(|_| BakeError::TooShort {
        needed: scratch_len(hf.width(), hf.height()),
        given: scratch.len(),
    })?;
    let w = hf.width();
    if rows.end > hf.height() || rows.start > rows.end {
        return Err(BakeError::BadRows);
    }
    check(rows.len() * w as usize, out.len())?;
    for (r, j) in rows.enumerate() {
        for i in 0..w {
            out[r * w as usize + i as usize] = f32_down(texel_ratio(hf, &mip, [i, j]));
        }
    }
    Ok(())
}

/// Bakes the whole map.
pub fn bake(hf: &HeightField, scratch: &mut [f32], out: &mut [f32]) -> Result<(), BakeError> {
    crate::cone::prepare(hf, scratch)?;
    let len = map_len(hf.width(), hf.height());
    check(len, out.len())?;
    bake_rows(hf, scratch, 0..hf.height(), &mut out[..len])
}

/// The book's Θ(N⁴) loop over every pair: the test oracle of the bake.
pub fn bake_brute(hf: &HeightField, out: &mut [f32]) -> Result<(), BakeError> {
    let (w, h) = (hf.width(), hf.height());
    check(map_len(w, h), out.len())?;
    for j in 0..h {
        for i in 0..w {
            let mut best = RATIO_MAX as f64;
            for dj in 0..h {
                for di in 0..w {
                    best = best.min(pair_ratio(hf, [i, j], [di, dj]));
                }
            }
            out[j as usize * w as usize + i as usize] = f32_down(best);
        }
    }
    Ok(())
}

/// Step budget of the march.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Steps {
    /// Most cone steps.
    pub cone: u32,
    /// Binary-search steps after the first point under the surface.
    pub binary: u32,
}

impl Default for Steps {
    fn default() -> Self {
        Steps {
            cone: 64,
            binary: 8,
        }
    }
}

/// Traces `q` (approximate). Fetches: four per surface height, one per ratio.
pub fn trace<R: Real>(map: &[f32], hf: &HeightField, q: &Query<R>, steps: Steps) -> Trace<R> {
    trace_steps(map, hf, q, steps, &mut |_| {})
}

/// [`trace`], reporting every new ray parameter to `on_step`.
pub fn trace_steps<R: Real>(
    map: &[f32],
    hf: &HeightField,
    q: &Query<R>,
    steps: Steps,
    on_step: &mut dyn FnMut(R),
) -> Trace<R> {
    let Some(span) = clip(hf, q) else {
        return Trace::MISS;
    };
    let d = q.dir();
    let hs = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let w = hf.width();
    let (xm, ym) = (R::from_u32(w - 1), R::from_u32(hf.height() - 1));
    let mut fetches = 0u32;
    let above = |t: R, fetches: &mut u32| {
        let p = q.at(t);
        *fetches += 4;
        p[2] - TRI.height_at(hf, p[0], p[1])
    };
    let hit = |t: R, fetches: u32, flags: Flags| {
        let p = q.at(t);
        let x = p[0].clamp_to(R::ZERO, xm);
        let y = p[1].clamp_to(R::ZERO, ym);
        let cell = [
            (x.floor().to_f64() as u32).min(w - 2),
            (y.floor().to_f64() as u32).min(hf.height() - 2),
        ];
        Trace {
            hit: Some(Hit {
                t,
                point: R::v3(p),
                cell,
                normal: R::v3(TRI.normal_at(hf, x, y)),
                flags: Flags::default(),
            }),
            fetches,
            clearance: R::INFINITY,
            flags,
        }
    };
    let mut t = span.t0;
    let mut dh = above(t, &mut fetches);
    if dh <= R::ZERO {
        return hit(t, fetches, Flags::default());
    }
    let mut t_prev = t;
    let mut n = 0;
    while dh > R::ZERO {
        if n == steps.cone {
            return hit(t, fetches, Flags::BUDGET_EXHAUSTED);
        }
        n += 1;
        let p = q.at(t);
        let i = (p[0].clamp_to(R::ZERO, xm) + R::HALF).floor().to_f64() as u32;
        let j = (p[1].clamp_to(R::ZERO, ym) + R::HALF).floor().to_f64() as u32;
        let r = R::from_f32(map[j as usize * w as usize + i.min(w - 1) as usize]);
        fetches += 1;
        let denom = if hs == R::ZERO { -d[2] } else { hs / r - d[2] };
        if !(denom > R::ZERO) {
            return Trace {
                fetches,
                ..Trace::MISS
            };
        }
        t_prev = t;
        t = t + dh / denom;
        if !(t <= span.t1) {
            return Trace {
                fetches,
                ..Trace::MISS
            };
        }
        on_step(t);
        dh = above(t, &mut fetches);
    }
    // Binary search between the last point above and the first one under.
    let (mut lo, mut hi) = (t_prev, t);
    for _ in 0..steps.binary {
        let mid = R::HALF * (lo + hi);
        if above(mid, &mut fetches) > R::ZERO {
            lo = mid;
        } else {
            hi = mid;
        }
        on_step(hi);
    }
    hit(hi, fetches, Flags::default())
}
