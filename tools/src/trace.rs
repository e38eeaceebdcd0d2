//! Tracing with any method of the command line ([`Tracer`]: the method's bake, once
//! per field, then one ray at a time), and the text format of `hfcast trace`: one ray
//! per line in, one answer per line out.
//!
//! In: `ox oy oz dx dy dz [t_min t_max]` (whitespace separated, grid space; `t_min`
//! defaults to 0, `t_max` to `inf`); `#` starts a comment. Out:
//! `hit t x y z cell_i cell_j nx ny nz fetches flags` (flags as the bit value of
//! [`hfcast::Flags`]), `miss fetches`, or `error <message>`.

use crate::{par_chunks, MethodSpec};
use hfcast::bake::{Spec, Texels};
use hfcast::ktx2::{DataMut, Desc, MapKind};
use hfcast::rayset::Rays;
use hfcast::scene::{BakePlan, RayClasses, Scene};
use hfcast::{HeightField, Marcher, Query, Surface, Trace};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::ops::Range;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Bakes the map of `desc` for `hf` on `threads` threads (the core's one bake
/// interface, `hfcast::bake::Spec`), rows in ranges, with a progress bar on a
/// terminal. The same texels for any thread count.
pub fn bake_texels(hf: &HeightField, desc: &Desc, threads: usize) -> Result<Texels, String> {
    let spec = Spec::new(*desc);
    let n = spec.map_len().map_err(|e| e.to_string())?;
    let mut scratch = vec![0.0; spec.scratch_len()];
    spec.prepare(hf, &mut scratch).map_err(|e| e.to_string())?;
    let scratch = &scratch;
    let rows = spec.rows();
    Ok(if spec.is_float() {
        let mut out = vec![0.0f32; n];
        by_rows(rows, &mut out, threads, |r, o| {
            spec.bake_rows(hf, scratch, r, DataMut::F32(o))
        })?;
        Texels::F32(out)
    } else {
        let mut out = vec![0u8; n];
        by_rows(rows, &mut out, threads, |r, o| {
            spec.bake_rows(hf, scratch, r, DataMut::U8(o))
        })?;
        Texels::U8(out)
    })
}

/// Runs `bake_rows(rows, part)` over the `rows` rows of `out` in ranges of a few rows,
/// on `threads` threads, advancing a progress bar (drawn only on a terminal) by the
/// rows each range baked. The first error stops nothing but is returned.
fn by_rows<T: Send, E: std::fmt::Display>(
    rows: u32,
    out: &mut [T],
    threads: usize,
    bake_rows: impl Fn(Range<u32>, &mut [T]) -> Result<(), E> + Sync,
) -> Result<(), String> {
    let row_len = out.len() / rows as usize;
    let per_range = (rows as usize).div_ceil(256).max(1);
    let bar = ProgressBar::new(u64::from(rows));
    if std::io::stderr().is_terminal() {
        let style = ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} rows")
            .map_err(|e| e.to_string())?
            .progress_chars("=> ");
        bar.set_style(style);
    } else {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    let first_error = Mutex::new(None);
    par_chunks(out, per_range * row_len, threads, |at, part| {
        let start = (at / row_len) as u32;
        let range = start..start + (part.len() / row_len) as u32;
        let n = range.len() as u64;
        if let Err(e) = bake_rows(range, part) {
            first_error
                .lock()
                .expect("a bake thread panicked")
                .get_or_insert(e.to_string());
        }
        bar.inc(n);
    });
    bar.finish_and_clear();
    match first_error.into_inner().expect("a bake thread panicked") {
        Some(e) => Err(format!("bake: {e}")),
        None => Ok(()),
    }
}

/// A method baked for one field and surface: traces one ray at a time.
pub struct Tracer<'a> {
    hf: HeightField<'a>,
    method: MethodSpec,
    surface: Surface,
    plan: BakePlan,
    /// The map's description and texels (`None` for the bake-free methods).
    map: Option<(Desc, Texels)>,
    bake_time: Duration,
}

