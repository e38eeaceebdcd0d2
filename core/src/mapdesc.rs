//! Map descriptors: what a baked map belongs to, stored in 64 bytes beside its texels.
//!
//! A descriptor names the map ([`Desc`]: which map, the field's size, the bake's cap,
//! ray classes and ray set, and the [`fingerprint`] of the heights it was baked from)
//! and the number of texel bytes before it. It is a function of the bake's inputs
//! alone, so a map refreshed after an update equals a fresh bake byte for byte, and a
//! map read back from a KTX2 file equals the one written. The C API writes one after the texels of every map
//! it bakes and checks it before every trace, so that a map of another field, a stale
//! map after an update, or a wrong cap or class set is an error instead of a wrong
//! answer; the KTX2 container carries the fingerprint as `hfcast.fingerprint`.
//!
//! **Layout** (little-endian, [`LEN`] bytes): `0` magic `HFMD`; `4` u32 layout
//! version ([`VERSION`]); `8` u32 map (`MapKind` value); `12`, `16` u32 width,
//! height; `20` u32 cap; `24` u32 ray-class bits; `28` f32 tolerance (the radius
//! bake's ray set); `32` u64 fingerprint; `40` u32 ray-set flags (bit 0: exterior rays only; bit 1: over occluders, their
//! 24-bit fingerprint in bits 8–31); `44` f32
//! largest view angle of the ray set (0: any, 180°); `48` u64 texel bytes;
//! `56` u32 flags ([`FINGERPRINT_KNOWN`]); `60` u32 FNV-1a hash of bytes 0–59.

use crate::ktx2::{Desc, MapKind};
use crate::scene::RayClasses;

/// Bytes of an encoded descriptor.
pub const LEN: usize = 64;

/// The layout version [`MapDescriptor::encode`] writes and [`MapDescriptor::decode`]
/// accepts.
pub const VERSION: u32 = 1;

/// Flag bit: the fingerprint names the heights the map was baked from (a descriptor
/// restored from a KTX2 file without `hfcast.fingerprint` lacks it and matches no
/// field).
pub const FINGERPRINT_KNOWN: u32 = 1;

/// The magic bytes that open a descriptor.
const MAGIC: [u8; 4] = *b"HFMD";

/// What a baked map belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapDescriptor {
    /// The map and its bake: kind, field size, cap, ray classes, ray set and the
    /// [`fingerprint`] of the heights baked from (normalized: the fields its map
    /// ignores at their defaults, [`Desc::normalized`]).
    pub desc: Desc,
    /// Bytes of the map's texels, which the descriptor follows.
    pub texel_bytes: u64,
}

/// Why bytes are not a descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DescriptorError {
    /// No magic: the bytes are texels, or the map was baked without a descriptor.
    Missing,
    /// The magic is there but the layout version is another.
    Version(u32),
    /// The hash disagrees, or a field is out of range: the bytes were overwritten.
    Corrupt,
}

impl MapDescriptor {
    /// The descriptor as its [`LEN`] bytes.
    pub fn encode(&self) -> [u8; LEN] {
        let d = self.desc.normalized();
        let mut b = [0u8; LEN];
        b[0..4].copy_from_slice(&MAGIC);
        let words = [
            VERSION,
            d.map as u32,
            d.width,
            d.height,
            d.cap.into(),
            d.classes.0.into(),
            d.tolerance.to_bits(),
        ];
        for (k, w) in words.iter().enumerate() {
            b[4 + 4 * k..8 + 4 * k].copy_from_slice(&w.to_le_bytes());
        }
        let angle = if d.rays.max_view_angle_deg < 180.0 {
            u64::from(d.rays.max_view_angle_deg.to_bits())
        } else {
            0
        };
        let occluded = u32::from(d.rays.occluders != 0) << 1 | d.rays.occluders << 8;
        let rays = u64::from(u32::from(d.rays.exterior) | occluded) | angle << 32;
        let longs = [d.fingerprint.unwrap_or(0), rays, self.texel_bytes];
        for (k, v) in longs.iter().enumerate() {
            b[32 + 8 * k..40 + 8 * k].copy_from_slice(&v.to_le_bytes());
        }
        let flags = if d.fingerprint.is_some() {
            FINGERPRINT_KNOWN
        } else {
            0
        };
        b[56..60].copy_from_slice(&flags.to_le_bytes());
        let check = fnv1a(&b[..60]);
        b[60..64].copy_from_slice(&check.to_le_bytes());
        b
    }

