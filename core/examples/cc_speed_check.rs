//! Checksums and timings of the safety-distance, cylinder–cone and radius bakes (for
//! keeping bake speed-ups byte-identical).
//!
//! `cargo run --release -p hfcast --example cc_speed_check -- check [big]` prints one
//! line per field and bake: an FNV-1a hash of the output map, and the bake's wall time
//! (one thread). Fields: the synthetic fields of the tests, the Himalaya map at 256²
//! and 512² (and 1024² with `big`), and two more DEMs of the data folder.
//!
//! `... -- bench KIND SIZE` bakes one map once, one thread (for `valgrind
//! --tool=callgrind`): KIND is `sd`, `iso`, `ccx`, `ccn` or `radE` (tolerance `E`),
//! SIZE the Himalaya side (256, 512, 1024).

#[cfg(feature = "safety")]
mod common;
#[cfg(feature = "safety")]
#[allow(dead_code, clippy::all)]
#[path = "../tests/common/mod.rs"]
mod tcommon;

fn main() {
    #[cfg(feature = "safety")]
    check::main();
}

#[cfg(feature = "safety")]
mod check {
    use crate::common::{downsample, load_png};
    use crate::tcommon::{fractal_field, march_fields, rows_field, Field, Rng};
    use hfcast::radius::{self, BakeOptions};
    use hfcast::safety::cc::{self, CcOptions, Slope};
    use hfcast::safety::{self, Options, Variant};
    use hfcast::scene::RayClasses;
    use hfcast::{HeightField, RayClass};
    use std::time::Instant;

    /// FNV-1a, 64 bits.
    fn fnv(data: &[u8]) -> u64 {
        data.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
    }

    /// A bake of one kind.
    #[derive(Clone, Copy, Debug)]
    enum Bake {
        Sd(Options, RayClasses),
        Cc(CcOptions, RayClasses),
        Radius(BakeOptions),
    }

    fn run(hf: &HeightField, b: Bake) -> Vec<u8> {
        let (w, h) = (hf.width(), hf.height());
        let mut scratch = vec![0f32; safety::scratch_len(w, h)];
        safety::prepare(hf, &mut scratch).unwrap();
        match b {
            Bake::Sd(o, cl) => {
                let mut out = vec![0xAAu8; safety::map_len_classes(w, h, o.variant, cl)];
                let rays = safety::AllRays;
                safety::bake_rows_classes(hf, &scratch, &rays, cl, 0..h, o, &mut out).unwrap();
                out
            }
            Bake::Cc(o, cl) => {
                let mut nb = vec![0f32; cc::nbuffer_len(w, h, o.cap)];
                cc::prepare_nbuffer(hf, o.cap, &mut nb).unwrap();
                let mut out = vec![0xAAu8; cc::map_len_classes(w, h, cl)];
                cc::bake_rows_classes(hf, &scratch, &nb, cl, 0..h, o, &mut out).unwrap();
                out
            }
            Bake::Radius(o) => {
                let mut out = vec![0xAAu8; radius::map_len(w, h)];
                radius::bake_rows(hf, &scratch, 0..h, o, &mut out).unwrap();
                out
            }
        }
    }

    fn sd(variant: Variant, positive: bool, cap: u8) -> Bake {
        Bake::Sd(
            Options {
                variant,
                positive,
                cap,
            },
            RayClasses::ALL,
        )
    }

    fn ccb(slope: Slope, cap: u8) -> Bake {
        Bake::Cc(CcOptions { slope, cap }, RayClasses::ALL)
    }

    fn rad(tolerance: f32, cap: u8) -> Bake {
        Bake::Radius(BakeOptions { tolerance, cap })
    }

    /// Every bake on a small field.
    fn small_bakes() -> Vec<Bake> {
        let mut v = vec![
            sd(Variant::Directional, false, 255),
            sd(Variant::Isotropic, false, 255),
            sd(Variant::Directional, true, 20),
            sd(Variant::Isotropic, false, 7),
            Bake::Sd(Options::default(), RayClasses::NONE.with(RayClass::YPos)),
            Bake::Cc(
                CcOptions::default(),
                RayClasses::NONE.with(RayClass::XNeg).with(RayClass::YPos),
            ),
        ];
        for slope in [Slope::Exact, Slope::NBuffer] {
            for cap in [64, 24, 20, 8, 1, 255] {
                v.push(ccb(slope, cap));
            }
        }
        for e in [0.0, 0.25, 0.5, 1.0, 2.0, 5.0] {
            v.push(rad(e, 255));
        }
        v.push(rad(0.5, 10));
        v
    }

