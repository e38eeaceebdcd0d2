//! Bit-identity check of the safety-shape marches: traces a fixed large ray set
//! (camera rays, random rays of every kind; `f32` and `f64`) through
//! `safety::trace_on`, `cc::trace_on` and `radius::trace` on a few fields and prints
//! one hash of every `Trace` field per method. Compare the output before and after a
//! change of the march.
//!
//! `cargo run --release -p hfcast --example march_check`

mod common;
#[path = "../tests/common/mod.rs"]
mod tc;

use common::{camera_rays, downsample, load_png};
use hfcast::radius::{self, RadiusMap, Zero};
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, MarchSurface, SafetyMap, Variant};
use hfcast::{HeightField, Query, Real, Surface, Trace};
use tc::{Field, RayKind, RaySpec, Rng};

/// FNV-1a over 64-bit words.
struct H(u64);
impl H {
    fn w(&mut self, v: u64) {
        for b in v.to_le_bytes() {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    fn r<R: Real>(&mut self, v: R) {
        self.w(v.to_f64().to_bits());
    }
    fn trace<R: Real>(&mut self, t: &Trace<R>) {
        self.w(u64::from(t.fetches));
        self.r(t.clearance);
        self.w(u64::from(t.flags.0));
        match &t.hit {
            None => self.w(7),
            Some(h) => {
                self.r(h.t);
                R::xyz(h.point).into_iter().for_each(|v| self.r(v));
                R::xyz(h.normal).into_iter().for_each(|v| self.r(v));
                self.w(u64::from(h.cell[0]) << 32 | u64::from(h.cell[1]));
                self.w(u64::from(h.flags.0));
            }
        }
    }
}

fn rays_of(field: &Field, hf: &HeightField, seed: u64, n: usize) -> Vec<RaySpec> {
    let mut v = Vec::new();
    for el in [45.0, 5.0, 80.0] {
        for q in camera_rays(hf, el, 30.0 + el, 96, 80) {
            let (o, d) = (q.origin(), q.dir());
            v.push(RaySpec::whole(o.map(f64::from), d.map(f64::from)));
        }
    }
    let mut rng = Rng::new(seed);
    for i in 0..n {
        let kind = RayKind::ALL[i % RayKind::ALL.len()];
        let surface = if i % 2 == 0 {
            Surface::Triangles
        } else {
            Surface::ViewLinear
        };
        v.push(tc::random_ray(&mut rng, field, surface, kind));
    }
    v
}

fn run<R: Real>(name: &str, hf: &HeightField, maps: &Maps, rays: &[Query<R>], total: &mut H) {
    let sm = [
        SafetyMap::new(hf, &maps.dir, Variant::Directional).unwrap(),
        SafetyMap::new(hf, &maps.iso, Variant::Isotropic).unwrap(),
    ];
    let cm = [
        CcMap::new(hf, &maps.cc, 64).unwrap(),
        CcMap::new(hf, &maps.ccn, 64).unwrap(),
    ];
    let rm = [
        RadiusMap::new(hf, &maps.rad).unwrap(),
        RadiusMap::new(hf, &maps.rad1).unwrap(),
    ];
    let surfs = [MarchSurface::Triangles, MarchSurface::ViewLinear];
    let mut hs = [H(1), H(2), H(3)];
    for q in rays {
        for s in surfs {
            for m in &sm {
                hs[0].trace(&safety::trace_on(m, hf, s, q));
            }
            for m in &cm {
                hs[1].trace(&cc::trace_on(m, hf, s, q));
            }
            for (m, zero) in [
                (&rm[0], Zero::Walk),
                (&rm[0], Zero::Clamp),
                (&rm[1], Zero::Walk),
            ] {
                let o = radius::Options { zero, surface: s };
                hs[2].trace(&radius::trace(m, hf, q, &o));
            }
        }
    }
    let p = core::any::type_name::<R>();
    for (k, h) in ["safety", "cc", "radius"].iter().zip(&hs) {
        println!("{name} {p} {k}: {:016x}", h.0);
        total.w(h.0);
    }
}

struct Maps {
    dir: Vec<u8>,
    iso: Vec<u8>,
    cc: Vec<u8>,
    ccn: Vec<u8>,
    rad: Vec<u8>,
    rad1: Vec<u8>,
}

fn bake(hf: &HeightField) -> Maps {
    let (w, h) = (hf.width(), hf.height());
    let mut scratch = vec![0f32; safety::scratch_len(w, h)];
    let sbake = |variant, scratch: &mut [f32]| {
        let mut out = vec![0u8; safety::map_len(w, h, variant)];
        let opts = safety::Options {
            variant,
            ..Default::default()
        };
        safety::bake(hf, scratch, opts, &mut out).unwrap();
        out
    };
    let dir = sbake(Variant::Directional, &mut scratch);
    let iso = sbake(Variant::Isotropic, &mut scratch);
    let cbake = |slope, scratch: &mut [f32]| {
        let opts = CcOptions { slope, cap: 64 };
        let mut nb = vec![0f32; cc::nbuffer_len(w, h, opts.cap)];
        let mut out = vec![0u8; cc::map_len(w, h)];
        cc::bake(hf, scratch, &mut nb, opts, &mut out).unwrap();
        out
    };
    let cc = cbake(Slope::Exact, &mut scratch);
    let ccn = cbake(Slope::NBuffer, &mut scratch);
    let rbake = |tolerance, scratch: &mut [f32]| {
        let mut out = vec![0u8; radius::map_len(w, h)];
        let opts = radius::BakeOptions {
            tolerance,
            ..Default::default()
        };
        radius::bake(hf, scratch, opts, &mut out).unwrap();
        out
    };
    let rad = rbake(0.0, &mut scratch);
    let rad1 = rbake(1.0, &mut scratch);
    Maps {
        dir,
        iso,
        cc,
        ccn,
        rad,
        rad1,
    }
}

fn main() {
    let mut fields: Vec<(String, Field)> = Vec::new();
    let (raw, w, h) = load_png("dem_etopo5_himalaya_1024.png").expect("himalaya map");
    let (v, w, h) = downsample(&raw, w, h, 4);
    let f = Field::from_fn(w, h, w as usize, |i, j| v[(j * w + i) as usize]);
    fields.push(("himalaya256".into(), f));
    let mut rng = Rng::new(5);
    fields.push(("walls".into(), tc::random_walls_field(&mut rng)));
    fields.push(("needles".into(), tc::needles_field(9)));
    fields.push(("plateau".into(), tc::plateau_field()));
    fields.push((
        "fractal".into(),
        tc::fractal_field(&mut rng, 70, 53, 75, 20.0),
    ));
    fields.push(("small".into(), tc::small_field(&mut rng)));
    let mut total = H(0);
    for (i, (name, field)) in fields.iter().enumerate() {
        let hf = field.hf();
        let maps = bake(&hf);
        let rays = rays_of(field, &hf, i as u64 + 11, 30_000);
        let r64: Vec<_> = rays.iter().map(|r| r.q64()).collect();
        let r32: Vec<_> = rays.iter().map(|r| r.q32()).collect();
        run(name, &hf, &maps, &r32, &mut total);
        run(name, &hf, &maps, &r64, &mut total);
    }
    println!("TOTAL {:016x}", total.0);
}
