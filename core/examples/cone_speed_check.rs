//! Checksums and bake times of the cone map and QDM bakes (issue 5).
//!
//! `cargo run --release -p hfcast --example cone_speed_check -- check`: one checksum
//! line per field (synthetic fractal 256², 512², Himalaya 256², 512² downsamples, the
//! test fields of `tests/cones.rs`), to compare before and after a change.
//! `... -- time 1024`: two-thread bake times (cone, QDM) at that size, synthetic and
//! Himalaya. `... -- one cone|qdm synth|himalaya 256`: one single-threaded bake (for
//! `valgrind --tool=callgrind`). `$HFCAST_DATA` or `../shared/data` holds the map.
#![cfg_attr(not(all(feature = "cone", feature = "qdm")), allow(unused))]

#[path = "common/mod.rs"]
mod common;
#[path = "../tests/common/mod.rs"]
mod tcommon;

#[cfg(all(feature = "cone", feature = "qdm"))]
use hfcast::{cone, qdm, HeightField};
use std::time::Instant;

#[cfg(all(feature = "cone", feature = "qdm"))]
/// The Himalaya map downsampled to `n` per side (depth 0.1 × n).
fn himalaya(n: u32) -> Vec<f32> {
    let (raw, w, h) = common::load_png("dem_etopo5_himalaya_1024.png").expect("himalaya map");
    common::downsample(&raw, w, h, w / n).0
}

#[cfg(all(feature = "cone", feature = "qdm"))]
/// FNV-1a over the bits of `v`.
fn checksum(v: &[f32]) -> u64 {
    v.iter().fold(0xcbf2_9ce4_8422_2325, |h, x| {
        (h ^ x.to_bits() as u64).wrapping_mul(0x100_0000_01b3)
    })
}

#[cfg(all(feature = "cone", feature = "qdm"))]
/// Bakes `which` ("cone" or "qdm") of `hf` on `threads` threads; returns the map.
fn bake(hf: &HeightField, which: &str, threads: u32) -> Vec<f32> {
    let (w, h) = (hf.width(), hf.height());
    let mut scratch = vec![0.0; cone::scratch_len(w, h)];
    cone::prepare(hf, &mut scratch).unwrap();
    let (len, ch) = if which == "cone" {
        (cone::map_len(w, h), cone::CHANNELS)
    } else {
        (qdm::map_len(w, h), qdm::CHANNELS)
    };
    let mut out = vec![0.0; len];
    let row_len = ch * (w - 1) as usize;
    common::in_bands(&mut out, row_len, h - 1, threads, |rows, part| {
        if which == "cone" {
            cone::bake_rows::<cone::Cone>(hf, &scratch, rows, part).unwrap()
        } else {
            cone::bake_rows::<qdm::Qdm>(hf, &scratch, rows, part).unwrap()
        }
    });
    out
}

#[cfg(all(feature = "cone", feature = "qdm"))]
/// The named fields of the checksum run.
fn fields() -> Vec<(String, tcommon::Field)> {
    let mut v = Vec::new();
    for n in [256, 512] {
        v.push((format!("synth {n}"), (n, common::fractal_field(n))));
        v.push((format!("himalaya {n}"), (n, himalaya(n))));
    }
    let mut v: Vec<(String, tcommon::Field)> = v
        .into_iter()
        .map(|(name, (n, s))| {
            (
                name,
                tcommon::Field::from_fn(n, n, n as usize, |i, j| s[(j * n + i) as usize]),
            )
        })
        .collect();
    let mut rng = tcommon::Rng::new(0xc0de);
    v.extend(tcommon::fractal_fields(&mut rng, "fractal 90x7 stride 95"));
    v.push(("needles 45x38".into(), tcommon::needles_field(7)));
    v.push((
        "checkerboard 24x20".into(),
        tcommon::checkerboard_field(0.0, 1.0),
    ));
    v.push(("plateau 33x29".into(), tcommon::plateau_field()));
    v.push(("2x2".into(), tcommon::tiny_field()));
    v.extend(tcommon::small_fields(&mut rng, 20));
    v
}

#[cfg(not(all(feature = "cone", feature = "qdm")))]
fn main() {}

#[cfg(all(feature = "cone", feature = "qdm"))]
fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("check") => {
            for (name, f) in fields() {
                let hf = f.hf();
                let c = checksum(&bake(&hf, "cone", 2));
                let q = checksum(&bake(&hf, "qdm", 2));
                println!("{name}: cone {c:016x} qdm {q:016x}");
            }
        }
        Some("time") => {
            let n: u32 = args[1].parse().unwrap();
            for (name, s) in [
                ("synth", common::fractal_field(n)),
                ("himalaya", himalaya(n)),
            ] {
                let hf = HeightField::new(&s, n, n, n as usize).unwrap();
                for which in ["cone", "qdm"] {
                    let t = Instant::now();
                    let m = bake(&hf, which, 2);
                    let dt = t.elapsed().as_secs_f64();
                    println!("{name} {n}² {which}: {dt:.2} s ({:016x})", checksum(&m));
                }
            }
        }
        Some("one") => {
            let n: u32 = args[3].parse().unwrap();
            let s = if args[2] == "synth" {
                common::fractal_field(n)
            } else {
                himalaya(n)
            };
            let hf = HeightField::new(&s, n, n, n as usize).unwrap();
            let m = bake(&hf, &args[1], 1);
            println!("{:016x}", checksum(&m));
        }
        _ => eprintln!("usage: cone_speed_check check | time N | one cone|qdm synth|himalaya N"),
    }
}
