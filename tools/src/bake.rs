//! `hfcast bake`: bakes one method's map of a height map and writes it as a KTX 2 file
//! (the core's `ktx2`: one Vulkan format per map, the pyramid as mip levels, the bake's
//! settings as metadata).

use crate::Args;
use hfcast::bake::Spec;
use hfcast::ktx2::{self, Data, DataMut, Desc, MapKind};
use hfcast::scene::RayClasses;
use hfcast::HeightField;
use hfcast_tools::maps::{bundled_map, load_map};
use hfcast_tools::{default_threads, par_chunks};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Mutex;

/// The map of `--method` (and `--safety-variant`).
fn map_kind(method: &str, variant: Option<&str>) -> Result<MapKind, String> {
    let kind = match (method, variant) {
        ("safety", None | Some("directional")) => MapKind::Safety,
        ("safety", Some("isotropic")) => MapKind::SafetyIsotropic,
        ("safety", Some(v)) => return Err(format!("--safety-variant: unknown layout {v:?}")),
        (m, _) => MapKind::ALL
            .into_iter()
            .find(|k| k.method() == m)
            .ok_or(format!(
            "unknown method {m:?} (heights | maxmip | safety | cc | cone | relaxed | qdm | radius)"
        ))?,
    };
    Ok(kind)
}

/// Runs `hfcast bake`.
pub fn cmd_bake(mut args: Args) -> Result<bool, String> {
    let method = args.opt("method").ok_or("bake: --method is required")?;
    let variant = args.opt("safety-variant");
    let map = map_kind(&method, variant.as_deref())?;
    let path = args.opt("map").map_or(bundled_map(), PathBuf::from);
    let depth = match args.opt("depth") {
        Some(d) => Some(d.parse().map_err(|_| format!("--depth: bad value {d:?}"))?),
        None => None,
    };
    let out = PathBuf::from(args.opt("out").ok_or("bake: --out FILE.ktx2 is required")?);
    let cap = args.get("cap", map.default_cap())?;
    let classes = match args.opt("classes") {
        Some(list) => ktx2::parse_class_names(&list)
            .ok_or(format!("--classes: bad list {list:?} (x+, x-, y+, y-)"))?,
        None => RayClasses::ALL,
    };
    let tolerance = args.get("tolerance", 0.0f32)?;
    let rays: hfcast::rayset::Rays = match args.opt("rays") {
        None => hfcast::rayset::Rays::ALL,
        Some(r) => r.parse().map_err(|e| format!("--rays: {e}"))?,
    };
    let threads = args.get("threads", default_threads())?.max(1);
    args.finish()?;
    if let Some(p) = args.positional.first() {
        return Err(format!("bake: unexpected argument {p:?}"));
    }
    let loaded = load_map(&path, depth).map_err(|e| e.to_string())?;
    let hf = loaded.field();
    let desc = Desc {
        cap,
        classes,
        tolerance,
        rays,
        fingerprint: Some(hfcast::mapdesc::fingerprint(hf.samples())),
        ..Desc::new(map, hf.width(), hf.height())
    };
    let len = ktx2::len(&desc).map_err(|e| format!("bake: {e}"))?;
    eprintln!(
        "bake {} of {} ({} x {}, depth {}), {} threads",
        method,
        path.display(),
        hf.width(),
        hf.height(),
        loaded.depth,
        threads
    );
    let mut file = vec![0u8; len];
    let start = std::time::Instant::now();
    let baked = bake(&hf, &desc, threads)?;
    let seconds = start.elapsed().as_secs_f64();
    match baked {
        Baked::U8(m) => ktx2::write(&desc, Data::U8(&m), &mut file),
        Baked::F32(m) => ktx2::write(&desc, Data::F32(&m), &mut file),
    }
    .map_err(|e| format!("bake: {e}"))?;
    std::fs::write(&out, &file).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "wrote {} ({} bytes, {:?}; baked in {seconds:.2} s)",
        out.display(),
        len,
        map.format()
    );
    Ok(true)
}

/// A baked map.
enum Baked {
    U8(Vec<u8>),
    F32(Vec<f32>),
}

/// Bakes the map of `desc` on `threads` threads (the core's one bake interface,
/// `hfcast::bake::Spec`), rows in ranges, with a progress bar on a terminal.
fn bake(hf: &HeightField, desc: &Desc, threads: usize) -> Result<Baked, String> {
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
        Baked::F32(out)
    } else {
        let mut out = vec![0u8; n];
        by_rows(rows, &mut out, threads, |r, o| {
            spec.bake_rows(hf, scratch, r, DataMut::U8(o))
        })?;
        Baked::U8(out)
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
