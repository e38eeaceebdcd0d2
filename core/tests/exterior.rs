//! Ray sets narrower than every ray (`hfcast::safety::Rays`: exterior rays, a largest
//! view angle, both): both safety-shape bakes for each set, against the brute-force
//! oracle on rays of the set (cameras outside the box, shadow rays traced from an
//! outside light, steep rays) and on every other kind of ray through the march's
//! guard; a test that the guard matters; the sets' distances against all rays'; and
//! the bake's witnesses, explicit rays of the set that a distance one larger would
//! get wrong.
#![cfg(feature = "safety")]

mod common;

use common::{judge_trace, march_fields, rays_with_grazing, Field, RaySpec, Rng, Tally};
use hfcast::bake::{Spec, Texels};
use hfcast::ktx2::{Desc, MapKind};
use hfcast::safety::cc::{CcMap, CcOptions, Slope};
use hfcast::safety::{self, MarchSurface, Occluder, Rays, SafetyMap, Variant, Witness, CLASSES};
use hfcast::{dda, Marcher, Query, Real, Surface, Trace};

const TRI: Surface = Surface::Triangles;

/// The sets under test, by name.
fn sets() -> [(&'static str, Rays); 4] {
    let angle = |exterior, deg| Rays {
        exterior,
        max_view_angle_deg: deg,
        occluders: 0,
    };
    [
        ("exterior", Rays::EXTERIOR),
        ("angle 45", angle(false, 45.0)),
        ("angle 120", angle(false, 120.0)),
        ("exterior angle 45", angle(true, 45.0)),
    ]
}

fn fields() -> Vec<(String, Field)> {
    march_fields(0xe7e, 5, ("checkerboard 24x20", 0.0, 1.0), Vec::new(), 6)
}

/// `field`'s map `map` baked for `rays` through the one bake interface.
fn bake_for(field: &Field, map: MapKind, rays: Rays, nbuffer_slope: bool) -> Vec<u8> {
    bake_with(field, map, (rays, &[]), nbuffer_slope)
}

/// [`bake_for`] with the set's occluders (exact cone slopes).
fn bake_over(field: &Field, map: MapKind, rays: Rays, occluders: &[Occluder]) -> Vec<u8> {
    bake_with(field, map, (rays, occluders), false)
}

fn bake_with(
    field: &Field,
    map: MapKind,
    (rays, occluders): (Rays, &[Occluder]),
    nbuffer_slope: bool,
) -> Vec<u8> {
    let spec = Spec {
        nbuffer_slope,
        ..Spec::new(Desc {
            rays,
            ..Desc::new(map, field.w, field.h)
        })
    };
    match spec.bake_owned_over(&field.hf(), occluders).unwrap() {
        Texels::U8(v) => v,
        Texels::F32(_) => unreachable!("8-bit maps"),
    }
}

/// The directional (or isotropic) safety distances of `field` for `rays`.
fn bake_sd(field: &Field, rays: Rays, variant: Variant) -> Vec<u8> {
    let map = match variant {
        Variant::Directional => MapKind::Safety,
        Variant::Isotropic => MapKind::SafetyIsotropic,
    };
    bake_for(field, map, rays, false)
}

/// The cylinder–cone map of `field` for `rays`.
fn bake_cc(field: &Field, rays: Rays, slope: Slope) -> Vec<u8> {
    bake_for(field, MapKind::Cc, rays, slope == Slope::NBuffer)
}

/// Rays of the exterior and steep kinds: cameras outside the box aimed at the surface
/// (some grazing it), shadow rays traced from outside lights down to surface points,
/// and steep rays from above.
fn set_rays(field: &Field, rng: &mut Rng, n: usize) -> Vec<RaySpec> {
    let hf = field.hf();
    let (xm, ym) = field.far_corner();
    let (zlo, zhi) = field.range();
    let zr = (zhi - zlo).max(1e-3);
    let far = 2.0 * (xm + ym) + 4.0 * zr + 4.0;
    let mut v = Vec::new();
    for k in 0..n {
        let (x, y) = (rng.range(0.0, xm), rng.range(0.0, ym));
        let z = TRI.height_at(&hf, x, y);
        let az = rng.range(0.0, std::f64::consts::TAU);
        // Down to the surface point (camera rays), from slightly above it (grazing),
        // or the light's ray to it (shadow rays traced from the light).
        let el = match k % 4 {
            0 => rng.range(0.01, 0.2),
            1 => rng.range(0.2, 1.0),
            2 => rng.range(0.8, 1.55),
            _ => 10f64.powf(rng.range(-3.0, -1.0)),
        };
        let target = [
            x,
            y,
            z + if k % 4 == 3 {
                rng.range(0.0, 0.05)
            } else {
                0.0
            },
        ];
        let d = [-az.cos() * el.cos(), -az.sin() * el.cos(), -el.sin()];
        let o = [0, 1, 2].map(|c| target[c] - far * d[c]);
        v.push(RaySpec::whole(o, d));
    }
    v
}

/// The rays that would go wrong first on a map whose distances are too long: for
/// sampled texels and classes, the every-ray witness of the every-ray distance `k`
/// (it dips under the surface in column `k`), lowered by a thousandth or a half,
/// started far back outside the box. Those of them that are exterior and within a view
/// angle exercise the narrower sets' longer distances (independently of their bake:
/// the witnesses come from the every-ray bake).
fn dipping_rays(field: &Field, rng: &mut Rng, n: usize) -> Vec<RaySpec> {
    let hf = field.hf();
    let all = bake_sd(field, Rays::ALL, Variant::Directional);
    let every = Rays::ALL.on(&hf);
    let (xm, ym) = field.far_corner();
    let (zlo, zhi) = field.range();
    let far = 2.0 * (xm + ym) + 4.0 * (zhi - zlo) + 4.0;
    let mut v = Vec::new();
    for _ in 0..n {
        let (i, j) = (
            rng.below(field.w as usize) as u32,
            rng.below(field.h as usize) as u32,
        );
        let class = CLASSES[rng.below(4)];
        let k = all[safety::texel_offset(field.w, Variant::Directional, class, i, j)];
        let lower = if rng.chance(0.5) { 1e-3 } else { 0.5 };
        if let Witness::Ray(q) = every.witness(class, i, j, u32::from(k), lower) {
            let (o, d) = (q.origin(), q.dir());
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let o = [0, 1, 2].map(|c| o[c] - far / len * d[c]);
            v.push(RaySpec::whole(o, d));
        }
    }
    v
}

/// What a test's [`judge_all`] calls add up to: wrong rays, traces, rays of the maps'
/// sets, and the report lines.
#[derive(Default)]
struct Totals {
    wrong: u64,
    tried: u64,
    held: u64,
    out: String,
}

impl Totals {
    /// Prints the counts; no wrong ray, and at least `held` rays of the sets.
    fn check(&self, held: u64) {
        let (tried, n) = (self.tried, self.held);
        println!("{tried} traces, {n} of their rays in the map's set");
        assert!(n > held, "too few rays of the sets: {n}");
        assert_eq!(self.wrong, 0, "wrong rays");
    }
}

/// Judges `rays` traced with `m` in `f32` and `f64` into `totals` (with how many the
/// map's set holds), and reports them as `name`.
fn judge_all(
    name: &str,
    field: &Field,
    m: &Marcher,
    (rays, occluders): (Rays, &[Occluder]),
    specs: &[RaySpec],
    totals: &mut Totals,
) {
    let mut t = Tally::new(name);
    for s in specs {
        totals.held += u64::from(rays.holds(&field.hf(), occluders, &s.q64()));
        judge_one(field, m, &s.q32(), &mut t);
        judge_one(field, m, &s.q64(), &mut t);
    }
    totals.wrong += t.wrong;
    totals.tried += t.tried;
    t.report(&mut totals.out);
}

/// Traces `q` with `m` and counts the verdict in `t`.
fn judge_one<R: Real>(field: &Field, m: &Marcher, q: &Query<R>, t: &mut Tally) {
    let got: Trace<R> = m.trace(&field.hf(), q);
    t.tried += 1;
    t.hits += u64::from(got.hit.is_some());
    match judge_trace(field, TRI, &got, q, field.z_scale()) {
        None => t.ambiguous += 1,
        Some(true) => {}
        Some(false) => t.wrong(|| format!("{q:?} got {:?}", got.hit)),
    }
}

#[test]
fn zero_wrong_rays_for_every_set() {
    let mut rng = Rng::new(0xe7e);
    let mut totals = Totals::default();
    for (name, field) in fields() {
        let hf = field.hf();
        let mut specs = set_rays(&field, &mut rng, 240);
        specs.extend(rays_with_grazing(&field, TRI, &mut rng, 12));
        specs.extend(dipping_rays(&field, &mut rng, 400));
        for (set_name, rays) in sets() {
            let mut maps: Vec<(String, Vec<u8>, Option<Variant>)> = Vec::new();
            for variant in [Variant::Directional, Variant::Isotropic] {
                maps.push((
                    format!("{variant:?}"),
                    bake_sd(&field, rays, variant),
                    Some(variant),
                ));
            }
            for slope in [Slope::Exact, Slope::NBuffer] {
                maps.push((format!("CC {slope:?}"), bake_cc(&field, rays, slope), None));
            }
            for (what, data, variant) in &maps {
                let m = match variant {
                    Some(v) => Marcher::Safety(
                        SafetyMap::new(&hf, data, *v).unwrap().with_rays(rays),
                        MarchSurface::Triangles,
                    ),
                    None => Marcher::Cc(
                        CcMap::new(&hf, data, CcOptions::default().cap)
                            .unwrap()
                            .with_rays(rays),
                        MarchSurface::Triangles,
                    ),
                };
                let name = format!("{name} {set_name} {what}");
                judge_all(&name, &field, &m, (rays, &[]), &specs, &mut totals);
            }
        }
    }
    println!("{}", totals.out);
    totals.check(20_000);
}

/// Without the guard (the same bytes read as a map for every ray) some ray outside
/// the set is wrong, for the exterior set and for the view angle alike. The rays: of
/// every kind (most start inside the box), and, for every texel whose distance the set
/// lengthens, the every-ray witness of the shorter distance started a quarter texel
/// before the texel's centerline (inside the box, so not exterior).
#[test]
fn the_guard_matters() {
    let mut rng = Rng::new(0x6a7d);
    for (set_name, rays) in [sets()[0], sets()[1]] {
        let (mut wrong_unguarded, mut wrong_guarded, mut tried) = (0, 0, 0);
        for (_, field) in fields() {
            let hf = field.hf();
            let all = bake_sd(&field, Rays::ALL, Variant::Directional);
            let data = bake_sd(&field, rays, Variant::Directional);
            let mut qs: Vec<Query<f64>> = rays_with_grazing(&field, TRI, &mut rng, 40)
                .iter()
                .map(RaySpec::q64)
                .collect();
            qs.extend(inside_witnesses(&field, &all, &data));
            let map = SafetyMap::new(&hf, &data, Variant::Directional).unwrap();
            for q in &qs {
                if rays.holds(&hf, &[], q) {
                    continue;
                }
                tried += 1;
                let oracle = dda::trace(&hf, TRI, q);
                let bad = |t: &hfcast::Trace<f64>| match (oracle.hit, t.hit) {
                    (None, None) => false,
                    (Some(a), Some(b)) => {
                        common::dist(a.point.to_array(), b.point.to_array()) > 1e-6
                    }
                    _ => true,
                };
                let unguarded = safety::trace(&map, &hf, q);
                let guarded = safety::trace(&map.with_rays(rays), &hf, q);
                wrong_unguarded += u64::from(bad(&unguarded) && oracle.clearance > 1e-9);
                wrong_guarded += u64::from(bad(&guarded) && oracle.clearance > 1e-9);
            }
        }
        println!(
            "{set_name}: {tried} rays outside the set; unguarded {wrong_unguarded} wrong, \
             guarded {wrong_guarded}"
        );
        assert_eq!(wrong_guarded, 0, "{set_name}: guarded");
        assert!(wrong_unguarded > 0, "{set_name}: the guard saved no ray");
    }
}

/// For the texels whose distance in `longer` exceeds that in `all`: the every-ray
/// witness of the `all` distance, started a quarter texel before the texel's
/// centerline (where it is above the surface).
fn inside_witnesses(field: &Field, all: &[u8], longer: &[u8]) -> Vec<Query<f64>> {
    let hf = field.hf();
    let every = Rays::ALL.on(&hf);
    let mut v = Vec::new();
    for j in 0..field.h {
        for i in 0..field.w {
            for class in CLASSES {
                let at = safety::texel_offset(field.w, Variant::Directional, class, i, j);
                if longer[at] <= all[at] {
                    continue;
                }
                let Witness::Ray(q) = every.witness(class, i, j, u32::from(all[at]), 0.5) else {
                    continue;
                };
                let (ax, _) = common::class_axis(class);
                let (o, d) = (q.origin(), q.dir());
                let m = f64::from(if ax == 0 { i } else { j });
                let t = (m - o[ax]) / d[ax] - 0.25 / d[ax].abs();
                let start = q.at(t);
                if common::clearance(field, TRI, &q, t) > 1e-6 {
                    v.extend(Query::from_arrays(start, d, 0.0, f64::INFINITY));
                }
            }
        }
    }
    v
}

/// A narrower set never has a shorter distance (its limiting triangles are some of
/// the wider set's), and the sets lengthen them on the fields.
#[test]
fn narrower_sets_have_longer_distances() {
    for (name, field) in fields().into_iter().take(6) {
        let all = bake_sd(&field, Rays::ALL, Variant::Directional);
        let mut sums = vec![("all", all.iter().map(|&d| u64::from(d)).sum::<u64>())];
        let maps: Vec<(&str, Vec<u8>)> = sets()
            .into_iter()
            .map(|(n, r)| (n, bake_sd(&field, r, Variant::Directional)))
            .collect();
        let get = |n: &str| &maps.iter().find(|(m, _)| *m == n).unwrap().1;
        let pairs = [
            ("exterior", "all"),
            ("angle 45", "all"),
            ("angle 120", "all"),
            ("angle 45", "angle 120"),
            ("exterior angle 45", "angle 45"),
            ("exterior angle 45", "exterior"),
        ];
        for (narrow, wide) in pairs {
            let (a, b) = (get(narrow), if wide == "all" { &all } else { get(wide) });
            let shorter = a.iter().zip(b).filter(|(x, y)| x < y).count();
            assert_eq!(shorter, 0, "{name}: {narrow} shorter than {wide}");
        }
        for (n, m) in &maps {
            sums.push((n, m.iter().map(|&d| u64::from(d)).sum()));
        }
        println!("{name}: distance sums {sums:?}");
    }
}

/// For sampled texels and classes of distance `k` below the cap, the bake's witness
/// for column `k` is checked with the oracle ([`witness_checks`]): a ray of the set
/// (outside the box for the exterior set) that exits the solid in column `k`, and,
/// for many, is above the surface where a jump of `k + 1` would land, so that jump
/// would skip its hit. The witness line is lowered by a millionth to nine tenths of
/// its height above the surface (the first that lands above counts). Every sampled
/// texel must have a witness or a scan that gave up (conservative); nine in ten
/// witnesses must exit in column `k`, one in three land above.
#[test]
fn witnesses_show_distance_plus_one_is_wrong() {
    let mut rng = Rng::new(0x717);
    for (set_name, rays) in sets() {
        witnesses_of(set_name, |_| (rays, Vec::new()), &mut rng);
    }
}

/// [`witnesses_show_distance_plus_one_is_wrong`] for the set (and occluders) that
/// `set_of` gives each field.
fn witnesses_of(set_name: &str, set_of: impl Fn(&Field) -> (Rays, Vec<Occluder>), rng: &mut Rng) {
    let (mut sampled, mut shown, mut gave_up) = (0u64, 0u64, 0u64);
    let (mut exits, mut lands) = (0u64, 0u64);
    for (_, field) in fields().into_iter().take(8) {
        let hf = field.hf();
        let (w, h) = (field.w, field.h);
        if w < 8 || h < 8 {
            continue;
        }
        let (rays, occluders) = set_of(&field);
        let data = bake_over(&field, MapKind::Safety, rays, &occluders);
        let set = rays.on_over(&hf, &occluders).unwrap();
        for _ in 0..120 {
            let (i, j) = (rng.below(w as usize) as u32, rng.below(h as usize) as u32);
            let class = CLASSES[rng.below(4)];
            let k = u32::from(data[safety::texel_offset(w, Variant::Directional, class, i, j)]);
            let (ax, sg) = common::class_axis(class);
            let (m, lm) = if ax == 0 { (i, w) } else { (j, h) };
            let ahead = if sg > 0.0 { lm - 1 - m } else { m };
            if k >= ahead || k == 255 {
                continue;
            }
            sampled += 1;
            let (mut any, mut exit, mut land) = (false, false, false);
            for lower in [1e-6, 1e-3, 0.1, 0.5, 0.9] {
                match set.witness(class, i, j, k, lower) {
                    Witness::Ray(q) => {
                        any = true;
                        let at = (ax, sg, m, k);
                        let verdict = witness_checks(&field, (rays, &occluders), &q, at);
                        exit |= verdict.is_some();
                        land |= verdict == Some(true);
                        if land {
                            break;
                        }
                    }
                    Witness::NoRay => {
                        gave_up += 1;
                        break;
                    }
                    Witness::None => break,
                }
            }
            shown += u64::from(any);
            exits += u64::from(exit);
            lands += u64::from(land);
        }
    }
    println!(
        "{set_name}: {sampled} texels sampled: {shown} witnesses, {gave_up} without a \
         ray to show (conservative); by the oracle {exits} exit the solid in column k, \
         {lands} of them are above it where a jump of k + 1 lands"
    );
    assert!(sampled > 200, "{set_name}: {sampled} sampled");
    assert_eq!(
        shown + gave_up,
        sampled,
        "{set_name}: a texel without a witness"
    );
    assert!(
        exits * 10 >= shown * 9,
        "{set_name}: {exits} of {shown} witnesses exit"
    );
    assert!(
        lands * 3 >= shown,
        "{set_name}: {lands} of {shown} witnesses land above"
    );
}

/// What the oracle says of a witness `q` for the texel on centerline `m` and column
/// `k` ahead: `Some(lands_above)` when `q` is a ray of `rays`, above the surface where
/// it crosses centerline `m`, whose first hit lies before the centerline `k + 1`
/// ahead and which leaves the solid again before it (an exit in column `k`: the bake's
/// distance cannot exceed `k`); `lands_above` when it is above the surface on that
/// centerline, where a jump of `k + 1` would land (so that jump would skip the hit).
fn witness_checks(
    field: &Field,
    (rays, occluders): (Rays, &[Occluder]),
    q: &Query<f64>,
    (ax, sg, m, k): (usize, f64, u32, u32),
) -> Option<bool> {
    let hf = field.hf();
    if !rays.holds(&hf, occluders, q) {
        return None;
    }
    let (o, d) = (q.origin(), q.dir());
    let t_at = |line: f64| (line - o[ax]) / d[ax];
    let (t0, t1) = (
        t_at(f64::from(m)),
        t_at(f64::from(m) + sg * f64::from(k + 1)),
    );
    let above = |t: f64| common::clearance(field, TRI, q, t) > 1e-9;
    let hit = dda::trace(&hf, TRI, q).hit.map(|h| h.t)?;
    if !(above(t0) && hit > t0 && hit < t1) {
        return None;
    }
    let exits = common::breakpoints(q, hit, t1).into_iter().any(above) || above(t1);
    exits.then(|| above(t1))
}

/// Shadow rays of camera hits traced from the light's side
/// (`Hit::shadow_query_from_light`, what `Shadows::FromLight` scenes trace): each starts
/// outside the box, so the exterior set holds it; each meets the surface iff the shadow
/// ray from the lit point does (where neither is ambiguous); through the exterior maps
/// each is right against the oracle, and the maps' steps serve them: fewer fetches than
/// the same rays walked cell by cell (the same bytes read as a map of a set that holds
/// none of them: the guard's walk). (The rays from the lit points cost fewer still on
/// these fields: a shadowed one stops at its first hit, near the point.)
#[test]
fn shadow_rays_from_the_light() {
    let mut rng = Rng::new(0x5a0);
    let (mut compared, mut disagree, mut wrong) = (0u64, 0u64, 0u64);
    // Per map (SD, CC): fetches of the rays from the light, through the map and walked.
    let mut fetches = [[0u64; 2]; 2];
    for (name, field) in fields() {
        let hf = field.hf();
        let exact = Marcher::Exact(TRI);
        let mut down: Vec<Query<f32>> = Vec::new();
        for spec in set_rays(&field, &mut rng, 300) {
            let q = spec.q32();
            let Some(hit) = exact.trace(&hf, &q).hit else {
                continue;
            };
            let m = q.origin().iter().fold(0f32, |m, v| m.max(v.abs()));
            for (az, el) in [(0.3f32, 0.15f32), (2.0, 0.5), (4.0, 1.1)] {
                let light = [az.cos() * el.cos(), az.sin() * el.cos(), el.sin()];
                let up = hit.shadow_query(&hf, TRI, light, m).unwrap();
                let from_light = hit.shadow_query_from_light(&hf, TRI, light, m).unwrap();
                assert!(
                    Rays::EXTERIOR.holds(&hf, &[], &from_light),
                    "{name}: {from_light:?} does not start outside the box"
                );
                let (a, b) = (exact.trace(&hf, &up), exact.trace(&hf, &from_light));
                let clear = |t: &Trace<f32>, q| judge_trace(&field, TRI, t, q, field.z_scale());
                if clear(&a, &up) == Some(true) && clear(&b, &from_light) == Some(true) {
                    compared += 1;
                    disagree += u64::from(a.hit.is_some() != b.hit.is_some());
                }
                down.push(from_light);
            }
        }
        let (sd, cc) = (
            bake_sd(&field, Rays::EXTERIOR, Variant::Directional),
            bake_cc(&field, Rays::EXTERIOR, Slope::Exact),
        );
        // A set no ray here is in (none is within a thousandth of a degree of the
        // vertical): the guard walks every ray.
        let none = Rays {
            max_view_angle_deg: 1e-3,
            ..Rays::EXTERIOR
        };
        let maps = [Rays::EXTERIOR, none].map(|set| {
            [
                Marcher::Safety(
                    SafetyMap::new(&hf, &sd, Variant::Directional)
                        .unwrap()
                        .with_rays(set),
                    MarchSurface::Triangles,
                ),
                Marcher::Cc(
                    CcMap::new(&hf, &cc, CcOptions::default().cap)
                        .unwrap()
                        .with_rays(set),
                    MarchSurface::Triangles,
                ),
            ]
        });
        for ((m, walked), f) in maps[0].iter().zip(&maps[1]).zip(&mut fetches) {
            let mut t = Tally::new(format!("{name} {:?} from the light", m.kind()));
            for q in &down {
                judge_one(&field, m, q, &mut t);
                judge_one(&field, m, &q.cast::<f64>(), &mut t);
                f[0] += u64::from(m.trace(&hf, q).fetches);
                f[1] += u64::from(walked.trace(&hf, q).fetches);
            }
            wrong += t.wrong;
            let mut out = String::new();
            t.report(&mut out);
            print!("{out}");
        }
    }
    println!(
        "{compared} pairs compared, {disagree} disagree; fetches of the rays from the \
         light, through the map / walked: SD {:?}, CC {:?}",
        fetches[0], fetches[1]
    );
    assert!(compared > 3000, "too few shadow rays compared: {compared}");
    assert_eq!(disagree, 0, "from the light and from the surface disagree");
    assert_eq!(wrong, 0, "wrong shadow rays from the light");
    for [map, walked] in fetches {
        assert!(
            map < walked,
            "the maps' steps do not serve the light's rays"
        );
    }
}

/// Walls around `field` as occluders (each wall's top as two triangles, one texel out
/// from the field, two thick). `ring`: four walls with level tops a fifth of the
/// height range above the highest sample. Else three (none to the south) whose tops
/// slope from the middle of the range up to above the highest sample: partly lower
/// than the terrain, so rays come in over them at every height.
fn walls_around(field: &Field, ring: bool) -> Vec<Occluder> {
    let (xm, ym) = field.far_corner();
    let (zlo, zhi) = field.range();
    let zr = (zhi - zlo).max(1e-3);
    let level = zhi + 0.2 * zr;
    let top = |x: f64, y: f64| {
        if ring {
            level
        } else {
            zlo + 0.5 * zr + 0.7 * zr * (x / xm.max(1.0) + y / ym.max(1.0)) / 2.0
        }
    };
    let (x0, x1, y0, y1) = (-3.0, xm + 3.0, -3.0, ym + 3.0);
    let mut rects = vec![
        ([x0, -1.0], [y0, y1]),
        ([xm + 1.0, x1], [y0, y1]),
        ([x0, x1], [ym + 1.0, y1]),
    ];
    if ring {
        rects.push(([x0, x1], [y0, -1.0]));
    }
    rects
        .into_iter()
        .flat_map(|(x, y)| Occluder::rectangle(x, y, top))
        .collect()
}

/// The occluder sets under test on `field`: the exterior set over each kind of walls,
/// and over the ring within 45° of the vertical.
fn occluder_sets(field: &Field) -> Vec<(&'static str, Rays, Vec<Occluder>)> {
    let over = |rays: Rays, ring| {
        let walls = walls_around(field, ring);
        (rays.passing_over(&walls).unwrap(), walls)
    };
    let phi = sets()[3].1;
    let (a, b, c) = (
        over(Rays::EXTERIOR, true),
        over(Rays::EXTERIOR, false),
        over(phi, true),
    );
    vec![
        ("exterior occluder ring", a.0, a.1),
        ("exterior occluder slopes", b.0, b.1),
        ("exterior phi 45 occluder ring", c.0, c.1),
    ]
}

/// Maps baked over occluders: 0 wrong rays against the oracle (rays of the set, which
/// come in over the walls, and every other ray through the guard, in `f32` and `f64`),
/// and no distance shorter than the set's without the occluders, some longer.
#[test]
fn occluders_zero_wrong_rays_and_longer_distances() {
    let mut rng = Rng::new(0x0cc1);
    let mut totals = Totals::default();
    let (mut sum_without, mut sum_with) = (0u64, 0u64);
    for (name, field) in fields().into_iter().take(10) {
        let hf = field.hf();
        let mut specs = set_rays(&field, &mut rng, 240);
        specs.extend(rays_with_grazing(&field, TRI, &mut rng, 12));
        specs.extend(dipping_rays(&field, &mut rng, 300));
        for (set_name, rays, walls) in occluder_sets(&field) {
            let without = Rays {
                occluders: 0,
                ..rays
            };
            let sd_without = bake_sd(&field, without, Variant::Directional);
            let sd = bake_over(&field, MapKind::Safety, rays, &walls);
            let cc = bake_over(&field, MapKind::Cc, rays, &walls);
            let shorter = sd.iter().zip(&sd_without).filter(|(a, b)| a < b).count();
            assert_eq!(
                shorter, 0,
                "{name} {set_name}: shorter than without occluders"
            );
            sum_without += sd_without.iter().map(|&d| u64::from(d)).sum::<u64>();
            sum_with += sd.iter().map(|&d| u64::from(d)).sum::<u64>();
            let sd_map = SafetyMap::new(&hf, &sd, Variant::Directional).unwrap();
            let cc_map = CcMap::new(&hf, &cc, CcOptions::default().cap).unwrap();
            let marchers = [
                (
                    "SD",
                    Marcher::Safety(sd_map.with_rays(rays), MarchSurface::Triangles),
                ),
                (
                    "CC",
                    Marcher::Cc(cc_map.with_rays(rays), MarchSurface::Triangles),
                ),
            ];
            for (what, m) in marchers {
                let m = m.with_occluders(&hf, &walls).unwrap();
                let name = format!("{name} {set_name} {what}");
                judge_all(&name, &field, &m, (rays, &walls), &specs, &mut totals);
            }
        }
    }
    println!("{}", totals.out);
    println!("safety distances summed: {sum_without} without the occluders, {sum_with} with them");
    assert!(
        sum_with > sum_without,
        "the occluders lengthened no distance"
    );
    totals.check(5_000);
}

/// A map over occluders must be read with them: the guard of the exterior set alone
/// (the same bytes read as an exterior map) gets rays wrong that come from under a
/// wall, the occluders' guard none. The rays: for texels the walls lengthen, the
/// exterior set's own witnesses of its shorter distance (exterior rays that would be
/// wrong with one more step, so they must dip under a wall).
#[test]
fn the_occluder_guard_matters() {
    let (mut tried, mut wrong_exterior, mut wrong_guarded) = (0u64, 0u64, 0u64);
    for (_, field) in fields().into_iter().take(10) {
        let hf = field.hf();
        let (rays, walls) = {
            let (_, r, w) = occluder_sets(&field).swap_remove(0);
            (r, w)
        };
        let ext = bake_sd(&field, Rays::EXTERIOR, Variant::Directional);
        let data = bake_over(&field, MapKind::Safety, rays, &walls);
        let map = SafetyMap::new(&hf, &data, Variant::Directional).unwrap();
        let as_exterior = map.with_rays(Rays::EXTERIOR);
        let guarded = map.with_rays(rays).with_occluders(&hf, &walls).unwrap();
        let every_exterior = Rays::EXTERIOR.on(&hf);
        for j in 0..field.h {
            for i in 0..field.w {
                for class in CLASSES {
                    let at = safety::texel_offset(field.w, Variant::Directional, class, i, j);
                    if data[at] <= ext[at] {
                        continue;
                    }
                    let k = u32::from(ext[at]);
                    let Witness::Ray(q) = every_exterior.witness(class, i, j, k, 0.5) else {
                        continue;
                    };
                    if !Rays::EXTERIOR.holds(&hf, &[], &q) {
                        continue;
                    }
                    tried += 1;
                    let oracle = dda::trace(&hf, TRI, &q);
                    let bad = |t: &Trace<f64>| match (oracle.hit, t.hit) {
                        (None, None) => false,
                        (Some(a), Some(b)) => {
                            common::dist(a.point.to_array(), b.point.to_array()) > 1e-6
                        }
                        _ => true,
                    };
                    let clear = oracle.clearance > 1e-9;
                    wrong_exterior +=
                        u64::from(bad(&safety::trace(&as_exterior, &hf, &q)) && clear);
                    wrong_guarded += u64::from(bad(&safety::trace(&guarded, &hf, &q)) && clear);
                    assert!(
                        !rays.holds(&hf, &walls, &q) || !bad(&safety::trace(&guarded, &hf, &q))
                    );
                }
            }
        }
    }
    println!(
        "{tried} exterior witnesses where the walls lengthen a distance: read as an \
         exterior map {wrong_exterior} wrong, with the occluders' guard {wrong_guarded}"
    );
    assert_eq!(wrong_guarded, 0, "guarded");
    assert!(wrong_exterior > 0, "the occluders' guard saved no ray");
}

/// The bake's witnesses over occluders: explicit rays that come in over the walls and
/// would be wrong with one more step ([`witnesses_of`]).
#[test]
fn occluder_witnesses_show_distance_plus_one_is_wrong() {
    let mut rng = Rng::new(0x0cc2);
    for k in 0..3 {
        let name = [
            "exterior occluder ring",
            "exterior occluder slopes",
            "exterior phi 45 occluder ring",
        ][k];
        witnesses_of(
            name,
            |field| {
                let (_, rays, walls) = occluder_sets(field).swap_remove(k);
                (rays, walls)
            },
            &mut rng,
        );
    }
}

/// A map baked over occluders refuses other occluders, and without them holds no ray.
#[test]
fn a_map_over_occluders_takes_its_own() {
    let (_, field) = fields().swap_remove(0);
    let hf = field.hf();
    let (_, rays, walls) = occluder_sets(&field).swap_remove(0);
    let data = bake_over(&field, MapKind::Safety, rays, &walls);
    let map = SafetyMap::new(&hf, &data, Variant::Directional)
        .unwrap()
        .with_rays(rays);
    assert!(map.with_occluders(&hf, &walls[1..]).is_err());
    assert!(map.with_occluders(&hf, &[]).is_err());
    let spec = Spec::new(Desc {
        rays,
        ..Desc::new(MapKind::Safety, field.w, field.h)
    });
    assert!(spec.bake_owned_over(&hf, &walls[..2]).is_err());
    let (xm, ym) = field.far_corner();
    let (_, zhi) = field.range();
    let q = Query::from_arrays(
        [xm / 2.0, ym / 2.0, zhi + 100.0],
        [0.1, 0.2, -1.0],
        0.0,
        f64::INFINITY,
    )
    .unwrap();
    assert!(rays.holds(&hf, &walls, &q));
    assert!(!rays.holds(&hf, &[], &q), "no occluders: no ray held");
}
