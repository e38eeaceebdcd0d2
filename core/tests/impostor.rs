//! Six-field impostors (issue 22, items 2–3; `hfcast::impostor`): bad meshes and
//! layouts are refused; the capture's heights are the mesh's first hits along the
//! projector lines (against Möller–Trumbore in `f64`, an independent ray cast); the
//! trace is the first point of the intersection of the six solids (checked by dense
//! sampling of each solid's membership), in `f32` as in `f64`; and against the mesh
//! itself the reverse-perspective fields outline and place the object better than the
//! orthographic ones at the same side.

use hfcast::camera::Pinhole;
use hfcast::impostor::{
    pad_silhouettes, procedural_tower, rasterize, Combine, Frustum, Impostor, ImpostorError,
    Layout, Mesh, EMPTY, FACES, FLOOR, NO_TRIANGLE,
};
use hfcast::rng::SplitMix as Rng;
use hfcast::{dda, HeightField, Query, Surface};

const TRI: Surface = Surface::Triangles;

/// The six captured fields of `mesh` at `side` on `layout`.
fn capture(mesh: &Mesh, layout: &Layout, side: u32) -> Vec<Vec<f32>> {
    capture_padded(mesh, layout, side, true)
}

/// [`capture`], with or without [`pad_silhouettes`].
fn capture_padded(mesh: &Mesh, layout: &Layout, side: u32, pad: bool) -> Vec<Vec<f32>> {
    (0..6)
        .map(|face| {
            let map = layout.face_map(face, side).unwrap();
            let mut h = vec![0.0; (side * side) as usize];
            rasterize(mesh, &map, side, &mut h, None).unwrap();
            if pad {
                pad_silhouettes(&mut h, side).unwrap();
            }
            h
        })
        .collect()
}

fn impostor<'a>(layout: Layout, heights: &'a [Vec<f32>], side: u32) -> Impostor<'a> {
    let fields =
        core::array::from_fn(|k| HeightField::new(&heights[k], side, side, side as usize).unwrap());
    Impostor::new(layout, fields).unwrap()
}

/// Rays from a sphere three half sides around the cube aimed at points inside it.
fn rays(layout: &Layout, n: usize, seed: u64) -> Vec<([f64; 3], [f64; 3])> {
    let mut rng = Rng::new(seed);
    let (c, s) = (layout.center(), layout.half());
    (0..n)
        .map(|_| {
            let dir = loop {
                let v = [0; 3].map(|_| rng.range(-1.0, 1.0));
                let l = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                if l > 0.1 && l <= 1.0 {
                    break v.map(|x| x / l);
                }
            };
            let o = [0, 1, 2].map(|k| c[k] + 3.0 * s * dir[k]);
            let target = [0, 1, 2].map(|k| c[k] + 0.8 * s * rng.range(-1.0, 1.0));
            (o, [0, 1, 2].map(|k| target[k] - o[k]))
        })
        .collect()
}

fn tower() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    procedural_tower(48)
}

