//! The fast cone and QDM bakes (hinted searches, early exits, three-direction
//! `dist_lb`) give the brute-force results bit for bit, whatever the hints.
#![cfg(all(feature = "cone", feature = "qdm"))]

mod common;

use common::{small_fields, Field, Rng};
use hfcast::maxmip::MaxMip;
use hfcast::{cone, qdm};

/// `max_k (cos θ_k gx + sin θ_k gy)` over all nine directions: the definition.
fn dist_lb_all(gx: f64, gy: f64) -> f64 {
    if gx == 0.0 || gy == 0.0 {
        return gx + gy;
    }
    cone::DIRS
        .iter()
        .map(|&(c, s)| c * gx + s * gy)
        .fold(0.0, f64::max)
}

#[test]
fn dist_lb_takes_the_maximum_of_all_directions() {
    for gx in 0..400 {
        for gy in 0..400 {
            let (x, y) = (gx as f64, gy as f64);
            assert_eq!(cone::dist_lb(x, y).to_bits(), dist_lb_all(x, y).to_bits());
        }
    }
    let mut rng = Rng::new(5);
    for _ in 0..1_000_000 {
        let s = 10f64.powf(rng.range(-3.0, 4.0));
        let (x, y) = (rng.range(0.0, s), rng.range(0.0, s));
        assert_eq!(cone::dist_lb(x, y).to_bits(), dist_lb_all(x, y).to_bits());
    }
    // Near the midpoints between directions, where two are nearly tied.
    for k in 0..8 {
        let t = (k as f64 + 0.5) * std::f64::consts::PI / 16.0;
        for n in -50..=50 {
            let a = t + n as f64 * 1e-15;
            let (x, y) = (a.cos() * 300.0, a.sin() * 300.0);
            assert_eq!(cone::dist_lb(x, y).to_bits(), dist_lb_all(x, y).to_bits());
        }
    }
}

/// Ties (integer heights), plateaus and rough random fields of middling size.
fn fields() -> Vec<(String, Field)> {
    let mut rng = Rng::new(0x5eed);
    let mut v = small_fields(&mut rng, 12);
    for (w, h, amp) in [(29, 23, 3.0), (37, 19, 40.0)] {
        let f = Field::from_fn(w, h, w as usize + 1, |_, _| {
            if rng.chance(0.5) {
                rng.int(0, 4) as f32
            } else {
                rng.range(0.0, amp) as f32
            }
        });
        v.push((format!("rough {w}x{h}"), f));
    }
    v
}

#[test]
fn hinted_bakes_equal_brute_force() {
    let mut rng = Rng::new(11);
    for (name, f) in fields() {
        let hf = f.hf();
        let (w, h) = (hf.width(), hf.height());
        let mut scratch = vec![0.0; cone::scratch_len(w, h)];
        let mut fast = vec![0.0; cone::map_len(w, h)];
        let mut brute = fast.clone();
        cone::bake::<cone::Cone>(&hf, &mut scratch, &mut fast).unwrap();
        cone::bake_brute(&hf, &mut brute).unwrap();
        assert_eq!(bits(&fast), bits(&brute), "{name}: cone");
        let mut qfast = vec![0.0; qdm::map_len(w, h)];
        let mut qbrute = qfast.clone();
        cone::bake::<qdm::Qdm>(&hf, &mut scratch, &mut qfast).unwrap();
        qdm::bake_brute(&hf, &mut qbrute).unwrap();
        assert_eq!(bits(&qfast), bits(&qbrute), "{name}: qdm");
        // Any hint gives the same texel.
        let mip = MaxMip::new(&hf, &scratch).unwrap();
        for j in 0..h - 1 {
            for i in 0..w - 1 {
                let c = [i, j];
                let mut hint = || {
                    [
                        rng.below(w as usize - 1) as u32,
                        rng.below(h as usize - 1) as u32,
                    ]
                };
                let k = (j * (w - 1) + i) as usize;
                let (r, _) = cone::ratio_search(&hf, &mip, c, hint());
                assert_eq!(
                    cone::f32_down(r).to_bits(),
                    brute[2 * k + 1].to_bits(),
                    "{name} {c:?}"
                );
                let (t, _) = qdm::texel_search(&hf, &mip, c, [hint(), hint()]);
                assert_eq!(
                    bits(&t),
                    bits(&qbrute[4 * k..4 * k + 4]),
                    "{name} {c:?}: qdm"
                );
            }
        }
    }
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}
