//! The relaxed cone bake (pruned search, early-stopped marches, seeded by the left
//! neighbour's destination) equals the book's Θ(N⁴) loop (`relaxed::bake_brute`) bit
//! for bit: on random, needle, checkerboard, wall and fractal fields, on 32² – 48²
//! crops of real maps of `../shared/data` (skipped when missing), in bands of rows;
//! and `pair_ratio_below` keeps the contract the exactness rests on.
#![cfg(feature = "relaxed")]

mod common;

use common::{checkerboard_field, needles_field, random_walls_field, small_fields, Field, Rng};
use hfcast::{cone, relaxed};

/// Bakes `f` fast (whole, and in bands of 5 rows) and by brute force; asserts equality.
fn assert_equal(name: &str, f: &Field) {
    let hf = f.hf();
    let n = relaxed::map_len(f.w, f.h);
    let mut scratch = vec![0.0; relaxed::scratch_len(f.w, f.h)];
    let (mut fast, mut bands, mut brute) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    cone::bake::<relaxed::Relaxed>(&hf, &mut scratch, &mut fast).unwrap();
    for (k, part) in bands.chunks_mut(5 * f.w as usize).enumerate() {
        let r0 = 5 * k as u32;
        cone::bake_rows::<relaxed::Relaxed>(&hf, &scratch, r0..(r0 + 5).min(f.h), part).unwrap();
    }
    relaxed::bake_brute(&hf, &mut brute).unwrap();
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&fast), bits(&brute), "{name}");
    assert_eq!(bits(&bands), bits(&brute), "{name} (bands)");
}

/// A centred `side × side` crop of the 16-bit PNG `file` of the data folder, heights
/// `v / 65535 × 0.1 × max(W, H)`; `None` when the file is missing.
fn crop(file: &str, side: u32) -> Option<Field> {
    let dir = std::env::var_os("HFCAST_DATA").map_or_else(
        || std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
        std::path::PathBuf::from,
    );
    let file = std::fs::File::open(dir.join(file)).ok()?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .ok()?;
    let mut buf = vec![0u8; reader.output_buffer_size()?];
    let frame = reader.next_frame(&mut buf).ok()?;
    assert_eq!(frame.bit_depth, png::BitDepth::Sixteen);
    let (w, h) = (frame.width, frame.height);
    let depth = 0.1 * w.max(h) as f32;
    let (x0, y0) = ((w - side) / 2, (h - side) / 2);
    Some(Field::from_fn(side, side, side as usize, |i, j| {
        let k = 2 * ((y0 + j) * w + x0 + i) as usize;
        u16::from_be_bytes([buf[k], buf[k + 1]]) as f32 / 65535.0 * depth
    }))
}

#[test]
fn equals_brute_on_synthetic_fields() {
    let mut rng = Rng::new(0x5eed);
    let mut fields: Vec<(String, Field)> = vec![
        ("needles 45x38".into(), needles_field(3)),
        ("checkerboard 24x20".into(), checkerboard_field(0.0, 1.0)),
        ("walls 40x40".into(), random_walls_field(&mut rng)),
        (
            "fractal 37x29".into(),
            common::fractal_field(&mut rng, 37, 29, 40, 6.0),
        ),
    ];
    let mut r = Rng::new(7);
    fields.push((
        "random 32x32".into(),
        Field::from_fn(32, 32, 32, |_, _| r.range(0.0, 8.0) as f32),
    ));
    fields.push((
        "integer steps 30x26".into(),
        Field::from_fn(30, 26, 33, |_, _| r.int(0, 4) as f32),
    ));
    fields.extend(small_fields(&mut rng, 20));
    for (name, f) in &fields {
        assert_equal(name, f);
    }
}

#[test]
fn equals_brute_on_real_crops() {
    for (file, side) in [
        ("dem_etopo5_himalaya_1024.png", 48),
        ("game_etr_i_like_spike_2_128x640.png", 40),
        ("relief_godot_stones_1024x666.png", 32),
    ] {
        match crop(file, side) {
            Some(f) => assert_equal(file, &f),
            None => eprintln!("{file}: missing, skipped"),
        }
    }
}

/// `pair_ratio_below(best)` is `pair_ratio` whenever that is below `best`, and at
/// least `best` otherwise, for bounds near the pair's ratio, at its own steps' ratios
/// and far from it.
#[test]
fn pair_ratio_below_keeps_its_contract() {
    let mut rng = Rng::new(11);
    let f = common::fractal_field(&mut rng, 24, 21, 24, 5.0);
    let hf = f.hf();
    let mut checked = 0;
    for _ in 0..20000 {
        let s = [rng.below(24) as u32, rng.below(21) as u32];
        let d = [rng.below(24) as u32, rng.below(21) as u32];
        let exact = relaxed::pair_ratio(&hf, s, d);
        let near = if exact.is_finite() {
            exact
        } else {
            rng.range(0.0, 10.0)
        };
        for best in [
            near,
            f64::from_bits(near.to_bits() + 1),
            f64::from_bits(near.to_bits().saturating_sub(1)),
            near * rng.range(0.5, 2.0),
            rng.range(0.0, 50.0),
            f64::INFINITY,
        ] {
            let got = relaxed::pair_ratio_below(&hf, s, d, best);
            if exact < best {
                assert_eq!(got.to_bits(), exact.to_bits(), "{s:?} {d:?} {best}");
            } else {
                assert!(got >= best, "{s:?} {d:?} {best}: {got} < {best}");
            }
            checked += 1;
        }
    }
    assert!(checked > 0);
}
