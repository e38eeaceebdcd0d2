//! World units (`hfcast::world`): a field placed by a per-axis scale and offset answers
//! world rays with the hits of the converted grid rays, mapped back; the identity
//! changes no bit; bad transforms and rays that overflow the conversion are errors.

mod common;

use common::*;
use hfcast::world::{TransformError, WorldTransform};
use hfcast::{dda, Flags, Query, Surface, Trace};

/// A transform with unequal spacings, a flipped y (north-up raster), a height scale and
/// offsets: every coefficient differs from 1 and 0.
fn dem_like() -> WorldTransform {
    WorldTransform::new([500_000.0, 4_100_000.0], [30.0, -25.0], 2.5, 236.0).unwrap()
}

/// A random ray of a random kind.
fn any_ray(rng: &mut Rng, field: &Field, surface: Surface) -> RaySpec {
    let kind = RayKind::ALL[rng.below(RayKind::ALL.len())];
    random_ray(rng, field, surface, kind)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[test]
fn bad_transforms_are_errors() {
    let ok = ([0.0, 0.0], [1.0, 1.0], 1.0, 0.0);
    assert!(WorldTransform::new(ok.0, ok.1, ok.2, ok.3)
        .unwrap()
        .is_identity());
    let cases = [
        (
            ([f64::NAN, 0.0], [1.0, 1.0], 1.0, 0.0),
            TransformError::NotFinite,
        ),
        (
            ([0.0, 0.0], [1.0, f64::INFINITY], 1.0, 0.0),
            TransformError::NotFinite,
        ),
        (
            ([0.0, 0.0], [1.0, 1.0], 1.0, f64::NAN),
            TransformError::NotFinite,
        ),
        (
            ([0.0, 0.0], [0.0, 1.0], 1.0, 0.0),
            TransformError::ZeroSpacing,
        ),
        (
            ([0.0, 0.0], [1.0, -0.0], 1.0, 0.0),
            TransformError::ZeroSpacing,
        ),
        (
            ([0.0, 0.0], [1.0, 1.0], 0.0, 0.0),
            TransformError::HeightScaleNotPositive,
        ),
        (
            ([0.0, 0.0], [1.0, 1.0], -2.0, 0.0),
            TransformError::HeightScaleNotPositive,
        ),
    ];
    for ((o, s, hs, ho), want) in cases {
        assert_eq!(
            WorldTransform::new(o, s, hs, ho),
            Err(want),
            "{o:?} {s:?} {hs} {ho}"
        );
    }
}

#[test]
fn identity_changes_no_bit() {
    let mut rng = Rng::new(7);
    let field = fractal_field(&mut rng, 33, 29, 33, 6.0);
    let hf = field.hf();
    assert!(hf.transform().is_identity());
    let id = WorldTransform::IDENTITY;
    for _ in 0..2000 {
        let q = any_ray(&mut rng, &field, Surface::Triangles).q32();
        let g = id
            .query_to_grid(q.origin(), q.dir(), q.t_min(), q.t_max())
            .unwrap();
        assert_eq!(g, q);
        let tr = dda::trace(&hf, Surface::Triangles, &q);
        assert_eq!(id.trace_to_world(tr), tr);
    }
}

/// World rays through a placed field: the same `t` as the grid trace of the converted
/// ray (exact in f64: the oracle), the world hit point on the world ray, the world
/// normal perpendicular to the world images of the surface's tangents, the clearance
/// scaled by the height scale.
#[test]
fn world_rays_hit_where_grid_rays_do() {
    let mut rng = Rng::new(11);
    let field = fractal_field(&mut rng, 40, 36, 40, 8.0);
    let xf = dem_like();
    let hf = field.hf().with_transform(xf);
    assert_eq!(*hf.transform(), xf);
    let (mut hits, mut checked) = (0, 0);
    for _ in 0..3000 {
        let g = any_ray(&mut rng, &field, Surface::Triangles).q64();
        // The world ray whose grid image is `g`.
        let (o, d) = (xf.point_to_world(g.origin()), xf.dir_to_world(g.dir()));
        let w = Query::<f64>::from_arrays(o, d, g.t_min(), g.t_max()).unwrap();
        let grid = dda::trace(&hf, Surface::Triangles, &g);
        let world: Trace<f64> = xf
            .trace(&w, |q| dda::trace(&hf, Surface::Triangles, q))
            .unwrap();
        checked += 1;
        assert_eq!(world.hit.is_some(), grid.hit.is_some(), "{g:?}");
        assert_eq!(world.fetches, grid.fetches);
        if grid.clearance.is_finite() {
            let want = grid.clearance * xf.height_scale();
            assert!((world.clearance - want).abs() <= 1e-9 * want.abs().max(1.0));
        }
        let (Some(gh), Some(wh)) = (grid.hit, world.hit) else {
            continue;
        };
        hits += 1;
        let scale = 1e-9 * (1.0 + gh.t.abs());
        assert!((wh.t - gh.t).abs() <= scale, "t {} vs {}", wh.t, gh.t);
        assert_eq!(wh.cell, gh.cell);
        assert_eq!(wh.flags, gh.flags);
        let on_ray = w.at(wh.t);
        let p = p64::<f64>(wh.point);
        assert!(
            dist(on_ray, p) <= 1e-6 * (1.0 + dist(o, [0.0; 3])),
            "{on_ray:?} {p:?}"
        );
        // Two tangents of the grid plane with normal n, mapped to world space.
        let n = p64::<f64>(gh.normal);
        let t1 = if n[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let c = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let u = c(n, t1);
        let v = c(n, u);
        let nw = p64::<f64>(wh.normal);
        assert!((dot(nw, nw) - 1.0).abs() < 1e-12);
        for tan in [u, v] {
            let tw = xf.dir_to_world(tan);
            assert!(
                dot(nw, tw).abs() <= 1e-9 * dot(tw, tw).sqrt(),
                "{nw:?} ⟂ {tw:?}"
            );
        }
        // Up stays up: a top hit's world normal points up.
        if !gh.flags.contains(Flags::SIDE) && !gh.flags.contains(Flags::WALL) {
            assert!(nw[2] > 0.0);
        }
    }
    assert!(checked == 3000 && hits > 500, "{hits} hits");
}

/// The f32 path through a placed field agrees with the f64 one (the same rays,
/// converted in f64 and rounded once): hit or miss alike on every ray the f64
/// trace does not call ambiguous.
#[test]
fn world_rays_in_f32() {
    let mut rng = Rng::new(5);
    let field = fractal_field(&mut rng, 64, 48, 64, 10.0);
    let xf = WorldTransform::new([-120.0, 40.0], [2.0, 3.0], 0.5, -7.0).unwrap();
    let hf = field.hf().with_transform(xf);
    let mut differ = 0;
    for _ in 0..3000 {
        let g = any_ray(&mut rng, &field, Surface::Bilinear).q64();
        let (o, d) = (xf.point_to_world(g.origin()), xf.dir_to_world(g.dir()));
        let w32 = Query::<f32>::from_arrays(
            o.map(|v| v as f32),
            d.map(|v| v as f32),
            g.t_min() as f32,
            g.t_max() as f32,
        );
        let Ok(w32) = w32 else { continue };
        let w64: Query<f64> = w32.cast();
        let a = xf
            .trace(&w32, |q| dda::trace(&hf, Surface::Bilinear, q))
            .unwrap();
        let b = xf
            .trace(&w64, |q| dda::trace(&hf, Surface::Bilinear, q))
            .unwrap();
        if a.hit.is_some() != b.hit.is_some() && b.clearance.abs() > 1e-3 {
            differ += 1;
        }
    }
    assert_eq!(differ, 0);
}

/// A world ray whose grid image overflows f32 (a huge origin over a tiny spacing), or
/// whose direction underflows to zero, is a `RayError`, never a silent miss.
#[test]
fn overflowing_conversion_is_an_error() {
    let xf = WorldTransform::new([0.0, 0.0], [1e-30, 1e-30], 1.0, 0.0).unwrap();
    assert!(xf
        .query_to_grid([1e10f32, 0.0, 1.0], [1.0, 0.0, -1.0], 0.0, f32::INFINITY)
        .is_err());
    let big = WorldTransform::new([0.0, 0.0], [1e30, 1e30], 1e30, 0.0).unwrap();
    assert!(big
        .query_to_grid([1.0f32, 1.0, 1.0], [1e-20, 0.0, 0.0], 0.0, f32::INFINITY)
        .is_err());
    // The world ray's own faults keep their names.
    let e = dem_like().query_to_grid([f32::NAN, 0.0, 0.0], [0.0, 0.0, -1.0], 0.0, 1.0);
    assert_eq!(e, Err(hfcast::RayError::OriginNotFinite));
}

/// Shadow rays: started at the hit point itself, many report `ORIGIN_INSIDE` (the point
/// rounds into the solid); from `Hit::shadow_query` none does, on every surface.
#[test]
fn shadow_query_starts_outside() {
    let mut rng = Rng::new(3);
    let field = fractal_field(&mut rng, 96, 80, 96, 20.0);
    let hf = field.hf();
    let light = [0.3f32, -0.4, 0.6];
    for surface in Surface::ALL {
        let (mut naive, mut lifted, mut n) = (0, 0, 0);
        for _ in 0..4000 {
            let q = any_ray(&mut rng, &field, surface).q32();
            let Some(h) = dda::trace(&hf, surface, &q).hit else {
                continue;
            };
            if h.flags.contains(Flags::ORIGIN_INSIDE) {
                continue;
            }
            n += 1;
            let p = h.point.to_array();
            let at = Query::from_arrays(p, light, 0.0, f32::INFINITY).unwrap();
            let inside = |t: Trace<f32>| {
                t.hit
                    .is_some_and(|h| h.flags.contains(Flags::ORIGIN_INSIDE))
            };
            naive += usize::from(inside(dda::trace(&hf, surface, &at)));
            let m = q.origin().iter().fold(0f32, |m, v| m.max(v.abs()));
            let sq = h.shadow_query(&hf, surface, light, m).unwrap();
            lifted += usize::from(inside(dda::trace(&hf, surface, &sq)));
        }
        assert!(n > 1000, "{surface:?}: {n} hits");
        assert!(
            naive > n / 20,
            "{surface:?}: only {naive} of {n} start inside: the test does not bite"
        );
        assert_eq!(
            lifted, 0,
            "{surface:?}: {lifted} of {n} lifted shadow rays start inside"
        );
    }
}
