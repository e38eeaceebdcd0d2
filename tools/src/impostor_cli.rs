//! `hfcast impostor capture|render`: the six-field impostors of a mesh
//! (`hfcast_tools::impostor`).

use crate::Args;
use hfcast::impostor::{Combine, Frustum};
use hfcast_tools::impostor::{capture, load_mesh, render, Capture, Orbit};
use std::path::PathBuf;

/// Runs `hfcast impostor SUBCOMMAND`.
pub fn cmd_impostor(mut args: Args) -> Result<bool, String> {
    let sub = if args.positional.is_empty() {
        String::new()
    } else {
        args.positional.remove(0)
    };
    match sub.as_str() {
        "capture" => cmd_capture(args),
        "render" => cmd_render(args),
        _ => Err("impostor: want `capture MESH --out DIR` or `render DIR --out PNG`".into()),
    }
}

/// The one positional argument.
fn one_path(args: &Args, what: &str) -> Result<PathBuf, String> {
    match &args.positional[..] {
        [p] => Ok(PathBuf::from(p)),
        _ => Err(format!("impostor: want one {what}")),
    }
}

fn cmd_capture(mut args: Args) -> Result<bool, String> {
    let out = PathBuf::from(
        args.opt("out")
            .ok_or("impostor capture: --out DIR is required")?,
    );
    let side = args.get("side", 128u32)?;
    let colour_side = args.get("colour-side", 256u32)?;
    let frustum = match args.opt("frustum").as_deref() {
        None | Some("reverse-perspective") => Frustum::ReversePerspective {
            apex: args.get("apex", 2.0f64)?,
        },
        Some("orthographic") => Frustum::Orthographic,
        Some(f) => {
            return Err(format!(
                "--frustum: {f:?} (orthographic | reverse-perspective)"
            ))
        }
    };
    args.finish()?;
    let path = one_path(&args, "mesh (.obj, .ply, or tower)")?;
    for (name, s) in [("--side", side), ("--colour-side", colour_side)] {
        if !(2..=8192).contains(&s) {
            return Err(format!("{name} {s}: want 2 to 8192"));
        }
    }
    let data = load_mesh(&path)?;
    eprintln!(
        "mesh {}: {} vertices, {} triangles",
        path.display(),
        data.positions.len(),
        data.triangles.len()
    );
    let t = std::time::Instant::now();
    let cap = capture(&data, frustum, side, colour_side)?;
    eprintln!("captured in {:.2} s", t.elapsed().as_secs_f64());
    cap.write(&out)?;
    println!("wrote {}", out.display());
    Ok(true)
}

fn cmd_render(mut args: Args) -> Result<bool, String> {
    let out = PathBuf::from(args.opt("out").unwrap_or("out/impostor.png".into()));
    let d = Orbit::default();
    let orbit = Orbit {
        elevation: args.get("elevation", d.elevation)?,
        azimuth: args.get("azimuth", d.azimuth)?,
        distance: args.get("distance", d.distance)?,
        fov_deg: args.get("fov", d.fov_deg)?,
    };
    let combine = match args.opt("combine") {
        None => Combine::Intersection,
        Some(c) => Combine::from_name(&c)
            .ok_or(format!("--combine: {c:?} (intersection | facing-field)"))?,
    };
    let (w, h) = (args.get("width", 512u32)?, args.get("height", 512u32)?);
    args.finish()?;
    if !(orbit.distance > 1.8 && orbit.distance.is_finite()) {
        return Err("--distance: want a camera outside the cube (over 1.8 half sides)".into());
    }
    if !(orbit.fov_deg > 0.0 && orbit.fov_deg < 170.0) || w == 0 || h == 0 {
        return Err("--fov in (0, 170) and a positive --width and --height, please".into());
    }
    let cap = Capture::read(&one_path(&args, "capture directory")?)?;
    let t = std::time::Instant::now();
    let r = render(&cap, combine, orbit, w, h)?;
    let secs = t.elapsed().as_secs_f64();
    let hits = r.depth.iter().filter(|d| d.is_finite()).count();
    println!(
        "{w} x {h}, {}: {hits} pixels hit, {:.2} field traces per pixel, {:.1} ms",
        combine.name(),
        r.traces as f64 / f64::from(w * h),
        secs * 1e3
    );
    hfcast_tools::render::write_png(&out, &r.image).map_err(|e| e.to_string())?;
    println!("wrote {}", out.display());
    Ok(true)
}
