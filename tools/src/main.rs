//! `hfcast`: render, trace and benchmark height fields from the command line.

use hfcast::scene::{MethodKind, RayClasses};
use hfcast::{Surface, WorldTransform};
use hfcast_tools::advise::{self, AdviseOptions};
use hfcast_tools::bench::{self, bench_rays, markdown_table, random_rays};
use hfcast_tools::maps::{bundled_map, shared_data_dir, Depth, Map, MapSpec, Nodata};
use hfcast_tools::render::{heat_maps, render, write_png, Camera, RenderOptions};
use hfcast_tools::report::{self, ReportOptions};
use hfcast_tools::table1::{self, Table1Options};
use hfcast_tools::trace::{self, Tracer};
use hfcast_tools::{default_threads, parse_method, MethodSpec};
use std::collections::HashMap;
use std::io::{BufRead, IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;

const USAGE: &str = "\
usage: hfcast <command> [options]

commands:
  render   ray-cast a shaded, shadowed image, and beside it (unless --no-heatmaps)
           its depth and fetch-count heat maps, PATH.depth.png and PATH.fetches.png
           --map PATH --depth GRID_UNITS --method M|auto (default maxmip; auto:
           advise's choice, measured on the scene)
           --surface S --elevation DEG --azimuth DEG --light-elevation DEG
           --light-azimuth DEG --width N --height N --threads N
           --rays all|exterior|angle:A|exterior,angle:A (all): the ray set the safety
           and cylinder-cone maps are baked for; exterior traces the shadow rays from
           the light's side, as exterior rays
           --out PATH (default out/render.png) --no-heatmaps
           --exaggerate F (heights x F in the picture; 1: a map with real units in
           its real proportions, whatever --depth, which sets the grid's relief)
  advise   measure every exact method on render's rays (the same options): bake
           time and bytes, ns/ray and fetches/ray (one thread, median of --reps N, 3),
           and choose the least one-frame time (bake + rays x ns) of the Pareto set
  trace    answer ray queries: hfcast trace [options] ox oy oz dx dy dz [t_min t_max]
           or, with no ray or '-', one ray per line from stdin ('#' comments)
           --map PATH --depth GRID_UNITS --method M --surface S
           out: 'hit t x y z cell_i cell_j nx ny nz fetches flags' | 'miss fetches'
  bench    rays/s, fetches/ray and hit rate of camera and random rays
           --map PATH (default ../shared/data/dem_etopo5_himalaya_1024.png)
           --depth GRID_UNITS --reps N (3) --random N (1000000) --size WxH (1280x1024)
           --threads LIST (1,2) --method M --surface S --order lanes|scalar
           (lanes, the default: 16 rays at once in AVX-512, 8 in AVX2, where the
           method and CPU can)
           --rays all|exterior|angle:A|exterior,angle:A (all): the ray set the safety
           and cylinder-cone maps are baked for (rays outside it march cell by cell)
  report   error against run time of every method setting vs the f64 oracle, on every
           map of ../shared/data at two depths and synthetic fields: Markdown + SVG plots
           (a map that cannot be read is skipped with a warning)
           --quick (CI smoke test: small scenes, every map's centre 128 x 128 samples,
           short sweep) --out DIR (out/report)
           --reps N (3) --size WxH (160x120; quick 64x48) --synthetic N (512;
           quick 128) --threads N (oracle only; timing is single-threaded)
           --scenes WORD,WORD (keep scenes whose name contains a word)
  table1   the paper's Table 1 side by side: safety distances and cylinder-cones for
           every ray and exterior rays, without and with phi_max = -45 deg, on centre
           crops: bake s, bytes, fetches/ray, ns/ray of a 45 deg camera, rays that
           differ from the exact traversal (none)
           --map PATH (default ../shared/data/dem_etopo5_himalaya_1024.png) --depth
           GRID_UNITS --sides LIST (256,512,1024) --threads N (bakes; all cores)
           --size WxH (320x256) --elevations LIST (45,70: a camera each; at 70
           every ray is within phi_max) --reps N (3) --out FILE (docs/report/table1.md)
  shader   the GLSL or WGSL shader of one scene: only the code it uses
           --method M (exact | linear-binary | linear-secant | maxmip | safety | cone |
           relaxed | qdm | cc; default exact) --surface S (triangles) --lang glsl|wgsl
           (glsl) --rays x+,x-,y+,y- (all) --max-view-angle DEG (180) --heights
           f32|u16|u8 (f32) --safety-variant directional|isotropic (directional)
           --no-shadows --shadows-from-light (traced down from the light's side, as
           exterior rays) --outside-only --occluders (maps baked over occluders: keep
           their guard) --no-depth --lod --all-methods (every method in one shader,
           hf_method chosen at run time) --out FILE (default stdout)
  bake     bake one method's map and write it as a KTX 2 file (hfcast::ktx2)
           --method heights|maxmip|safety|cc|cone|relaxed|qdm|radius --map PATH
           --depth GRID_UNITS --out FILE.ktx2 --cap N (safety, radius 255; cc 64)
           --classes x+,x-,y+,y- (all; safety, cc) --safety-variant
           directional|isotropic --tolerance E (radius, 0) --threads N (all cores)
           --rays all|exterior|angle:A|exterior,angle:A (all; safety, cc)

  impostor six reverse-perspective height fields of a triangle mesh (an object's
           impostor): impostor capture MESH (.obj, .ply, or tower: a procedural one)
           --out DIR --side N (128) --colour-side N (256: colour and normal textures)
           --frustum orthographic|reverse-perspective (orthographic: the more
           accurate for the intersection) --apex HALF_SIDES (2, reverse perspective);
           impostor render DIR --out PNG --width N --height N (512) --elevation DEG
           --azimuth DEG (30) --distance HALF_SIDES (4) --fov DEG (40) --combine
           intersection|facing-field (intersection: the six solids' intersection); impostor export
           MESH --out FILE.obj (the mesh as OBJ: a PLY, or the procedural tower)

angles: compass degrees (azimuth 0 = north = image top of the map, 90 = east)
maps: grayscale PNG, heights = png/65535 * depth; depth defaults to 0.1 * max(W, H);
      its JSON sidecar gives metres and spacing (world units); GeoTIFF DEM (.tif):
      real proportion by default, --nodata refuse|lowest|HEIGHT (refuse); raw
      little-endian f32 in grid units: --raw-size WxH; --depth real: heights in
      their real proportion to the spacing; default map: the bundled
      data/dem_jacksboro_fault_403x344.png";

mod bake;
mod impostor_cli;
mod shader;

/// Options that take no value (`--quick` is `--quick=true`).
const FLAGS: [&str; 2] = ["quick", "no-heatmaps"];

/// `--name value` / `--name=value` options, `--flag`s ([`FLAGS`]) and positional words
/// of one command line.
struct Args {
    opts: HashMap<String, String>,
    positional: Vec<String>,
}

impl Args {
    fn parse(words: impl Iterator<Item = String>) -> Result<Args, String> {
        let (mut opts, mut positional) = (HashMap::new(), Vec::new());
        let mut words = words.peekable();
        while let Some(w) = words.next() {
            let Some(name) = w.strip_prefix("--") else {
                positional.push(w);
                continue;
            };
            let (name, value) = match name.split_once('=') {
                Some((n, v)) => (n.to_string(), v.to_string()),
                None if FLAGS.contains(&name) || shader::FLAGS.contains(&name) => {
                    (name.to_string(), "true".to_string())
                }
                None => {
                    let v = words.next().ok_or(format!("--{name} needs a value"))?;
                    (name.to_string(), v)
                }
            };
            opts.insert(name, value);
        }
        Ok(Args { opts, positional })
    }

    /// Removes option `name` and parses it, or gives `default`.
    fn get<T: FromStr>(&mut self, name: &str, default: T) -> Result<T, String> {
        match self.opts.remove(name) {
            Some(v) => v.parse().map_err(|_| format!("--{name}: bad value {v:?}")),
            None => Ok(default),
        }
    }

    /// Removes option `name` if given.
    fn opt(&mut self, name: &str) -> Option<String> {
        self.opts.remove(name)
    }

    /// Removes `--name A,B,…` (or takes `default`) and parses each item, each one that
    /// `ok` refuses an error that says what is wanted (`want`).
    fn list<T: FromStr>(
        &mut self,
        name: &str,
        default: &str,
        ok: impl Fn(&T) -> bool,
        want: &str,
    ) -> Result<Vec<T>, String> {
        let text = self.opt(name).unwrap_or(default.into());
        text.split(',')
            .map(|t| t.parse().ok().filter(&ok))
            .collect::<Option<_>>()
            .ok_or(format!("--{name}: bad list {text:?} (want {want})"))
    }

    /// Removes `--size WxH` and parses it (both positive), or gives `default`.
    fn size(&mut self, default: (u32, u32)) -> Result<(u32, u32), String> {
        let Some(size) = self.opt("size") else {
            return Ok(default);
        };
        size.split_once('x')
            .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
            .filter(|&(w, h)| w > 0 && h > 0)
            .ok_or(format!("--size: bad value {size:?} (want WxH)"))
    }

    /// Fails on options nobody asked for.
    fn finish(&self) -> Result<(), String> {
        match self.opts.keys().next() {
            Some(k) => Err(format!("unknown option --{k}")),
            None => Ok(()),
        }
    }

    /// `--method` and `--surface`.
    fn method_surface(&mut self) -> Result<(MethodSpec, Surface), String> {
        let method = parse_method(&self.opt("method").unwrap_or("exact".into()))?;
        let name = self.opt("surface").unwrap_or("triangles".into());
        let surface = Surface::from_name(&name).ok_or(format!("unknown surface {name:?}"))?;
        Ok((method, surface))
    }

    /// `--map` (default `default`), `--depth` (grid units, or `real`), `--nodata`
    /// (`refuse`, `lowest` or a height) and `--raw-size WxH`.
    fn map(&mut self, default: PathBuf) -> Result<MapSpec, String> {
        let mut spec = MapSpec::new(self.opt("map").map_or(default, PathBuf::from));
        spec.depth = match self.opt("depth").as_deref() {
            None => Depth::Default,
            Some("real") => Depth::Real,
            Some(d) => Depth::Grid(d.parse().map_err(|_| format!("--depth: bad value {d:?}"))?),
        };
        spec.nodata = match self.opt("nodata").as_deref() {
            None | Some("refuse") => Nodata::Refuse,
            Some("lowest") => Nodata::FillLowest,
            Some(v) => Nodata::Fill(
                v.parse()
                    .map_err(|_| format!("--nodata: bad value {v:?}"))?,
            ),
        };
        if let Some(size) = self.opt("raw-size") {
            spec.raw_size = Some(
                parse_size(&size).ok_or(format!("--raw-size: bad value {size:?} (want WxH)"))?,
            );
        }
        Ok(spec)
    }
}

/// `WxH` with both positive.
fn parse_size(s: &str) -> Option<(u32, u32)> {
    let (w, h) = s.split_once('x')?;
    Some((w.parse().ok()?, h.parse().ok()?)).filter(|&(w, h)| w > 0 && h > 0)
}

/// Loads a map and says so on stderr (with its real spacing when it has one).
fn load(spec: &MapSpec) -> Result<Map, String> {
    let map = spec.load().map_err(|e| e.to_string())?;
    let xf = map.transform;
    let units = if xf.is_identity() {
        String::new()
    } else {
        let [sx, sy] = xf.spacing();
        format!(
            ", spacing {:.1} x {:.1} m, {:.3} m per grid height unit",
            sx.abs(),
            sy.abs(),
            xf.height_scale()
        )
    };
    eprintln!(
        "map {} ({} x {}), depth {} grid units{units}",
        spec.path.display(),
        map.width,
        map.height,
        map.depth
    );
    Ok(map)
}

/// The render options of `render` and `advise` (`--surface`, camera, light,
/// `--threads`), with `method`.
fn render_options(args: &mut Args, method: MethodSpec) -> Result<RenderOptions, String> {
    let name = args.opt("surface").unwrap_or("triangles".into());
    let surface = Surface::from_name(&name).ok_or(format!("unknown surface {name:?}"))?;
    let d = RenderOptions::default();
    let opts = RenderOptions {
        method,
        surface,
        elevation: args.get("elevation", d.elevation)?,
        azimuth: args.get("azimuth", d.azimuth)?,
        light_elevation: args.get("light-elevation", d.light_elevation)?,
        light_azimuth: args.get("light-azimuth", d.light_azimuth)?,
        width: args.get("width", d.width)?,
        height: args.get("height", d.height)?,
        threads: args.get("threads", d.threads)?,
        progress: std::io::stderr().is_terminal(),
        rays: hfcast_tools::parse_ray_set(args.opt("rays"))?,
    };
    if opts.width == 0 || opts.height == 0 {
        return Err("--width and --height must be positive".into());
    }
    Ok(opts)
}

/// Measures the exact methods on a render's rays (stderr names each) and returns the
/// advice.
fn measure_advice(
    hf: &hfcast::HeightField,
    opts: &RenderOptions,
    how: AdviseOptions,
) -> Result<advise::Advice, String> {
    advise::advise(hf, opts, how, |m| {
        eprintln!("advise: measuring {}", m.name())
    })
}

fn cmd_render(mut args: Args) -> Result<bool, String> {
    let map_spec = args.map(bundled_map())?;
    // The default: the fastest exact method for one frame on the measured scenes
    // (advise, README "Command line"); `auto` measures the scene's own.
    let name = args.opt("method").unwrap_or("maxmip".into());
    let auto = name == "auto";
    let method = if auto {
        MethodSpec::of(MethodKind::Exact)
    } else {
        parse_method(&name)?
    };
    let mut opts = render_options(&mut args, method)?;
    let out = PathBuf::from(args.opt("out").unwrap_or("out/render.png".into()));
    let heatmaps = !args.get("no-heatmaps", false)?;
    let exaggerate = args.get("exaggerate", 1.0f64)?;
    args.finish()?;
    let map = load(&map_spec)?;
    let xf = map.transform;
    let shown = WorldTransform::new(
        xf.origin(),
        xf.spacing(),
        xf.height_scale() * exaggerate,
        xf.height_offset(),
    )
    .map_err(|e| format!("--exaggerate {exaggerate}: {e}"))?;
    let hf = map.field().with_transform(shown);
    if auto {
        // Every 8th ray timed, one repetition: the choice in a fraction of a frame.
        let how = AdviseOptions { reps: 1, every: 8 };
        let advice = measure_advice(&hf, &opts, how)?;
        eprint!("{}", advise::markdown(&advice));
        opts.method = advice.chosen().method;
    }
    eprintln!(
        "render {} x {}, method {}, surface {}, elevation {}, azimuth {}, {} threads",
        opts.width,
        opts.height,
        opts.method.name(),
        opts.surface.name(),
        opts.elevation,
        opts.azimuth,
        opts.threads
    );
    let frame = render(&hf, &opts)?;
    eprintln!("bake plan: {}", advise::plan_text(&frame.plan));
    write_png(&out, &frame.image).map_err(|e| e.to_string())?;
    println!("{}", frame.stats.summary());
    println!("wrote {}", out.display());
    if heatmaps {
        let [(depth, d0, d1), (fetches, _, p99)] = heat_maps(&frame);
        let most = frame.fetches.iter().max().copied().unwrap_or(0);
        for (ext, image, what) in [
            ("depth.png", depth, format!("depth {d0:.1} .. {d1:.1} world units (metres for a map with real units) from the eye, sky black")),
            ("fetches.png", fetches, format!("fetches a pixel, primary + shadow ray: 0 .. {p99} (99th percentile; most {most})")),
        ] {
            let path = out.with_extension(ext);
            write_png(&path, &image).map_err(|e| e.to_string())?;
            println!("wrote {} ({what}; dark blue, blue, cyan, green, yellow, red)", path.display());
        }
    }
    Ok(true)
}

fn cmd_advise(mut args: Args) -> Result<bool, String> {
    let map_spec = args.map(bundled_map())?;
    let mut opts = render_options(&mut args, MethodSpec::of(MethodKind::Exact))?;
    let how = AdviseOptions {
        reps: args.get("reps", AdviseOptions::default().reps)?.max(1),
        every: 1,
    };
    args.finish()?;
    if let Some(p) = args.positional.first() {
        return Err(format!("advise: unexpected argument {p:?}"));
    }
    opts.progress = false;
    let map = load(&map_spec)?;
    let advice = measure_advice(&map.field(), &opts, how)?;
    println!(
        "## hfcast advise: {}, {} x {}, elevation {}, azimuth {}, surface {}\n",
        map_spec
            .path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy(),
        opts.width,
        opts.height,
        opts.elevation,
        opts.azimuth,
        opts.surface.name()
    );
    print!("{}", advise::markdown(&advice));
    Ok(true)
}

fn cmd_trace(mut args: Args) -> Result<bool, String> {
    let map_spec = args.map(bundled_map())?;
    let (method, surface) = args.method_surface()?;
    args.finish()?;
    let map = load(&map_spec)?;
    let tracer = Tracer::bake(map.field(), method, surface, RayClasses::ALL)?;
    if !tracer.plan().bakes_nothing() {
        eprintln!(
            "baked {} in {:.3} s: {} bytes ({})",
            method.name(),
            tracer.bake_time().as_secs_f64(),
            tracer.bytes(),
            advise::plan_text(tracer.plan())
        );
    }
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut ok = true;
    let mut answer = |line: &str| -> Result<(), String> {
        if let Some((text, err)) = trace::answer_line(&tracer, line) {
            ok &= !err;
            writeln!(out, "{text}").map_err(|e| e.to_string())?;
        }
        Ok(())
    };
    match args.positional.as_slice() {
        [] => read_lines(&mut answer)?,
        [dash] if dash == "-" => read_lines(&mut answer)?,
        words => answer(&words.join(" "))?,
    }
    Ok(ok)
}

fn read_lines(answer: &mut impl FnMut(&str) -> Result<(), String>) -> Result<(), String> {
    for line in std::io::stdin().lock().lines() {
        answer(&line.map_err(|e| e.to_string())?)?;
    }
    Ok(())
}

fn cmd_bench(mut args: Args) -> Result<bool, String> {
    let default_map = shared_data_dir().join("dem_etopo5_himalaya_1024.png");
    let map_spec = args.map(default_map)?;
    let (method, surface) = args.method_surface()?;
    let reps = args.get("reps", 3usize)?;
    let n_random = args.get("random", 1_000_000usize)?;
    let order = match args.opt("order").as_deref() {
        None | Some("lanes") => bench::Order::Lanes,
        Some("scalar") => bench::Order::Scalar,
        Some(o) => return Err(format!("--order: bad value {o:?} (want scalar or lanes)")),
    };
    let rays = hfcast_tools::parse_ray_set(args.opt("rays"))?;
    let (w, h) = args.size((1280, 1024))?;
    let threads: Vec<usize> = args.list("threads", "1,2", |_| true, "thread counts")?;
    args.finish()?;
    let map = load(&map_spec)?;
    let hf = map.field();
    let tracer = Tracer::bake_for(hf, method, surface, RayClasses::ALL, rays, 1)?;
    println!(
        "## hfcast bench: {} ({} x {}), depth {}, {} reps (median), {} cores available\n",
        map_spec
            .path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy(),
        map.width,
        map.height,
        map.depth,
        reps,
        default_threads()
    );
    println!(
        "bake: {:.2} s (one thread), {} bytes, ray set {rays}\n",
        tracer.bake_time().as_secs_f64(),
        tracer.bytes()
    );
    let mut results = Vec::new();
    for elevation in [45.0, 5.0] {
        let rays = Camera::orbit(&hf, elevation, 200.0, w, h).rays();
        let name = format!("camera {w}x{h}, elevation {elevation}°");
        eprintln!("bench: {name}");
        results.push(bench_rays(&tracer, &name, &rays, &threads, reps, order));
    }
    if n_random > 0 {
        let rays = random_rays(&hf, n_random, 1);
        eprintln!("bench: random rays");
        let name = "random, origin in box";
        results.push(bench_rays(&tracer, name, &rays, &threads, reps, order));
    }
    println!("{}", markdown_table(method, surface, &results));
    Ok(true)
}

fn cmd_table1(mut args: Args) -> Result<bool, String> {
    let default_map = shared_data_dir().join("dem_etopo5_himalaya_1024.png");
    let map_spec = args.map(default_map)?;
    let sides = args.list("sides", "256,512,1024", |&s| s >= 2, "sides of at least 2")?;
    let opts = Table1Options {
        sides,
        threads: args.get("threads", default_threads())?.max(1),
        size: args.size((320, 256))?,
        elevations: args.list(
            "elevations",
            "45,70",
            |&e: &f64| e > 0.0 && e <= 90.0,
            "degrees in (0, 90]",
        )?,
        reps: args.get("reps", 3usize)?.max(1),
    };
    let out = PathBuf::from(args.opt("out").unwrap_or("docs/report/table1.md".into()));
    args.finish()?;
    let map = load(&map_spec)?;
    let name = map_spec
        .path
        .file_name()
        .unwrap_or_default()
        .to_string_lossy();
    let table = table1::run(&name, &map.heights, map.width, map.height, &opts);
    let command: Vec<String> = std::iter::once("hfcast".to_string())
        .chain(std::env::args().skip(1))
        .collect();
    let text = format!(
        "# Table 1 of Baboud, Eisemann, Seidel (2011), side by side\n\n\
         Made by `{}` (`tools/src/table1.rs`), the whole file by `bash scripts/table1.sh`.\n\n\
         The paper's own bakes at 1024² (as issue 20 quotes its Table 1): cyl_ext 1,197 s, \
         cyl_ext+cone_ext 24,111 s. Its other columns (frame rates on its GPU) are not \
         reproduced: no copy of the paper's table is reachable from this machine.\n\n\
         ## CPU: bakes, fetches and ns per ray\n\n{table}",
        command.join(" ")
    );
    std::fs::write(&out, &text).map_err(|e| format!("{}: {e}", out.display()))?;
    println!("{table}");
    println!("wrote {}", out.display());
    Ok(true)
}

fn cmd_report(mut args: Args) -> Result<bool, String> {
    let quick = args.get("quick", false)?;
    let out = PathBuf::from(args.opt("out").unwrap_or("out/report".into()));
    let mut opts = ReportOptions::new(quick, out);
    opts.reps = args.get("reps", opts.reps)?;
    opts.size = args.size(opts.size)?;
    opts.synthetic_size = args.get("synthetic", opts.synthetic_size)?;
    if opts.synthetic_size < 2 {
        return Err("--synthetic must be at least 2".into());
    }
    opts.threads = args.get("threads", opts.threads)?.max(1);
    if let Some(words) = args.opt("scenes") {
        opts.only = words.split(',').map(String::from).collect();
    }
    args.finish()?;
    if let Some(p) = args.positional.first() {
        return Err(format!("report: unexpected argument {p:?}"));
    }
    opts.command = std::iter::once("hfcast".to_string())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let summary = report::run(&opts)?;
    println!("{summary}");
    println!("wrote {}", opts.out.join("README.md").display());
    Ok(true)
}

fn main() -> ExitCode {
    let mut words = std::env::args().skip(1);
    let command = words.next().unwrap_or_default();
    let run = |f: fn(Args) -> Result<bool, String>| Args::parse(words).and_then(f);
    let result = match command.as_str() {
        "render" => run(cmd_render),
        "trace" => run(cmd_trace),
        "advise" => run(cmd_advise),
        "bench" => run(cmd_bench),
        "report" => run(cmd_report),
        "table1" => run(cmd_table1),
        "shader" => run(shader::cmd_shader),
        "bake" => run(bake::cmd_bake),
        "impostor" => run(impostor_cli::cmd_impostor),
        "help" | "--help" | "-h" => {
            let (top, rest) = USAGE.split_at(USAGE.find("angles: ").unwrap_or(USAGE.len()));
            println!("{top}{}{rest}", hfcast_tools::methods_help());
            return ExitCode::SUCCESS;
        }
        "" => Err("no command given; try `hfcast help`".into()),
        other => Err(format!("unknown command {other:?}; try `hfcast help`")),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("hfcast: {e}");
            ExitCode::from(2)
        }
    }
}
