//! `hfcast bake`: bakes one method's map of a height map and writes it as a KTX 2 file
//! (the core's `ktx2`: one Vulkan format per map, the pyramid as mip levels, the bake's
//! settings as metadata).

use crate::Args;
use hfcast::bake::Texels;
use hfcast::ktx2::{self, Data, Desc, MapKind};
use hfcast::scene::RayClasses;
use hfcast_tools::default_threads;
use hfcast_tools::maps::{bundled_map, load_map};
use hfcast_tools::trace::bake_texels;
use std::path::PathBuf;

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
    let rays = hfcast_tools::parse_ray_set(args.opt("rays"))?;
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
    let baked = bake_texels(&hf, &desc, threads)?;
    let seconds = start.elapsed().as_secs_f64();
    match baked {
        Texels::U8(m) => ktx2::write(&desc, Data::U8(&m), &mut file),
        Texels::F32(m) => ktx2::write(&desc, Data::F32(&m), &mut file),
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
