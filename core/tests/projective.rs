//! Projective height fields (issue 22, item 1; `hfcast::projective`): degenerate maps
//! are refused; the identity map traces every ray as the plain march, bit for bit; on a
//! reverse-perspective frustum the world rays' grid lines are traced exactly (no wrong
//! ray against the `f64` oracle on the grid query, by the exact traversal and the
//! maximum mipmap alike), and their hits map back: the world point projects onto the
//! grid hit, the world `t` lies in the ray's range, and the world normal is orthogonal
//! to the surface's world tangents.
#![cfg(feature = "maxmip")]

mod common;

use common::{judge_trace, march_fields, Field, Rng};
use hfcast::maxmip::{self, MaxMip};
use hfcast::projective::{Mat4, Projective, ProjectiveError};
use hfcast::{dda, Marcher, Query, Surface};

const TRI: Surface = Surface::Triangles;

const IDENTITY: Mat4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// A reverse-perspective frustum: projection centre `f` under the point `c` of the
/// footprint, so the field's grid shrinks towards `c` with height (`w = (z + f) / f`,
/// grid x = c.x + (x − c.x)/w, grid z = z/w), composed with a shear and scale of the
/// world so that no entry is trivial.
fn reverse_perspective(f: f64, c: [f64; 2]) -> Mat4 {
    let p: Mat4 = [
        [1.0, 0.0, c[0] / f, 0.0],
        [0.0, 1.0, c[1] / f, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0 / f, 1.0],
    ];
    // World = a sheared, scaled copy: grid-side p applied to (1.5 x + 0.2 y, 0.8 y, 1.2 z).
    let a: Mat4 = [
        [1.5, 0.2, 0.0, 0.0],
        [0.0, 0.8, 0.0, 0.0],
        [0.0, 0.0, 1.2, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let mut m = [[0.0; 4]; 4];
    for r in 0..4 {
        for c in 0..4 {
            m[r][c] = (0..4).map(|k| p[r][k] * a[k][c]).sum();
        }
    }
    m
}

fn fields() -> Vec<(String, Field)> {
    march_fields(0x9e0, 3, ("checkerboard 24x20", 0.0, 1.0), Vec::new(), 3)
}

#[test]
fn degenerate_maps_are_refused() {
    let mut nan = IDENTITY;
    nan[1][2] = f64::NAN;
    let mut inf = IDENTITY;
    inf[3][0] = f64::INFINITY;
    let mut flat = IDENTITY;
    flat[2] = [0.0; 4];
    let mut rank3 = IDENTITY;
    rank3[3] = [1.0, 1.0, 0.0, 0.0];
    rank3[0] = [2.0, 2.0, 0.0, 0.0];
    assert_eq!(Projective::new(nan), Err(ProjectiveError::NotFinite));
    assert_eq!(Projective::new(inf), Err(ProjectiveError::NotFinite));
    assert_eq!(Projective::new(flat), Err(ProjectiveError::Singular));
    assert_eq!(Projective::new(rank3), Err(ProjectiveError::Singular));
    assert_eq!(
        Projective::new([[0.0; 4]; 4]),
        Err(ProjectiveError::Singular)
    );
    assert!(Projective::new(reverse_perspective(40.0, [10.0, 8.0])).is_ok());
    assert!(Projective::from_unit_cube(IDENTITY, 64, 32, 10.0).is_ok());
    assert_eq!(
        Projective::from_unit_cube(IDENTITY, 64, 32, 0.0),
        Err(ProjectiveError::Singular)
    );
}

#[test]
fn the_identity_is_the_plain_march() {
    let id = Projective::new(IDENTITY).unwrap();
    let mut rng = Rng::new(5);
    let mut traced = 0;
    for (name, field) in fields() {
        let hf = field.hf();
        let (xm, ym) = field.far_corner();
        let (zlo, zhi) = field.range();
        for _ in 0..400 {
            let o = [
                rng.range(-2.0, xm + 2.0),
                rng.range(-2.0, ym + 2.0),
                rng.range(zlo, zhi + 3.0),
            ];
            let d = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 0.3),
            ];
            let Ok(q) = Query::<f32>::from_arrays(
                o.map(|v| v as f32),
                d.map(|v| v as f32),
                0.0,
                f32::INFINITY,
            ) else {
                continue;
            };
            let plain = dda::trace(&hf, TRI, &q);
            let got = id.trace(&hf, &q, |g| dda::trace(&hf, TRI, g)).unwrap();
            // The identity's grid query is the ray clipped to the box: the same hit (the
            // normal renormalised in f64).
            let key = |t: &hfcast::Trace<f32>| t.hit.map(|h| (h.t, h.point, h.cell, h.flags));
            assert_eq!(key(&got), key(&plain), "{name}: {q:?}");
            if let (Some(a), Some(b)) = (got.hit, plain.hit) {
                assert!((a.normal - b.normal).length() < 1e-6, "{name}: {q:?}");
            }
            traced += 1;
        }
    }
    assert!(traced > 1000);
}