impl<'a> Tracer<'a> {
    /// Bakes `method` for `hf` and `surface` (one thread), for rays of the horizontal
    /// classes `classes` (the safety-shape maps hold only those; rays of other classes
    /// are still exact, cell by cell). What is baked is the core's bake plan of the
    /// scene ([`Scene::bake_plan`], [`Tracer::plan`]). Fails when the method does not
    /// trace `surface` ([`MethodSpec::supports`]).
    pub fn bake(
        hf: HeightField<'a>,
        method: MethodSpec,
        surface: Surface,
        classes: RayClasses,
    ) -> Result<Tracer<'a>, String> {
        Tracer::bake_for(hf, method, surface, classes, Rays::ALL, 1)
    }

    /// [`Tracer::bake`] with the safety-distance and cylinder–cone maps baked for the
    /// rays of `rays` (other methods ignore it; the march guards the rays outside it),
    /// on `threads` threads ([`bake_texels`]).
    pub fn bake_for(
        hf: HeightField<'a>,
        method: MethodSpec,
        surface: Surface,
        classes: RayClasses,
        rays: Rays,
        threads: usize,
    ) -> Result<Tracer<'a>, String> {
        if !method.supports(surface) {
            return Err(format!(
                "method {} does not trace the {} surface",
                method.name(),
                surface.name()
            ));
        }
        let scene = Scene {
            ray_classes: classes,
            ..Scene::general(method.kind(), surface)
        };
        let mut plan = scene.bake_plan();
        if plan.map_spec(2, 2).is_some_and(|s| s.desc.map.has_rays()) {
            plan.rays = rays;
        }
        let start = Instant::now();
        let map = match plan.map_spec(hf.width(), hf.height()) {
            Some(spec) => Some((spec.desc, bake_texels(&hf, &spec.desc, threads.max(1))?)),
            None => None,
        };
        Ok(Tracer {
            hf,
            method,
            surface,
            plan,
            map,
            bake_time: start.elapsed(),
        })
    }

    /// The method.
    pub fn method(&self) -> MethodSpec {
        self.method
    }

    /// The core's bake plan this tracer baked by (the one `hf_scene_bake_plan` gives for
    /// the same scene).
    pub fn plan(&self) -> &BakePlan {
        &self.plan
    }

    /// Wall time of the bake.
    pub fn bake_time(&self) -> Duration {
        self.bake_time
    }

    /// Bytes of baked data kept for the march.
    pub fn bytes(&self) -> usize {
        self.map.as_ref().map_or(0, |(_, t)| t.bytes())
    }

    /// Traces one ray.
    pub fn trace(&self, q: &Query<f32>) -> Trace<f32> {
        self.marcher().trace(&self.hf, q)
    }

    /// Traces `rays[k]` into `out[k]` (same lengths), one thread, in SIMD lanes where the
    /// method has them and the CPU can ([`Marcher::trace_all`]).
    pub fn trace_all(&self, rays: &[Query<f32>], out: &mut [Trace<f32>]) {
        self.marcher()
            .trace_all(&self.hf, rays, out, hfcast::detect_avx2!());
    }

    /// [`Tracer::trace_all`] one ray after another, never in SIMD lanes (the benchmark's
    /// `--order scalar`).
    pub fn trace_each(&self, rays: &[Query<f32>], out: &mut [Trace<f32>]) {
        let m = self.marcher();
        for (o, q) in out.iter_mut().zip(rays) {
            *o = m.trace(&self.hf, q);
        }
    }

    /// The core's marcher of the method over the baked map.
    fn marcher(&self) -> Marcher<'_> {
        let (hf, w, h) = (&self.hf, self.hf.width(), self.hf.height());
        let heights = Desc::new(MapKind::Heights, w, h);
        let desc = self.map.as_ref().map_or(&heights, |(d, _)| d);
        let texels = self.map.as_ref().map(|(_, t)| t.data());
        let o = self.method.march_options(self.surface);
        Marcher::of(self.method.kind(), hf, desc, texels, &o).expect("baked for this field")
    }
}

/// Parses one input line; `Ok(None)` for a blank or comment-only line.
pub fn parse_ray(line: &str) -> Result<Option<Query<f32>>, String> {
    let text = line.split('#').next().unwrap_or("");
    let fields: Vec<&str> = text.split_whitespace().collect();
    if fields.is_empty() {
        return Ok(None);
    }
    parse_fields(&fields).map(Some)
}

/// Parses `ox oy oz dx dy dz [t_min t_max]` from separate words.
pub fn parse_fields(fields: &[&str]) -> Result<Query<f32>, String> {
    if fields.len() != 6 && fields.len() != 8 {
        return Err(format!(
            "expected 6 or 8 numbers (ox oy oz dx dy dz [t_min t_max]), got {}",
            fields.len()
        ));
    }
    let mut v = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, f32::INFINITY];
    for (slot, word) in v.iter_mut().zip(fields) {
        *slot = word
            .parse()
            .map_err(|_| format!("not a number: {word:?}"))?;
    }
    Query::from_arrays([v[0], v[1], v[2]], [v[3], v[4], v[5]], v[6], v[7])
        .map_err(|e| e.to_string())
}

/// Formats a trace as one output line (without the newline).
pub fn format_trace(tr: &Trace<f32>) -> String {
    match tr.hit {
        Some(h) => format!(
            "hit {} {} {} {} {} {} {} {} {} {} {}",
            h.t,
            h.point.x,
            h.point.y,
            h.point.z,
            h.cell[0],
            h.cell[1],
            h.normal.x,
            h.normal.y,
            h.normal.z,
            tr.fetches,
            h.flags.0
        ),
        None => format!("miss {}", tr.fetches),
    }
}

/// Answers one input line: `None` for blank and comment lines, else the output line
/// and whether it is an error.
pub fn answer_line(tracer: &Tracer, line: &str) -> Option<(String, bool)> {
    match parse_ray(line) {
        Ok(None) => None,
        Ok(Some(q)) => Some((format_trace(&tracer.trace(&q)), false)),
        Err(e) => Some((format!("error {e}"), true)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines() {
        let h = [0.0f32, 1.0, 1.0, 2.0];
        let hf = HeightField::new(&h, 2, 2, 2).unwrap();
        let exact = MethodSpec::of(hfcast::scene::MethodKind::Exact);
        let tracer = Tracer::bake(hf, exact, Surface::Triangles, RayClasses::ALL).unwrap();
        let ask = |l: &str| answer_line(&tracer, l);
        assert_eq!(ask("  # nothing"), None);
        assert_eq!(ask(""), None);
        let (out, err) = ask("0.5 0.5 5 0 0 -1 # down").unwrap();
        assert!(!err && out.starts_with("hit 4 0.5 0.5 1 0 0 "), "{out}");
        assert_eq!(ask("5 5 5 0 0 1").unwrap(), ("miss 0".into(), false));
        assert!(ask("0 0 0 0 0 0").unwrap().1);
        assert!(ask("0 0 0 1 0").unwrap().1);
        assert!(ask("0 0 0 1 0 x").unwrap().1);
        assert!(ask("0 0 0 1 0 0 2 1").unwrap().1);
    }
}
