//! `hfcast impostor capture|render`: the six-field impostors of a mesh
//! (`hfcast_tools::impostor`).

use crate::Args;
use hfcast::impostor::{Combine, Frustum};
use hfcast_tools::impostor::{capture, colour_error, load_mesh, render, Capture, Orbit};
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
        "export" => cmd_export(args),
        "colours" => cmd_colours(args),
        _ => Err(
            "impostor: want `capture MESH --out DIR`, `render DIR --out PNG` or `export MESH \
             --out FILE.obj`"
                .into(),
        ),
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
    // Orthographic by default: the more accurate faces for the default combination,
    // the intersection (docs/DESIGN.md, "Six-field impostors").
    let apex: Option<f64> = match args.opt("apex") {
        Some(a) => Some(a.parse().map_err(|_| format!("--apex: bad value {a:?}"))?),
        None => None,
    };
    let frustum = match args.opt("frustum").as_deref() {
        Some("reverse-perspective") => Frustum::ReversePerspective {
            apex: apex.unwrap_or(2.0),
        },
        None | Some("orthographic") if apex.is_some() => {
            return Err("--apex is for --frustum reverse-perspective".into())
        }
        None | Some("orthographic") => Frustum::Orthographic,
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

fn cmd_export(mut args: Args) -> Result<bool, String> {
    let out = PathBuf::from(
        args.opt("out")
            .ok_or("impostor export: --out FILE.obj is required")?,
    );
    args.finish()?;
    let path = one_path(&args, "mesh (.obj, .ply, or tower)")?;
    let data = load_mesh(&path)?;
    data.mesh()?;
    let mut text = format!(
        "# {} as OBJ, written by hfcast impostor export\n",
        path.display()
    );
    for p in &data.positions {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in &data.triangles {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(&out, text).map_err(|e| format!("{}: {e}", out.display()))?;
    println!("wrote {}", out.display());
    Ok(true)
}

/// A comma-separated list of sides, each 2 to 8192.
fn sides(args: &mut Args, name: &str, default: &str) -> Result<Vec<u32>, String> {
    args.list(
        name,
        default,
        |s: &u32| (2..=8192).contains(s),
        "sides of 2 to 8192",
    )
}

fn cmd_colours(mut args: Args) -> Result<bool, String> {
    let depth_sides = sides(&mut args, "depth-sides", "32,64,128,256")?;
    let colour_sides = sides(&mut args, "colour-sides", "32,64,128,256,512")?;
    let size = args.get("size", 192u32)?.max(1);
    args.finish()?;
    let path = one_path(&args, "mesh (.obj, .ply, or tower)")?;
    let data = load_mesh(&path)?;
    let orbit = Orbit::default();
    println!(
        "Colour texels against the mesh's colour at its first hit, {size} × {size} pixels, \
         orbit {}° up, azimuth {}°, reverse perspective, intersection of the six fields \
         (`hfcast impostor colours`): pixels of another colour (any channel off by more \
         than 8 of 255) among those both hit, and the mean difference per channel.\n",
        orbit.elevation, orbit.azimuth
    );
    let head: Vec<String> = colour_sides
        .iter()
        .map(|c| format!("colour {c}²"))
        .collect();
    println!("| depth side | {} |", head.join(" | "));
    println!("|---:|{}", "---:|".repeat(colour_sides.len()));
    for &d in &depth_sides {
        let mut row = format!("| {d}² |");
        for &c in &colour_sides {
            let cap = capture(&data, hfcast::impostor::Frustum::DEFAULT_REVERSE, d, c)?;
            let r = render(&cap, Combine::Intersection, orbit, size, size)?;
            let e = colour_error(&data, &cap, &r, orbit)?;
            row += &format!(
                " {:.2} % ({:.1}) |",
                100.0 * e.wrong as f64 / e.both.max(1) as f64,
                e.mean_abs
            );
        }
        println!("{row}");
    }
    Ok(true)
}