#[test]
fn bad_meshes_and_layouts_are_refused() {
    let p = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(Mesh::new(&p, &[]).unwrap_err(), ImpostorError::NoTriangles);
    let nan = [[0.0f32, f32::NAN, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(
        Mesh::new(&nan, &[[0, 1, 2]]).unwrap_err(),
        ImpostorError::NotFinite
    );
    assert_eq!(
        Mesh::new(&p, &[[0, 1, 3]]).unwrap_err(),
        ImpostorError::IndexOutOfRange
    );
    let point = [[2.0f32, 2.0, 2.0]; 3];
    let m = Mesh::new(&point, &[[0, 1, 2]]).unwrap();
    assert_eq!(
        Layout::around(&m, Frustum::Orthographic).unwrap_err(),
        ImpostorError::NoExtent
    );
    // A flat triangle still has a cube (its largest extent).
    let flat = Mesh::new(&p, &[[0, 1, 2]]).unwrap();
    let l = Layout::around(&flat, Frustum::DEFAULT_REVERSE).unwrap();
    for apex in [1.0, 0.5, f64::NAN, f64::INFINITY] {
        let f = Frustum::ReversePerspective { apex };
        assert_eq!(
            Layout::new([0.0; 3], 1.0, f).unwrap_err(),
            ImpostorError::BadApex
        );
    }
    assert_eq!(
        Layout::new([f64::NAN, 0.0, 0.0], 1.0, Frustum::Orthographic).unwrap_err(),
        ImpostorError::NotFinite
    );
    assert_eq!(l.face_map(0, 1).unwrap_err(), ImpostorError::BadSide);
    // A layout from its parts: the same layout back; a bad unit map refused.
    let units = core::array::from_fn(|k| l.face_unit(k));
    let back = Layout::from_parts(l.center(), l.half(), l.frustum(), units).unwrap();
    assert_eq!(back, l);
    let mut singular = units;
    singular[3][2] = [0.0; 4];
    assert!(matches!(
        Layout::from_parts(l.center(), l.half(), l.frustum(), singular),
        Err(ImpostorError::Map(_))
    ));
    let map = l.face_map(0, 8).unwrap();
    let mut short = vec![0.0; 63];
    assert_eq!(
        rasterize(&flat, &map, 8, &mut short, None).unwrap_err(),
        ImpostorError::BufferTooSmall
    );
    let (mut h, mut t) = (vec![0.0; 64], vec![0u32; 10]);
    assert_eq!(
        rasterize(&flat, &map, 8, &mut h, Some(&mut t)).unwrap_err(),
        ImpostorError::BufferTooSmall
    );
    // Fields of two sides.
    let (a, b) = (vec![0.0f32; 64], vec![0.0f32; 81]);
    let fa = HeightField::new(&a, 8, 8, 8).unwrap();
    let fb = HeightField::new(&b, 9, 9, 9).unwrap();
    let fields = [fa, fa, fa, fb, fa, fa];
    assert_eq!(
        Impostor::new(l, fields).unwrap_err(),
        ImpostorError::FieldsDiffer
    );
}

/// Every face's footprint covers the cube at every depth, and the grid height runs
/// from 0 at the opposite face to `side − 1` at the face.
#[test]
fn every_face_spans_the_cube() {
    let side = 33;
    for frustum in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
        let l = Layout::new([1.0, -2.0, 0.5], 3.0, frustum).unwrap();
        for (face, [n, ..]) in FACES.iter().enumerate() {
            let m = l.face_map(face, side).unwrap();
            let g = |p: [f64; 3]| {
                let h = m.to_grid_h(p);
                [h[0] / h[3], h[1] / h[3], h[2] / h[3]]
            };
            let at = |k: f64| [0, 1, 2].map(|a| l.center()[a] + k * l.half() * n[a]);
            assert!((g(at(1.0))[2] - 32.0).abs() < 1e-9, "face {face}");
            assert!(g(at(-1.0))[2].abs() < 1e-9, "face {face}");
            for corner in 0..8 {
                let p = [0, 1, 2].map(|a| {
                    let s = if corner >> a & 1 == 1 { 1.0 } else { -1.0 };
                    l.center()[a] + s * l.half()
                });
                let q = g(p);
                for v in q {
                    assert!(
                        (-1e-9..=32.0 + 1e-9).contains(&v),
                        "{frustum:?} face {face}: {q:?}"
                    );
                }
            }
        }
    }
}

/// The captured height of a sample is where its projector line first meets the mesh
/// from the face, by Möller–Trumbore in `f64`; the triangle is the one met.
#[test]
fn capture_is_the_first_hit_along_each_projector_line() {
    let (pos, tri) = tower();
    let mesh = Mesh::new(&pos, &tri).unwrap();
    let side = 48;
    let (mut checked, mut hits) = (0, 0);
    for frustum in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
        let layout = Layout::around(&mesh, frustum).unwrap();
        for face in 0..6 {
            let map = layout.face_map(face, side).unwrap();
            let mut h = vec![0.0; (side * side) as usize];
            let mut t = vec![0; (side * side) as usize];
            rasterize(&mesh, &map, side, &mut h, Some(&mut t)).unwrap();
            for j in 0..side {
                for i in 0..side {
                    let at = (j * side + i) as usize;
                    // The projector line from the face (z = side − 1) down.
                    let top = map.to_world([f64::from(i), f64::from(j), f64::from(side - 1)]);
                    let bottom = map.to_world([f64::from(i), f64::from(j), 0.0]);
                    let d = [0, 1, 2].map(|k| bottom[k] - top[k]);
                    let hit = mesh.first_hit(top, d, 0.0, 1.0);
                    checked += 1;
                    match hit {
                        None => {
                            assert_eq!(h[at], EMPTY, "{frustum:?} face {face} ({i}, {j})");
                            assert_eq!(t[at], NO_TRIANGLE);
                        }
                        Some((s, _)) => {
                            hits += 1;
                            let p = [0, 1, 2].map(|k| top[k] + s * d[k]);
                            let g = map.to_grid_h(p);
                            let z = g[2] / g[3];
                            // Within rounding (edges shared by two triangles may go
                            // either way; both give the same height).
                            assert!(
                                (f64::from(h[at]) - z).abs() < 1e-3,
                                "{frustum:?} face {face} ({i}, {j}): {} vs {z}",
                                h[at]
                            );
                        }
                    }
                }
            }
        }
    }
    println!("{checked} projector lines, {hits} meet the tower: heights agree");
    assert!(hits > checked / 4 && hits < checked);
}

