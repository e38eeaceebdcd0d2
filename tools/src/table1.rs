//! `hfcast table1`: Table 1 of Baboud, Eisemann and Seidel (2011) reproduced side by
//! side: safety distances (`cyl`) and cylinder–cone shapes (`cyl+cone`) baked for
//! every ray and for exterior rays, each without and with a largest view angle of
//! 45° from the vertical (the paper's φmax = −45°), on centre crops of one map. Per
//! setting: bake seconds on the given threads, map bytes, and on each orbit camera the
//! share of its rays in the map's ray set (the others walk cell by cell), the texel
//! fetches per ray, single-thread CPU ns per ray, and the rays whose answer differs
//! from the exact traversal's (hit or miss, or hit points over 10⁻³ texel apart),
//! which must be none.

use crate::bench::{bench_rays, BenchResult, Order};
use crate::render::Camera;
use crate::trace::Tracer;
use crate::MethodSpec;
use hfcast::rayset::Rays;
use hfcast::scene::{MethodKind, RayClasses};
use hfcast::{HeightField, Query, Surface, Trace};
use std::cmp::Ordering;
use std::fmt::Write as _;

/// What `hfcast table1` measures.
#[derive(Clone, Debug)]
pub struct Table1Options {
    /// Sides of the centre crops (each at most the map's).
    pub sides: Vec<u32>,
    /// Threads of the bakes.
    pub threads: usize,
    /// The camera's image size, pixels.
    pub size: (u32, u32),
    /// The cameras' elevations, degrees.
    pub elevations: Vec<f64>,
    /// Timing repetitions (median).
    pub reps: usize,
}

/// The largest view angle of the paper's φmax = −45° rows, degrees from the downward
/// vertical.
pub const PHI_DEG: f32 = 45.0;

/// The paper's rows: its name, the method, exterior rays only.
const ROWS: [(&str, MethodKind, bool); 4] = [
    ("cyl_all", MethodKind::Safety, false),
    ("cyl_ext", MethodKind::Safety, true),
    ("cyl_all+cone_all", MethodKind::Cc, false),
    ("cyl_ext+cone_ext", MethodKind::Cc, true),
];

/// The rays whose answers differ in `a` and `b`: hit or miss, or hit points more than
/// 10⁻³ texel apart.
fn differ(a: &[Trace<f32>], b: &[Trace<f32>]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(x, y)| match (&x.hit, &y.hit) {
            // Over 10⁻³ apart, or a NaN distance.
            (Some(p), Some(q)) => !matches!(
                p.point.distance(q.point).partial_cmp(&1e-3),
                Some(Ordering::Less | Ordering::Equal)
            ),
            (None, None) => false,
            _ => true,
        })
        .count()
}

/// The centre `side × side` samples (at most the field's) of the row-major `heights`
/// of a `w × h` field, as a view of them.
fn centre_crop(heights: &[f32], w: u32, h: u32, side: u32) -> HeightField<'_> {
    let (cw, ch) = (side.min(w), side.min(h));
    let at = ((h - ch) / 2 * w + (w - cw) / 2) as usize;
    HeightField::new(&heights[at..], cw, ch, w as usize).expect("a crop of a valid field")
}

/// One camera of the table: its elevation, rays, the exact traversal's answers and
/// cost.
struct View {
    elevation: f64,
    rays: Vec<Query<f32>>,
    want: Vec<Trace<f32>>,
}

