//! `hfcast report`: error against run time for every method setting on the same rays,
//! judged against the `f64` exact oracle, written as Markdown with SVG plots.
//!
//! Scenes: every map of the shared data folder at two depths, synthetic fields
//! (fractal, 1-texel walls, needles, max/min checkerboard, flat), a few of them on the
//! bilinear surface too. Rays: orbit cameras at 45°, 15° and 5° elevation, a camera
//! inside the box looking sideways, and shadow rays from the first camera's hits
//! towards a light. Methods: [`methods::settings`], with parry3d's height field as a
//! peer. The definitions (wrong, ambiguous, costs) are written into the report itself.

pub mod markdown;
pub mod measure;
pub mod methods;
pub mod parry;
pub mod plot;
pub mod scenes;

use measure::{measure, oracle, Measured};
use methods::{settings, Setting, Sweep};
use scenes::{map_scenes, ray_sets, RaySet, Scene, Synthetic};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

/// What `hfcast report` does.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// Small scenes, small images, a shorter sweep, one timing repetition.
    pub quick: bool,
    /// Output folder (`README.md`, `results.csv`, `plots/*.svg`).
    pub out: PathBuf,
    /// Timing repetitions (median).
    pub reps: usize,
    /// Image size of every camera, pixels.
    pub size: (u32, u32),
    /// Side of the synthetic fields.
    pub synthetic_size: u32,
    /// Side of the small synthetic fractal, the scene the slow bakes (relaxed cone
    /// stepping; in `--quick` cone steps and QDM too) fit on.
    pub small_size: u32,
    /// Threads for the oracle (timing is always single-threaded).
    pub threads: usize,
    /// Keep only scenes whose name contains one of these words (all when empty).
    pub only: Vec<String>,
    /// The command line, quoted in the report.
    pub command: String,
}

impl ReportOptions {
    /// The defaults of the full report or of `--quick`.
    pub fn new(quick: bool, out: PathBuf) -> ReportOptions {
        ReportOptions {
            quick,
            out,
            reps: 3,
            size: if quick { (64, 48) } else { (160, 120) },
            synthetic_size: if quick { 128 } else { 512 },
            small_size: if quick { 64 } else { 96 },
            threads: crate::default_threads(),
            only: Vec::new(),
            command: String::new(),
        }
    }
}

/// Shadow rays start this many [`LIFT_UNIT`]s straight above the surface point they
/// leave.
pub const SHADOW_LIFT: f64 = 4.0;

/// The unit of [`SHADOW_LIFT`]: `2⁻¹³ · max(1, |z|)`, `|z|` the field's largest
/// |height| (the ambiguity threshold before docs/DESIGN.md's resolution δ; kept so that the
/// shadow rays stay the same rays).
pub const LIFT_UNIT: f64 = 1.0 / 8192.0;

/// Side of the centre crop of every map in the `--quick` report (the full report
/// takes the whole maps).
pub const QUICK_CROP: u32 = 128;

/// Everything measured on one scene.
pub struct SceneResult {
    /// The scene (heights dropped after measuring).
    pub scene: Scene,
    /// Ray set names, sizes and whether they are pixels.
    pub sets: Vec<(String, usize, bool)>,
    /// Ambiguous rays per set.
    pub ambiguous: Vec<u64>,
    /// Oracle hits per set.
    pub oracle_hits: Vec<u64>,
    /// Seconds the oracle took (all threads).
    pub oracle_s: f64,
    /// One entry per setting traced on the scene.
    pub measured: Vec<Measured>,
    /// Settings (indices) of the scene's surface skipped because the field is over
    /// their [`Setting::max_texels`].
    pub skipped: Vec<usize>,
}

/// Whether the scene named `name` passes `--scenes`.
fn kept(opts: &ReportOptions, name: &str) -> bool {
    opts.only.is_empty() || opts.only.iter().any(|w| name.contains(w.as_str()))
}