    /// The bakes on a large map.
    fn big_bakes() -> Vec<Bake> {
        let mut v = vec![
            sd(Variant::Directional, false, 255),
            sd(Variant::Isotropic, false, 255),
            ccb(Slope::Exact, 64),
            ccb(Slope::NBuffer, 64),
        ];
        for e in [0.0, 0.25, 0.5, 1.0, 2.0] {
            v.push(rad(e, 255));
        }
        v
    }

    fn himalaya(step: u32) -> Field {
        let (raw, w, h) = load_png("dem_etopo5_himalaya_1024.png").expect("himalaya map");
        let (v, w, h) = downsample(&raw, w, h, step);
        Field {
            samples: v,
            w,
            h,
            stride: w as usize,
        }
    }

    fn dem(name: &str, step: u32) -> Option<Field> {
        let (raw, w, h) = load_png(name)?;
        let (v, w, h) = downsample(&raw, w, h, step);
        Some(Field {
            samples: v,
            w,
            h,
            stride: w as usize,
        })
    }

    /// `check [big]` or `bench KIND SIZE` (see the file's doc).
    pub fn main() {
        let args: Vec<String> = std::env::args().skip(1).collect();
        if args.first().map(String::as_str) == Some("bench") {
            let size: u32 = args[2].parse().unwrap();
            let f = himalaya(1024 / size);
            let kind = args[1].as_str();
            let b = match kind {
                "sd" => sd(Variant::Directional, false, 255),
                "iso" => sd(Variant::Isotropic, false, 255),
                "ccx" => ccb(Slope::Exact, 64),
                "ccn" => ccb(Slope::NBuffer, 64),
                k => rad(k.strip_prefix("rad").expect("kind").parse().unwrap(), 255),
            };
            let t = Instant::now();
            let out = run(&f.hf(), b);
            println!(
                "{kind} {size}: {:016x} {:.0} ms",
                fnv(&out),
                t.elapsed().as_secs_f64() * 1e3
            );
            return;
        }
        let big = args.iter().any(|a| a == "big");
        let mut fields: Vec<(String, Field, bool)> = Vec::new();
        let sf = march_fields(0x5afe, 7, ("checkerboard 24x20", 0.0, 1.0), Vec::new(), 12);
        let dome = Field::from_fn(50, 44, 50, |i, j| {
            let (x, y) = (f64::from(i) - 24.5, f64::from(j) - 21.5);
            (12.0 - (x * x + y * y) / 60.0) as f32
        });
        let checker = ("checkerboard max/min 24x20", 5.0, -1.0);
        let rf = march_fields(0x4ad1, 11, checker, vec![("dome 50x44".into(), dome)], 8);
        for (n, f) in sf.into_iter().chain(rf) {
            fields.push((n, f, false));
        }
        fields.push(("rows 3".into(), rows_field(3), false));
        fields.push(("rows 5".into(), rows_field(5), false));
        let plan = fractal_field(&mut Rng::new(8), 41, 29, 41, 6.0);
        fields.push(("plan".into(), plan, false));
        for (name, step) in [
            ("dem_jacksboro_fault_403x344.png", 2),
            ("dem_srtm30_bigtujunga_1197x643.png", 4),
        ] {
            if let Some(f) = dem(name, step) {
                fields.push((name.into(), f, true));
            }
        }
        fields.push(("himalaya 256".into(), himalaya(4), true));
        fields.push(("himalaya 512".into(), himalaya(2), true));
        if big {
            fields.push(("himalaya 1024".into(), himalaya(1), true));
        }
        for (name, f, large) in &fields {
            let hf = f.hf();
            for cap in [1u8, 24, 64, 255] {
                let mut nb = vec![0f32; cc::nbuffer_len(f.w, f.h, cap)];
                cc::prepare_nbuffer(&hf, cap, &mut nb).unwrap();
                let bytes: Vec<u8> = nb.iter().flat_map(|v| v.to_le_bytes()).collect();
                println!("{name} | n-buffers cap {cap} | {:016x} | -", fnv(&bytes));
            }
            let bakes = if *large { big_bakes() } else { small_bakes() };
            for b in bakes {
                let t = Instant::now();
                let out = run(&hf, b);
                let ms = t.elapsed().as_secs_f64() * 1e3;
                println!("{name} | {b:?} | {:016x} | {ms:.0} ms", fnv(&out));
            }
        }
    }
}