/// Runs the table on the row-major `heights` of a `w × h` map named `name`; returns
/// it as Markdown.
pub fn run(name: &str, heights: &[f32], w: u32, h: u32, opts: &Table1Options) -> String {
    let mut md = String::new();
    let (iw, ih) = opts.size;
    let _ = writeln!(
        md,
        "Map `{name}`, centre crops; {iw} × {ih} orbit cameras (vertical field of view \
         {}°) at the elevations of the `camera` column. Bakes on {} threads; ns per ray \
         on one thread, median of {}. `in set`: the camera's rays in the map's ray set \
         (the others walk cell by cell); `differ`: rays whose answer is not the exact \
         traversal's.\n",
        crate::render::FOV_Y_DEG,
        opts.threads,
        opts.reps
    );
    let _ = writeln!(
        md,
        "| side | setting | φmax | bake s | bytes | camera | in set | fetches / ray | ns / ray | differ |\n\
         |---:|---|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    for &side in &opts.sides {
        let hf = centre_crop(heights, w, h, side);
        let side_s = format!("{} × {}", hf.width(), hf.height());
        let exact = Tracer::bake(
            hf,
            MethodSpec::of(MethodKind::Exact),
            Surface::Triangles,
            RayClasses::ALL,
        )
        .expect("the exact traversal needs no bake");
        let views: Vec<View> = opts
            .elevations
            .iter()
            .map(|&elevation| {
                let rays = Camera::orbit(&hf, elevation, 200.0, iw, ih).rays();
                let mut want = vec![Trace::MISS; rays.len()];
                exact.trace_all(&rays, &mut want);
                View {
                    elevation,
                    rays,
                    want,
                }
            })
            .collect();
        let bench =
            |t: &Tracer, v: &View| bench_rays(t, "", &v.rays, &[1], opts.reps, Order::Lanes);
        let ns = |b: &BenchResult| 1e9 / b.rays_per_s[0].1;
        for v in &views {
            let b = bench(&exact, v);
            let _ = writeln!(
                md,
                "| {side_s} | exact traversal (DDA) | – | – | 0 | {}° | – | {:.1} | {:.0} | 0 |",
                v.elevation,
                b.fetch_mean,
                ns(&b)
            );
        }
        for (label, kind, exterior) in ROWS {
            for phi in [None, Some(PHI_DEG)] {
                let rays_set = Rays {
                    exterior,
                    max_view_angle_deg: phi.unwrap_or(180.0),
                    occluders: 0,
                };
                let phi_s = phi.map_or("–".into(), |p| format!("−{p}°"));
                eprintln!("table1: {side_s} {label} {rays_set}");
                let tracer = match Tracer::bake_for(
                    hf,
                    MethodSpec::of(kind),
                    Surface::Triangles,
                    RayClasses::ALL,
                    rays_set,
                    opts.threads,
                ) {
                    Ok(t) => t,
                    Err(e) => {
                        let _ = writeln!(md, "| {side_s} | {label} | {phi_s} | {e} | | | | | | |");
                        continue;
                    }
                };
                for v in &views {
                    let mut got = vec![Trace::MISS; v.rays.len()];
                    tracer.trace_all(&v.rays, &mut got);
                    let b = bench(&tracer, v);
                    let held = v
                        .rays
                        .iter()
                        .filter(|q| rays_set.holds(&hf, &[], q))
                        .count();
                    let _ = writeln!(
                        md,
                        "| {side_s} | {label} | {phi_s} | {:.2} | {} | {}° | {:.0} % | {:.1} | {:.0} | {} |",
                        tracer.bake_time().as_secs_f64(),
                        tracer.bytes(),
                        v.elevation,
                        100.0 * held as f64 / v.rays.len().max(1) as f64,
                        b.fetch_mean,
                        ns(&b),
                        differ(&v.want, &got)
                    );
                }
            }
        }
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_crop_takes_the_middle_samples() {
        let heights: Vec<f32> = (0..20).map(|k| k as f32).collect();
        let crop = centre_crop(&heights, 5, 4, 2);
        assert_eq!((crop.width(), crop.height()), (2, 2));
        assert_eq!(crop.cell_corners(0, 0), [6.0, 7.0, 11.0, 12.0]);
    }

    #[test]
    fn a_small_table_has_every_row_and_no_differing_ray() {
        let side = 24u32;
        let heights: Vec<f32> = (0..side * side)
            .map(|k| ((k % side) as f32 * 0.7).sin() * 3.0 + ((k / side) as f32 * 0.4).cos() * 2.0)
            .collect();
        let opts = Table1Options {
            sides: vec![16],
            threads: 2,
            size: (16, 12),
            elevations: vec![45.0, 70.0],
            reps: 1,
        };
        let md = run("test", &heights, side, side, &opts);
        let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| 16 × 16")).collect();
        assert_eq!(rows.len(), 2 * (1 + 2 * ROWS.len()), "{md}");
        for row in &rows {
            assert!(row.trim_end().ends_with("| 0 |"), "a ray differs: {row}");
        }
    }
}