/// Builds the scene list, and says which maps could not be read (one line each: they
/// are skipped). Maps no scene of `--scenes` names are never read.
pub fn build_scenes(opts: &ReportOptions) -> Result<(Vec<Scene>, Vec<String>), String> {
    let crop = opts.quick.then_some(QUICK_CROP);
    let (mut list, skipped) = map_scenes(|name| kept(opts, name), crop);
    if list.is_empty() && kept(opts, &scenes::bundled_name()) {
        list.push(scenes::bundled_scene().map_err(|e| e.to_string())?);
    }
    let n = opts.synthetic_size;
    for kind in Synthetic::ALL {
        list.push(kind.scene(n, hfcast::Surface::Triangles));
    }
    // A small field for the bakes too slow for `--quick` on the others.
    let mut small = Synthetic::Fractal.scene(opts.small_size, hfcast::Surface::Triangles);
    small.name = format!("{}-{}", small.name, opts.small_size);
    list.push(small);
    // The bilinear surface (where the iterative bilinear settings apply).
    for kind in [Synthetic::Fractal, Synthetic::Checkerboard] {
        list.push(kind.scene(n, hfcast::Surface::Bilinear));
    }
    // Qu et al.'s fixed-diagonal triangles, beside the triangle scenes of the same
    // fields (the cost of their division-free test).
    list.push(Synthetic::Fractal.scene(n, hfcast::Surface::QuTriangles));
    if let Some(first) = list
        .first()
        .filter(|s| !s.name.starts_with("synthetic"))
        .cloned()
    {
        for (surface, suffix, what) in [
            (hfcast::Surface::Bilinear, "bilinear", "bilinear surface"),
            (
                hfcast::Surface::QuTriangles,
                "qu-triangles",
                "Qu's fixed-diagonal triangles",
            ),
            (
                hfcast::Surface::ViewLinear,
                "view-linear",
                "view-linear surface",
            ),
        ] {
            let mut s = first.clone();
            s.surface = surface;
            s.name = format!("{}-{suffix}", s.name);
            s.about = format!("{}, {what}", s.about);
            list.push(s);
        }
    }
    list.retain(|s| kept(opts, &s.name));
    Ok((list, skipped))
}

/// Runs the report and writes it; returns the Markdown summary section.
pub fn run(opts: &ReportOptions) -> Result<String, String> {
    let start = Instant::now();
    let (scenes, skipped) = build_scenes(opts)?;
    for why in &skipped {
        eprintln!("report: warning: skipping a map that could not be read: {why}");
    }
    if scenes.is_empty() {
        return Err("no scene left (check --scenes)".into());
    }
    let pixel_angle = scenes::pixel_angle(opts.size.1) as f32;
    let sweep = if opts.quick {
        Sweep::quick(pixel_angle)
    } else {
        Sweep::full(pixel_angle)
    };
    let all = settings(&sweep);
    let units: u64 = scenes
        .iter()
        .map(|s| {
            1 + all
                .iter()
                .filter(|m| m.surfaces.contains(&s.surface) && m.fits(s.width, s.height))
                .count() as u64
        })
        .sum();
    let bar = indicatif::ProgressBar::new(units);
    if std::io::stderr().is_terminal() {
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {pos}/{len} {msg}",
            )
            .map_err(|e| e.to_string())?
            .progress_chars("=> "),
        );
    } else {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let mut results = Vec::new();
    for scene in scenes {
        let line = format!(
            "report: {} ({} x {}, {}) at {:.0} s",
            scene.name,
            scene.width,
            scene.height,
            scene.surface.name(),
            start.elapsed().as_secs_f64()
        );
        if bar.is_hidden() {
            eprintln!("{line}");
        } else {
            bar.println(line);
        }
        bar.set_message(format!("{}: oracle", scene.name));
        let r = run_scene(opts, scene, &all, &bar);
        results.push(r);
    }
    bar.finish_and_clear();
    let elapsed = start.elapsed().as_secs_f64();
    markdown::write_all(opts, &sweep, &all, &results, &skipped, elapsed)
}

/// Measures every setting that applies on one scene.
fn run_scene(
    opts: &ReportOptions,
    mut scene: Scene,
    all: &[Setting],
    bar: &indicatif::ProgressBar,
) -> SceneResult {
    let hf = scene.field();
    let (w, h) = opts.size;
    let lift = SHADOW_LIFT * LIFT_UNIT * scene.z_scale();
    let sets: Vec<RaySet> = ray_sets(&hf, scene.surface, w, h, lift);
    let t0 = Instant::now();
    let oracles: Vec<_> = sets
        .iter()
        .map(|s| oracle(&hf, scene.surface, &s.rays, opts.threads))
        .collect();
    let oracle_s = t0.elapsed().as_secs_f64();
    bar.inc(1);
    let ambiguous = oracles
        .iter()
        .map(|o| o.iter().filter(|r| r.ambiguous).count() as u64)
        .collect();
    let oracle_hits = oracles
        .iter()
        .map(|o| o.iter().filter(|r| r.hit.is_some()).count() as u64)
        .collect();
    let mut measured = Vec::new();
    let mut skipped = Vec::new();
    for (k, s) in all.iter().enumerate() {
        if !s.surfaces.contains(&scene.surface) {
            continue;
        }
        if !s.fits(scene.width, scene.height) {
            skipped.push(k);
            continue;
        }
        bar.set_message(format!("{}: {}", scene.name, s.label));
        measured.push(measure(
            k,
            s,
            &hf,
            scene.surface,
            &sets,
            &oracles,
            opts.reps,
        ));
        bar.inc(1);
    }
    let set_info = sets
        .iter()
        .map(|s| (s.name.clone(), s.rays.len(), s.pixels))
        .collect();
    scene.heights = Vec::new();
    SceneResult {
        scene,
        sets: set_info,
        ambiguous,
        oracle_hits,
        oracle_s,
        measured,
        skipped,
    }
}