#[test]
fn perspective_rays_are_exact_and_map_back() {
    let mut rng = Rng::new(0x22);
    let (mut rays, mut hits, mut wrong, mut ambiguous, mut behind) = (0u32, 0u32, 0u32, 0u32, 0u32);
    let (mut max_back, mut max_normal) = (0f64, 0f64);
    for (name, field) in fields() {
        let hf = field.hf();
        let (xm, ym) = field.far_corner();
        let (zlo, zhi) = field.range();
        let f = 3.0 * (xm + ym);
        let proj = Projective::new(reverse_perspective(f, [0.5 * xm, 0.4 * ym])).unwrap();
        let mut pyramid = vec![0.0; maxmip::pyramid_len(hf.width(), hf.height())];
        maxmip::bake(&hf, &mut pyramid).unwrap();
        let mip = MaxMip::new(&hf, &pyramid).unwrap();
        let marchers = [
            Marcher::Exact(TRI),
            Marcher::MaxMip(mip, TRI, maxmip::Options::default()),
        ];
        for k in 0..500 {
            // Aimed at a grid point over the footprint (near the surface for some),
            // from a world point back along a random direction.
            let (gx, gy) = (rng.range(0.0, xm), rng.range(0.0, ym));
            let gz = TRI.height_at(&hf, gx, gy)
                + if k % 3 == 0 {
                    rng.range(0.0, 0.05)
                } else {
                    0.0
                };
            let target = proj.to_world([gx, gy, gz]);
            let az = rng.range(0.0, std::f64::consts::TAU);
            // Every fifth from below, from behind the centre of projection (w < 0 at
            // the start: the range starts at w = 0, the line at infinity).
            let from_below = k % 5 == 4;
            let el = if from_below {
                -rng.range(0.6, 1.4)
            } else {
                rng.range(0.02, 1.4)
            };
            let d = [-az.cos() * el.cos(), -az.sin() * el.cos(), -el.sin()];
            let back = match from_below {
                true => 4.0 * f,
                false => rng.range(1.0, 2.0) * (xm + ym + zhi - zlo),
            };
            let o = [0, 1, 2].map(|c| target[c] - back * d[c]);
            let Ok(q) = Query::<f32>::from_arrays(
                o.map(|v| v as f32),
                d.map(|v| v as f32),
                0.0,
                f32::INFINITY,
            ) else {
                continue;
            };
            let Some(mapped) = proj.map(&hf, &q).unwrap() else {
                continue;
            };
            rays += 1;
            behind += u32::from(proj.to_grid_h(o)[3] <= 0.0);
            for m in &marchers {
                let got = proj.trace(&hf, &q, |g| m.trace(&hf, g)).unwrap();
                let grid = m.trace(&hf, &mapped.grid);
                assert_eq!(
                    got.hit.map(|h| (h.cell, h.flags)),
                    grid.hit.map(|h| (h.cell, h.flags))
                );
                match judge_trace(&field, TRI, &grid, &mapped.grid, field.z_scale()) {
                    None => ambiguous += 1,
                    Some(true) => {}
                    Some(false) => {
                        wrong += 1;
                        println!("{name}: {q:?} -> {:?}: {:?}", mapped.grid, grid.hit);
                    }
                }
                let (Some(h), Some(gh)) = (got.hit, grid.hit) else {
                    continue;
                };
                hits += 1;
                assert!(
                    h.t >= q.t_min() && h.t <= q.t_max(),
                    "{name}: t {} out of range",
                    h.t
                );
                // The world point projects onto the grid hit.
                let wp = h.point.to_array().map(f64::from);
                let g = proj.to_grid_h(wp);
                let gp = gh.point.to_array().map(f64::from);
                let scale = 1.0 + gp.iter().fold(0f64, |s, v| s.max(v.abs()));
                let off = (0..3)
                    .map(|c| (g[c] / g[3] - gp[c]).abs())
                    .fold(0f64, f64::max);
                max_back = max_back.max(off / scale);
                // The world normal is orthogonal to the world images of grid tangents.
                let n = gh.normal.to_array().map(f64::from);
                let helper = if n[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                let t1 = cross(n, helper);
                let t2 = cross(n, t1);
                let wn = h.normal.to_array().map(f64::from);
                let base = proj.to_world(gp);
                for t in [t1, t2] {
                    let e = 1e-3;
                    let q2 = proj.to_world([gp[0] + e * t[0], gp[1] + e * t[1], gp[2] + e * t[2]]);
                    let v = [0, 1, 2].map(|c| q2[c] - base[c]);
                    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    let dot = (v[0] * wn[0] + v[1] * wn[1] + v[2] * wn[2]) / len;
                    max_normal = max_normal.max(dot.abs());
                }
                // On the side of the world ray that the grid normal is of the grid ray.
                let (dir, e) = (q.dir().map(f64::from), mapped.grid.dir().map(f64::from));
                let world_side = wn[0] * dir[0] + wn[1] * dir[1] + wn[2] * dir[2];
                let grid_side = n[0] * e[0] + n[1] * e[1] + n[2] * e[2];
                assert!(
                    world_side * grid_side >= 0.0 || world_side.abs() < 1e-6,
                    "{name}: the world normal is on the other side ({world_side} vs {grid_side}, {:?})",
                    gh.flags
                );
            }
        }
    }
    println!(
        "{rays} world rays ({behind} from behind the centre), {hits} hits (two marches), \
         {wrong} wrong, {ambiguous} ambiguous; \
         world point off its grid hit by at most {max_back:.1e} (relative), \
         |normal · tangent| at most {max_normal:.1e}"
    );
    assert!(
        rays > 1000 && hits > 1000,
        "too few rays: {rays}, hits {hits}"
    );
    assert!(
        behind > 200,
        "too few rays from behind the centre: {behind}"
    );
    assert_eq!(wrong, 0, "wrong rays");
    assert!(
        max_back < 1e-5,
        "world points off their grid hits: {max_back:e}"
    );
    assert!(
        max_normal < 1e-5,
        "world normals not orthogonal: {max_normal:e}"
    );
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