/// Is the world point `p` in face `k`'s solid (under its surface, over its footprint,
/// above [`FLOOR`]),
/// with `slack` grid units of tolerance (positive: lenient)?
fn in_solid(imp: &Impostor, k: usize, p: [f64; 3], slack: f64) -> bool {
    let g = imp.map(k).to_grid_h(p);
    let (x, y, z) = (g[0] / g[3], g[1] / g[3], g[2] / g[3]);
    let hf = imp.field(k);
    let last = f64::from(hf.width() - 1);
    if !(-slack..=last + slack).contains(&x) || !(-slack..=last + slack).contains(&y) {
        return false;
    }
    z >= f64::from(FLOOR) - slack
        && z <= TRI.height_at(hf, x.clamp(0.0, last), y.clamp(0.0, last)) + slack
}

/// The trace's hit is in all six solids, and every sampled point before it is outside
/// one of them (a miss: every sampled point in the cube is); `f32` agrees with `f64`.
#[test]
fn trace_is_the_first_point_in_every_solid() {
    let (pos, tri) = tower();
    let mesh = Mesh::new(&pos, &tri).unwrap();
    let side = 40;
    for frustum in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
        let layout = Layout::around(&mesh, frustum).unwrap();
        let heights = capture(&mesh, &layout, side);
        let imp = impostor(layout, &heights, side);
        let (mut n_hits, mut agree, mut traces, mut total) = (0, 0, 0u64, 0);
        for (o, d) in rays(&layout, 1500, 0x1a9) {
            total += 1;
            let q = Query::<f64>::from_arrays(o, d, 0.0, f64::INFINITY).unwrap();
            let r = imp
                .trace(Combine::Intersection, &q, |hf, g| dda::trace(hf, TRI, g))
                .unwrap();
            traces += u64::from(r.traces);
            let (t_in, t_out) = layout.clip(&q).unwrap_or((0.0, -1.0));
            let end = r.trace.hit.map_or(t_out, |h| h.t);
            let at = |t: f64| [0, 1, 2].map(|k| o[k] + t * d[k]);
            if let Some(h) = r.trace.hit {
                n_hits += 1;
                for k in 0..6 {
                    assert!(in_solid(&imp, k, at(h.t), 1e-6), "face {k} misses the hit");
                }
            }
            // Dense samples before the answer, away from it by 1e-4 of the span.
            let span = end - t_in;
            for s in 0..400 {
                let t = t_in + span * (f64::from(s) + 0.5) / 400.0;
                if t < end - 1e-4 * span.max(1e-9) {
                    let inside = (0..6).all(|k| in_solid(&imp, k, at(t), -1e-6));
                    assert!(
                        !inside,
                        "{frustum:?}: a point at {t} before {end} is inside"
                    );
                }
            }
            let q32 = Query::<f32>::from_arrays(
                o.map(|v| v as f32),
                d.map(|v| v as f32),
                0.0,
                f32::INFINITY,
            )
            .unwrap();
            let r32 = imp
                .trace(Combine::Intersection, &q32, |hf, g| dda::trace(hf, TRI, g))
                .unwrap();
            let same = match (r.trace.hit, r32.trace.hit) {
                (None, None) => true,
                (Some(a), Some(b)) => (a.t - f64::from(b.t)).abs() < 1e-3 * a.t,
                _ => false,
            };
            agree += usize::from(same);
        }
        println!(
            "{frustum:?}: {n_hits}/{total} hit, {:.2} field traces per ray, f32 agrees on {agree}",
            traces as f64 / total as f64
        );
        assert!(n_hits > total / 3);
        assert!(agree * 1000 >= total * 995, "{agree}/{total}");
    }
}

/// The Stanford bunny of `data/` (an OBJ of `v` and `f` lines: read here without a
/// parser crate; the tools read it with one).
fn bunny() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/mesh_stanford_bunny.obj"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let (mut pos, mut tri) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => pos.push([0; 3].map(|_| w.next().unwrap().parse::<f32>().unwrap())),
            Some("f") => tri.push([0; 3].map(|_| w.next().unwrap().parse::<u32>().unwrap() - 1)),
            _ => {}
        }
    }
    (pos, tri)
}

