//! The exact traversal on the real maps of `../shared/data`: the f32 fast path against
//! the f64 oracle on every map, and every single-texel spike of the spike map.

use hfcast::{dda, HeightField, Query, Surface, Trace};
use hfcast_tools::bench::random_rays;
use hfcast_tools::maps::{list_maps, load_map, shared_data_dir};
use hfcast_tools::render::{compass_dir, Camera};

/// Hit points agree when closer than `1e-4 + 8 ε32 · (|origin|∞ + |point|∞)` texels.
///
/// A plain 1e-4 cannot be met in f32: at x ≥ 2048 neighbouring f32 values are 2.4e-4
/// apart, and `origin + t · dir` from a camera thousands of texels away carries a few
/// ulps of that scale (measured: at most ≈ 5 ε32 · scale). The count of hits beyond a
/// plain 1e-4 is printed too.
fn tolerance(origin: [f32; 3], point: [f64; 3]) -> f64 {
    let scale = |v: [f64; 3]| v.iter().fold(0f64, |m, x| m.max(x.abs()));
    1e-4 + 8.0 * f64::from(f32::EPSILON) * (scale(origin.map(f64::from)) + scale(point))
}

/// The oracle flags a ray ambiguous when it passes closer than 2⁻¹³ · max(1, |z|) above
/// the surface before its hit (or anywhere, for a miss), or, for a hit where the traced
/// span begins, starts less than that under it; z is the oracle's hit height, or for a
/// miss the highest |height|.
fn ambiguous(hf: &HeightField, oracle: &Trace<f64>) -> bool {
    let z = match oracle.hit {
        Some(h) => h.point.z.abs(),
        None => f64::from(hf.max_height().abs().max(hf.min_height().abs())),
    };
    oracle.clearance.abs() < (2f64).powi(-13) * z.max(1.0)
}

#[derive(Default)]
struct Tally {
    tried: usize,
    wrong: usize,
    ambiguous: usize,
    over_1e4: usize,
    max_error: f64,
    first_wrong: Option<String>,
}

fn compare(hf: &HeightField, q: &Query<f32>, t: &mut Tally) {
    let fast = dda::trace(hf, Surface::Triangles, q);
    let oracle = dda::trace(hf, Surface::Triangles, &q.cast::<f64>());
    t.tried += 1;
    if ambiguous(hf, &oracle) {
        t.ambiguous += 1;
        return;
    }
    let (error, tol) = match (fast.hit, oracle.hit) {
        (None, None) => (0.0, 0.0),
        (Some(f), Some(o)) => (
            f.point.as_dvec3().distance(o.point),
            tolerance(q.origin(), o.point.to_array()),
        ),
        _ => (f64::INFINITY, 0.0),
    };
    t.max_error = t.max_error.max(error);
    t.over_1e4 += usize::from(error > 1e-4);
    if error > tol {
        t.wrong += 1;
        t.first_wrong.get_or_insert_with(|| {
            format!(
                "{q:?}: f32 {:?} f64 {:?} clearance {}",
                fast.hit, oracle.hit, oracle.clearance
            )
        });
    }
}