    /// Reads a descriptor back from its bytes.
    pub fn decode(b: &[u8; LEN]) -> Result<MapDescriptor, DescriptorError> {
        if b[0..4] != MAGIC {
            return Err(DescriptorError::Missing);
        }
        let word = |at: usize| u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
        let long = |at: usize| u64::from(word(at)) | u64::from(word(at + 4)) << 32;
        if word(4) != VERSION {
            return Err(DescriptorError::Version(word(4)));
        }
        if word(60) != fnv1a(&b[..60])
            || word(56) & !FINGERPRINT_KNOWN != 0
            || word(40) & 0xfc != 0
            || (word(40) & 2 != 0) != (word(40) >> 8 != 0)
        {
            return Err(DescriptorError::Corrupt);
        }
        let map = MapKind::from_u32(word(8)).ok_or(DescriptorError::Corrupt)?;
        let cap = u8::try_from(word(20)).map_err(|_| DescriptorError::Corrupt)?;
        let classes = u8::try_from(word(24)).map_err(|_| DescriptorError::Corrupt)?;
        let mut desc = Desc::new(map, word(12), word(16));
        desc.cap = cap;
        desc.classes = RayClasses(classes);
        desc.tolerance = f32::from_bits(word(28));
        desc.rays = crate::rayset::Rays {
            exterior: word(40) & 1 == 1,
            occluders: word(40) >> 8,
            max_view_angle_deg: match word(44) {
                0 => 180.0,
                bits => f32::from_bits(bits),
            },
        }
        .validate()
        .map_err(|_| DescriptorError::Corrupt)?;
        desc.fingerprint = (word(56) & FINGERPRINT_KNOWN != 0).then(|| long(32));
        Ok(MapDescriptor {
            desc,
            texel_bytes: long(48),
        })
    }
}

/// 32-bit FNV-1a of `bytes`.
fn fnv1a(bytes: &[u8]) -> u32 {
    bytes.iter().fold(0x811c_9dc5u32, |h, &b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    })
}

/// The fingerprint term of sample `index` (row-major, stride W) holding `height`: a
/// 64-bit mix of both. [`fingerprint`] is the wrapping sum of the terms, so replacing
/// a sample changes the sum by `term(new) − term(old)`: an update is O(samples changed).
pub fn sample_term(index: usize, height: f32) -> u64 {
    let x = (index as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ u64::from(height.to_bits()).wrapping_mul(0xD6E8_FEB8_6659_FD93);
    // The splitmix64 finalizer.
    let x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The fingerprint of a field's samples (row-major, stride W, as
/// `HeightField::samples`): the wrapping sum of [`sample_term`] over them. Equal
/// heights give equal fingerprints; any changed sample changes it with probability
/// 1 − 2⁻⁶⁴ (it is a checksum against mistakes, not a cryptographic hash).
pub fn fingerprint(samples: &[f32]) -> u64 {
    samples
        .iter()
        .enumerate()
        .fold(0u64, |s, (i, &h)| s.wrapping_add(sample_term(i, h)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> MapDescriptor {
        let mut desc = Desc::new(MapKind::Cc, 65, 33);
        desc.cap = 17;
        desc.classes = RayClasses(0b0101);
        desc.fingerprint = Some(0x0123_4567_89ab_cdef);
        MapDescriptor {
            desc,
            texel_bytes: 65 * 33 * 2 * 2,
        }
    }

    #[test]
    fn round_trips_and_detects_damage() {
        let d = sample();
        let b = d.encode();
        assert_eq!(MapDescriptor::decode(&b), Ok(d));
        let mut unknown = d;
        unknown.desc.fingerprint = None;
        assert_eq!(MapDescriptor::decode(&unknown.encode()), Ok(unknown));
        for rays in [
            "exterior",
            "angle:45",
            "exterior,angle:120.5",
            "exterior,occluders:a1b2c3",
        ] {
            let mut narrowed = d;
            narrowed.desc.rays = rays.parse().unwrap();
            assert_eq!(
                MapDescriptor::decode(&narrowed.encode()),
                Ok(narrowed),
                "{rays}"
            );
        }
        // A ray-set word of a later version, and a NaN angle: refused.
        let mut later = b;
        later[40] = 2;
        let h = fnv1a(&later[..60]);
        later[60..64].copy_from_slice(&h.to_le_bytes());
        assert_eq!(MapDescriptor::decode(&later), Err(DescriptorError::Corrupt));
        let mut nan = b;
        nan[44..48].copy_from_slice(&f32::NAN.to_bits().to_le_bytes());
        let h = fnv1a(&nan[..60]);
        nan[60..64].copy_from_slice(&h.to_le_bytes());
        assert_eq!(MapDescriptor::decode(&nan), Err(DescriptorError::Corrupt));
        for at in 4..LEN {
            let mut bad = b;
            bad[at] ^= 0x10;
            assert!(MapDescriptor::decode(&bad).is_err(), "byte {at}");
        }
        assert_eq!(
            MapDescriptor::decode(&[0; LEN]),
            Err(DescriptorError::Missing)
        );
    }

    #[test]
    fn fingerprint_updates_by_difference() {
        let mut s = [0.0f32, 1.0, 2.0, 3.0, 4.0, 5.0];
        let before = fingerprint(&s);
        let (i, new) = (4, -7.5f32);
        let updated = before
            .wrapping_sub(sample_term(i, s[i]))
            .wrapping_add(sample_term(i, new));
        s[i] = new;
        assert_eq!(fingerprint(&s), updated);
        assert_ne!(updated, before);
        // Swapping two samples changes it (the index is mixed in).
        let mut t = [0.0f32, 1.0, 2.0, 3.0, 4.0, 5.0];
        t.swap(1, 2);
        assert_ne!(
            fingerprint(&t),
            fingerprint(&[0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
        );
    }
}