/// Rays of six pinhole cameras (`px × px` each) three half sides from the centre,
/// looking at it from around the object, the cube filling the frame (the views of
/// `hfcast_tools::impostor::six_views`).
fn camera_rays(layout: &Layout, px: u32) -> Vec<([f64; 3], [f64; 3])> {
    let backs: [[f64; 3]; 6] = [
        [1.0, 0.3, 0.2],
        [-0.4, 1.0, 0.5],
        [-1.0, -0.6, 0.1],
        [0.2, -1.0, -0.7],
        [0.3, 0.4, 1.0],
        [-0.2, 0.1, -1.0],
    ];
    let c = layout.center();
    let mut out = Vec::new();
    for b in backs {
        let l = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
        let eye = [0, 1, 2].map(|k| c[k] + 3.0 * layout.half() * b[k] / l);
        let up = if b[2].abs() < 0.9 * l {
            [0.0, 0.0, 1.0]
        } else {
            [1.0, 0.0, 0.0]
        };
        let fov = 2.0 * 0.6f64.atan().to_degrees();
        let cam = Pinhole::new(eye, b.map(|v| -v), up, fov, px, px).unwrap();
        for j in 0..px {
            for i in 0..px {
                let q = cam.ray(i, j, f32::INFINITY).unwrap();
                out.push((q.origin().map(f64::from), q.dir().map(f64::from)));
            }
        }
    }
    out
}

/// Silhouette pixels that differ from the mesh's (hit against miss) and the mean
/// depth error (half sides) of pixels both hit, for `mesh` at `side` with `frustum`.
fn error_against_mesh(
    mesh: &Mesh,
    frustum: Frustum,
    combine: Combine,
    side: u32,
    pad: bool,
) -> (usize, f64) {
    let layout = Layout::around(mesh, frustum).unwrap();
    let heights = capture_padded(mesh, &layout, side, pad);
    let imp = impostor(layout, &heights, side);
    let (mut wrong, mut both, mut depth_err) = (0, 0, 0.0);
    for (o, d) in camera_rays(&layout, 48) {
        let q =
            Query::<f32>::from_arrays(o.map(|v| v as f32), d.map(|v| v as f32), 0.0, f32::INFINITY)
                .unwrap();
        let r = imp
            .trace(combine, &q, |hf, g| dda::trace(hf, TRI, g))
            .unwrap();
        match (r.trace.hit, mesh.first_hit(o, d, 0.0, f64::INFINITY)) {
            (Some(h), Some((t, _))) => {
                both += 1;
                let len = d.iter().map(|v| v * v).sum::<f64>().sqrt();
                depth_err += (f64::from(h.t) - t).abs() * len / layout.half();
            }
            (None, None) => {}
            _ => wrong += 1,
        }
    }
    (wrong, depth_err / f64::from(both))
}

/// Against the mesh (Möller–Trumbore) at equal side, six views of 48² pixels:
/// silhouette pixels that differ and the mean depth error of pixels both hit. On the
/// bunny, with one field per ray (the paper's renderer) the reverse perspective beats
/// the orthographic fields at both, and the intersection of the six beats one field
/// per ray at both, whichever the frustum; without [`pad_silhouettes`] more silhouette
/// pixels are wrong (the tower is printed).
#[test]
fn frusta_and_combinations_against_the_mesh() {
    let meshes = [("bunny", bunny()), ("tower", tower())];
    for (name, (pos, tri)) in &meshes {
        let mesh = Mesh::new(pos, tri).unwrap();
        for side in [32u32, 64] {
            let mut score = Vec::new();
            for combine in Combine::ALL {
                for frustum in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
                    let e = error_against_mesh(&mesh, frustum, combine, side, true);
                    println!(
                        "{name} {side}² {} {frustum:?}: {} of {} pixels hit/miss wrong, \
                         mean depth error {:.4} half sides",
                        combine.name(),
                        e.0,
                        6 * 48 * 48,
                        e.1
                    );
                    score.push(e);
                }
            }
            if *name != "bunny" {
                continue;
            }
            let [i_ortho, i_reverse, f_ortho, f_reverse] = score[..] else {
                unreachable!()
            };
            assert!(
                f_reverse.0 < f_ortho.0 && f_reverse.1 < f_ortho.1,
                "{score:?}"
            );
            for (i, f) in [(i_ortho, f_ortho), (i_reverse, f_reverse)] {
                assert!(i.0 < f.0 && i.1 < f.1, "{score:?}");
            }
            // Without the padding, silhouette cells ramp into the object.
            let bare = error_against_mesh(
                &mesh,
                Frustum::Orthographic,
                Combine::Intersection,
                side,
                false,
            );
            println!("{name} {side}² intersection Orthographic, not padded: {bare:?}");
            assert!(bare.0 > i_ortho.0, "{bare:?} vs {i_ortho:?}");
        }
    }
}