#[test]
fn f32_agrees_with_f64_oracle_on_every_map() {
    let maps = list_maps();
    assert!(
        !maps.is_empty(),
        "no maps in {} (set HFCAST_DATA)",
        shared_data_dir().display()
    );
    let mut failures = Vec::new();
    for info in &maps {
        let map = load_map(&info.path, None).unwrap();
        let hf = map.field();
        let mut rays = Vec::new();
        for elevation in [45.0, 5.0] {
            rays.extend(Camera::orbit(&hf, elevation, 200.0, 64, 48).rays());
        }
        rays.extend(random_rays(&hf, 2000, 7));
        let mut t = Tally::default();
        for q in &rays {
            compare(&hf, q, &mut t);
        }
        println!(
            "{:<32} depth {:>5.1}: tried {}, wrong {}, ambiguous {}; \
             max hit error {:.1e} texel, {} beyond 1e-4",
            info.name, map.depth, t.tried, t.wrong, t.ambiguous, t.max_error, t.over_1e4
        );
        if let Some(w) = t.first_wrong {
            failures.push(format!("{}: {} wrong, e.g. {w}", info.name, t.wrong));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn every_spike_of_the_spike_map_is_hit() {
    let path = shared_data_dir().join("game_etr_i_like_spike_2_128x640.png");
    let map = load_map(&path, Some(0.2 * 640.0)).unwrap();
    let hf = map.field();
    let margin = 0.05 * map.depth;
    let mut spikes = Vec::new();
    for j in 1..hf.height() - 1 {
        for i in 1..hf.width() - 1 {
            let neighbours = (0..9)
                .filter(|&k| k != 4)
                .map(|k| hf.at(i + k % 3 - 1, j + k / 3 - 1))
                .fold(f32::NEG_INFINITY, f32::max);
            if hf.at(i, j) - neighbours >= margin {
                spikes.push([i, j]);
            }
        }
    }
    assert!(spikes.len() > 500, "only {} spikes found", spikes.len());

    // From 8 azimuths at 30° elevation, aim at a point 0.01 under (and over) the tip,
    // from 1 texel away horizontally (above everything in the spike's 3 × 3 samples)
    // and from far outside the field.
    let (below, above, far) = (0.01, 0.01, 2.0 * 640.0);
    let (mut rays, mut near_hits, mut far_at_spike) = (0, 0, 0);
    for &[i, j] in &spikes {
        let tip = [f64::from(i), f64::from(j), f64::from(hf.at(i, j))];
        for k in 0..8 {
            let to_eye = compass_dir(45.0 * f64::from(k), 30.0);
            let dir = to_eye.map(|v| -v);
            for (dist, dz) in [(1.0, -below), (far, -below), (1.0, above)] {
                let s = dist / 30f64.to_radians().cos();
                let target = [tip[0], tip[1], tip[2] + dz];
                let origin = [0, 1, 2].map(|c| target[c] - s * dir[c]);
                let q64 = Query::<f64>::from_arrays(origin, dir, 0.0, f64::INFINITY).unwrap();
                let q32 = Query::<f32>::from_arrays(
                    origin.map(|v| v as f32),
                    dir.map(|v| v as f32),
                    0.0,
                    f32::INFINITY,
                )
                .unwrap();
                // (t, cell) of the f32 fast path and of the f64 oracle.
                let hits = [
                    dda::trace(&hf, Surface::Triangles, &q32)
                        .hit
                        .map(|h| (f64::from(h.t), h.cell)),
                    dda::trace(&hf, Surface::Triangles, &q64)
                        .hit
                        .map(|h| (h.t, h.cell)),
                ];
                for hit in hits {
                    rays += 1;
                    let what = format!("spike ({i}, {j}) azimuth {} dist {dist} dz {dz}", 45 * k);
                    let at_spike = |cell: [u32; 2]| {
                        (i - 1..=i).contains(&cell[0]) && (j - 1..=j).contains(&cell[1])
                    };
                    if dz > 0.0 {
                        // Passing over the tip: nothing is hit before it.
                        assert!(hit.is_none_or(|h| h.0 > s), "{what}: {hit:?}");
                        continue;
                    }
                    let (t, cell) = hit.unwrap_or_else(|| panic!("{what}: missed"));
                    assert!(t <= s * (1.0 + 1e-6), "{what}: passed through: {hit:?}");
                    if dist == 1.0 {
                        assert!(at_spike(cell), "{what}: hit elsewhere: {hit:?}");
                        near_hits += 1;
                    } else if at_spike(cell) {
                        far_at_spike += 1;
                    }
                }
            }
        }
    }
    println!(
        "{} spikes (higher than all 8 neighbours by >= {margin}), {rays} rays (f32 and f64): \
         {near_hits} near rays hit the spike; far rays: {far_at_spike} of {} hit at the \
         spike, the others something in front of it",
        spikes.len(),
        spikes.len() * 8 * 2
    );
}
