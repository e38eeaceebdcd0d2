//! KTX 2 files of every baked map (`hfcast::ktx2`), on the bundled real map and on
//! synthetic fields: read back with the independent `ktx2` crate (header, format, DFD
//! against the crate's own for the format, sizes, level count, every level byte for
//! byte against the bake, metadata) and with the core's reader (the description and
//! the baked map back); bad files are errors, never panics; `hfcast bake` end to end.

use ::ktx2::{ColorModel, ColorPrimaries, Format, TransferFunction};
use hfcast::ktx2::{self, Data, DataMut, Desc, Ktx2Error, MapKind};
use hfcast::maxmip::{self, Layout};
use hfcast::safety::{self, cc, AllRays, Options, Variant};
use hfcast::scene::RayClasses;
use hfcast::{cone, qdm, radius, relaxed, HeightField};
use hfcast_tools::maps::{bundled_map, load_map};
use std::collections::HashMap;

/// A baked map: floats or bytes, as its bake wrote them.
enum Baked {
    U8(Vec<u8>),
    F32(Vec<f32>),
}

impl Baked {
    fn data(&self) -> Data<'_> {
        match self {
            Baked::U8(v) => Data::U8(v),
            Baked::F32(v) => Data::F32(v),
        }
    }

    /// The little-endian bytes of elements `range`.
    fn bytes(&self, range: std::ops::Range<usize>) -> Vec<u8> {
        match self {
            Baked::U8(v) => v[range].to_vec(),
            Baked::F32(v) => v[range].iter().flat_map(|x| x.to_le_bytes()).collect(),
        }
    }

    fn len(&self) -> usize {
        match self {
            Baked::U8(v) => v.len(),
            Baked::F32(v) => v.len(),
        }
    }
}

/// The whole-map bake of the cone family.
type WholeBake = fn(&HeightField, &mut [f32], &mut [f32]) -> Result<(), cone::BakeError>;

/// Bakes `desc`'s map of `hf` with the core's whole-map bakes (one thread).
fn bake(hf: &HeightField, desc: &Desc) -> Baked {
    let (w, h) = (hf.width(), hf.height());
    let cap = desc.cap;
    match desc.map {
        MapKind::Heights => Baked::F32(hf.samples().to_vec()),
        MapKind::MaxMip => {
            let mut p = vec![0.0; maxmip::pyramid_len(w, h)];
            maxmip::bake(hf, &mut p).unwrap();
            Baked::F32(p)
        }
        MapKind::Safety | MapKind::SafetyIsotropic => {
            let variant = if desc.map == MapKind::Safety {
                Variant::Directional
            } else {
                Variant::Isotropic
            };
            let opts = Options {
                variant,
                positive: false,
                cap,
            };
            let mut scratch = vec![0.0; safety::scratch_len(w, h)];
            safety::prepare(hf, &mut scratch).unwrap();
            let mut out = vec![0; safety::map_len_classes(w, h, variant, desc.classes)];
            let (rays, classes) = (&AllRays, desc.classes);
            safety::bake_rows_classes(hf, &scratch, rays, classes, 0..h, opts, &mut out).unwrap();
            Baked::U8(out)
        }
        MapKind::Cc => {
            let mut scratch = vec![0.0; safety::scratch_len(w, h)];
            safety::prepare(hf, &mut scratch).unwrap();
            let mut nb = vec![0.0; cc::nbuffer_len(w, h, cap)];
            cc::prepare_nbuffer(hf, cap, &mut nb).unwrap();
            let opts = cc::CcOptions {
                cap,
                ..Default::default()
            };
            let mut out = vec![0; cc::map_len_classes(w, h, desc.classes)];
            let classes = desc.classes;
            cc::bake_rows_classes(hf, &scratch, &nb, classes, 0..h, opts, &mut out).unwrap();
            Baked::U8(out)
        }
        MapKind::Radius => {
            let mut scratch = vec![0.0; radius::scratch_len(w, h)];
            let opts = radius::BakeOptions {
                tolerance: desc.tolerance,
                cap,
            };
            let mut out = vec![0; radius::map_len(w, h)];
            radius::bake(hf, &mut scratch, opts, &mut out).unwrap();
            Baked::U8(out)
        }
        MapKind::Cone | MapKind::Relaxed | MapKind::Qdm => {
            let mut scratch = vec![0.0; cone::scratch_len(w, h)];
            let (len, bake): (usize, WholeBake) = match desc.map {
                MapKind::Cone => (cone::map_len(w, h), cone::bake::<cone::Cone>),
                MapKind::Relaxed => (relaxed::map_len(w, h), cone::bake::<relaxed::Relaxed>),
                _ => (qdm::map_len(w, h), cone::bake::<qdm::Qdm>),
            };
            let mut out = vec![0.0; len];
            bake(hf, &mut scratch, &mut out).unwrap();
            Baked::F32(out)
        }
    }
}

/// The description of each map, with non-default settings where a map has them.
fn descs(w: u32, h: u32) -> Vec<Desc> {
    let x_pos_y_neg = RayClasses(0b1001);
    MapKind::ALL
        .into_iter()
        .map(|map| {
            let mut d = Desc::new(map, w, h);
            match map {
                MapKind::Safety | MapKind::SafetyIsotropic => {
                    (d.cap, d.classes) = (40, x_pos_y_neg)
                }
                MapKind::Cc => (d.cap, d.classes) = (32, x_pos_y_neg),
                MapKind::Radius => (d.cap, d.tolerance) = (200, 0.5),
                _ => {}
            }
            d
        })
        .collect()
}

/// The `ktx2` crate's format of a map.
fn crate_format(map: MapKind) -> Format {
    match map {
        MapKind::Heights | MapKind::MaxMip | MapKind::Relaxed => Format::R32_SFLOAT,
        MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Radius => Format::R8_UINT,
        MapKind::Cc => Format::R8G8_UINT,
        MapKind::Cone => Format::R32G32_SFLOAT,
        MapKind::Qdm => Format::R32G32B32A32_SFLOAT,
    }
}

/// The bytes each KTX level must hold, built here from the bake: the map itself, or
/// for the pyramid each level in the top-left corner of a power-of-two mip level,
/// `−∞` elsewhere.
fn expected_levels(hf: &HeightField, desc: &Desc, baked: &Baked) -> Vec<Vec<u8>> {
    if desc.map != MapKind::MaxMip {
        return vec![baked.bytes(0..baked.len())];
    }
    let layout = Layout::of(hf);
    let pw = (hf.width() - 1).next_power_of_two();
    let ph = (hf.height() - 1).next_power_of_two();
    (0..layout.levels())
        .map(|k| {
            let [w, h] = layout.dims(k);
            let (kw, kh) = ((pw >> k).max(1), (ph >> k).max(1));
            let mut level = Vec::new();
            for j in 0..kh {
                for i in 0..kw {
                    let v = if i < w && j < h {
                        let at = layout.offset(k) + (j * w + i) as usize;
                        baked.bytes(at..at + 1)
                    } else {
                        f32::NEG_INFINITY.to_le_bytes().to_vec()
                    };
                    level.extend(v);
                }
            }
            level
        })
        .collect()
}

/// Writes `desc`'s map of `hf` and checks the file with the `ktx2` crate and the
/// core's reader; returns the file.
fn check_map(hf: &HeightField, desc: &Desc) -> Vec<u8> {
    let baked = bake(hf, desc);
    let what = format!("{:?} {}x{}", desc.map, hf.width(), hf.height());
    assert_eq!(ktx2::map_len(desc), Ok(baked.len()), "{what}");
    let n = ktx2::len(desc).unwrap();
    let mut file = vec![0xAA; n + 3];
    assert_eq!(
        ktx2::write(desc, baked.data(), &mut file[..n - 1]),
        Err(Ktx2Error::OutputTooShort { needed: n })
    );
    assert!(file.iter().all(|&b| b == 0xAA), "{what}: written on error");
    assert_eq!(ktx2::write(desc, baked.data(), &mut file), Ok(n), "{what}");
    assert!(
        file[n..].iter().all(|&b| b == 0xAA),
        "{what}: past the file"
    );
    file.truncate(n);

    // The independent reader.
    let reader = ::ktx2::Reader::new(&file[..]).unwrap_or_else(|e| panic!("{what}: {e}"));
    let header = reader.header();
    let format = crate_format(desc.map);
    assert_eq!(header.format, Some(format), "{what}");
    assert_eq!(header.supercompression_scheme, None);
    assert_eq!(
        (header.pixel_depth, header.layer_count, header.face_count),
        (0, 0, 1)
    );
    let want = expected_levels(hf, desc, &baked);
    assert_eq!(header.level_count as usize, want.len(), "{what}");
    let (w, h) = (hf.width(), hf.height());
    let rows = desc.classes.count();
    let dims = match desc.map {
        MapKind::MaxMip => [(w - 1).next_power_of_two(), (h - 1).next_power_of_two()],
        MapKind::Cone | MapKind::Qdm => [w - 1, h - 1],
        MapKind::Safety | MapKind::Cc => [w, rows * h],
        _ => [w, h],
    };
    assert_eq!([header.pixel_width, header.pixel_height], dims, "{what}");
    let levels: Vec<_> = reader.levels().collect();
    for (k, (level, want)) in levels.iter().zip(&want).enumerate() {
        assert_eq!(level.data, &want[..], "{what}: level {k}");
        assert_eq!(level.uncompressed_byte_length, want.len() as u64);
    }
    // Level data smallest first: level 0 lies last.
    let start = |l: &::ktx2::Level| l.data.as_ptr() as usize;
    assert!(
        levels.windows(2).all(|p| start(&p[0]) > start(&p[1])),
        "{what}"
    );
    assert_eq!(
        start(&levels[0]) + levels[0].data.len(),
        file.as_ptr() as usize + n
    );

    // The DFD is the one the crate builds for the format, but for the colour space of
    // integer formats, which the KTX spec asks to leave unspecified.
    let (mut expected, type_size) = ::ktx2::dfd::Basic::from_format(format).unwrap();
    assert_eq!(header.type_size, type_size, "{what}");
    let basic = reader.basic_dfd().expect("a basic DFD block");
    assert_eq!(reader.dfd_blocks().len(), 1);
    if matches!(format, Format::R8_UINT | Format::R8G8_UINT) {
        assert_eq!(
            (basic.color_primaries, basic.transfer_function),
            (None, None)
        );
        expected.color_primaries = None;
        expected.transfer_function = None;
    } else {
        let space = (basic.color_primaries, basic.transfer_function);
        assert_eq!(
            space,
            (Some(ColorPrimaries::BT709), Some(TransferFunction::Linear))
        );
    }
    assert_eq!(basic, &expected, "{what}");
    assert_eq!(basic.color_model, Some(ColorModel::RGBSDA));

    // Metadata.
    let kv: Vec<(&str, &[u8])> = reader.key_value_data().collect();
    let keys: Vec<&str> = kv.iter().map(|(k, _)| *k).collect();
    let mut sorted = keys.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(keys, sorted, "{what}: keys sorted and unique");
    let kv: HashMap<&str, &str> = kv
        .into_iter()
        .map(|(k, v)| {
            (
                k,
                std::str::from_utf8(v.strip_suffix(&[0]).expect("NUL")).unwrap(),
            )
        })
        .collect();
    assert_eq!(
        reader.writer(),
        Some(&*format!("hfcast {}\0", env!("CARGO_PKG_VERSION")))
    );
    assert_eq!(kv["hfcast.method"], desc.map.method());
    assert_eq!(kv["hfcast.version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(kv["hfcast.field"], format!("{w}x{h}"));
    if let Some(f) = desc.fingerprint {
        assert_eq!(kv["hfcast.fingerprint"], format!("{f:016x}"));
    }
    if desc.map.has_rays() {
        assert_eq!(kv["hfcast.cap"], desc.cap.to_string());
        let classes = if desc.map == MapKind::Radius {
            "x+,x-,y+,y-"
        } else {
            "x+,y-"
        };
        assert_eq!(kv["hfcast.ray_classes"], classes);
        let set = if desc.map == MapKind::Radius {
            "lowered:0.5"
        } else {
            "all"
        };
        assert_eq!(kv["hfcast.ray_set"], set);
        assert_eq!(
            kv.len(),
            7 + usize::from(desc.map == MapKind::Safety || desc.map == MapKind::SafetyIsotropic)
                + usize::from(desc.fingerprint.is_some())
        );
    } else {
        let fingerprint = usize::from(desc.fingerprint.is_some());
        assert_eq!(kv.len(), 4 + fingerprint, "{what}: {kv:?}");
    }
    if let Some(variant) = kv.get("hfcast.variant") {
        let want = if desc.map == MapKind::Safety {
            "directional"
        } else {
            "isotropic"
        };
        assert_eq!(*variant, want);
    }

    // The core's reader.
    let view = ktx2::read(&file).unwrap();
    assert_eq!(view.desc(), Ok(desc.normalized()), "{what}");
    for (k, level) in levels.iter().enumerate() {
        assert_eq!(view.level(k as u32), Some(level.data));
    }
    assert_eq!(view.level(levels.len() as u32), None);
    let back = match &baked {
        Baked::U8(v) => {
            let mut out = vec![0; v.len()];
            view.read_map(DataMut::U8(&mut out)).unwrap();
            out == *v
        }
        Baked::F32(v) => {
            let mut out = vec![0.0f32; v.len()];
            view.read_map(DataMut::F32(&mut out)).unwrap();
            out.iter().zip(v).all(|(a, b)| a.to_bits() == b.to_bits())
        }
    };
    assert!(back, "{what}: the baked map back");
    file
}

/// A synthetic field: ridges, a wall and a flat patch.
fn synthetic(w: u32, h: u32) -> Vec<f32> {
    (0..w * h)
        .map(|k| {
            let (i, j) = ((k % w) as f32, (k / w) as f32);
            let wall = if (i - 7.0).abs() < 1.0 { 6.0 } else { 0.0 };
            (i * 0.7).sin() * 2.0 + (j * 0.4).cos() * 3.0 + wall + if j > 20.0 { 1.0 } else { 0.0 }
        })
        .collect()
}

#[test]
fn every_map_of_synthetic_fields() {
    // 37 x 29: a padded pyramid (36 x 28 cells in 64 x 32); 33 x 17: exact (32 x 16).
    for (w, h) in [(37, 29), (33, 17), (2, 2)] {
        let heights = synthetic(w, h);
        let hf = HeightField::new(&heights, w, h, w as usize).unwrap();
        for desc in descs(w, h) {
            check_map(&hf, &desc);
        }
    }
}

#[test]
fn every_map_of_the_bundled_map() {
    let map = load_map(bundled_map(), None).unwrap();
    let hf = map.field();
    assert_eq!((hf.width(), hf.height()), (403, 344));
    for desc in descs(hf.width(), hf.height()) {
        let file = check_map(&hf, &desc);
        if desc.map == MapKind::MaxMip {
            let r = ::ktx2::Reader::new(&file[..]).unwrap();
            assert_eq!((r.header().pixel_width, r.header().level_count), (512, 10));
        }
    }
}

/// A small valid file (the directional safety map of a 5 x 4 field) to break.
fn small_file() -> Vec<u8> {
    let heights = synthetic(5, 4);
    let hf = HeightField::new(&heights, 5, 4, 5).unwrap();
    check_map(&hf, &Desc::new(MapKind::MaxMip, 5, 4))
}

#[test]
fn bad_files_are_errors_not_panics() {
    let file = small_file();
    assert!(ktx2::read(&file).is_ok());
    // Every truncation.
    for n in 0..file.len() {
        let r = ktx2::read(&file[..n]).and_then(|v| v.desc());
        assert!(r.is_err(), "truncated to {n} bytes");
    }
    assert_eq!(ktx2::read(&file[..40]).unwrap_err(), Ktx2Error::Truncated);
    assert_eq!(
        ktx2::read(&file[..file.len() - 1]).unwrap_err(),
        Ktx2Error::Truncated
    );
    // Another identifier.
    let mut bad = file.clone();
    bad[5] = b'1';
    assert_eq!(ktx2::read(&bad).unwrap_err(), Ktx2Error::BadIdentifier);
    assert_eq!(ktx2::read(b"PNG").unwrap_err(), Ktx2Error::BadIdentifier);
    // A level index pointing past the end, or at a wrong length.
    let level0 = 80;
    let mut bad = file.clone();
    bad[level0..level0 + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    assert_eq!(ktx2::read(&bad).unwrap_err(), Ktx2Error::Truncated);
    let mut bad = file.clone();
    bad[level0..level0 + 8].copy_from_slice(&(file.len() as u64 - 8).to_le_bytes());
    assert_eq!(ktx2::read(&bad).unwrap_err(), Ktx2Error::Truncated);
    let mut bad = file.clone();
    bad[level0 + 8] += 4;
    bad[level0 + 16] += 4;
    assert!(matches!(
        ktx2::read(&bad),
        Err(Ktx2Error::Invalid(_) | Ktx2Error::Truncated)
    ));
    // Too many levels, another format, supercompression.
    for (at, v, want) in [
        (40, 9, Ktx2Error::Invalid("levelCount above log2(size) + 1")),
        (12, 37, Ktx2Error::Unsupported),
        (44, 2, Ktx2Error::Unsupported),
        (36, 6, Ktx2Error::Unsupported),
    ] {
        let mut bad = file.clone();
        bad[at..at + 4].copy_from_slice(&(v as u32).to_le_bytes());
        assert_eq!(ktx2::read(&bad).unwrap_err(), want, "header field at {at}");
    }
    // Metadata that disagrees with the header.
    let text = |f: &[u8], s: &[u8]| f.windows(s.len()).position(|w| w == s).unwrap();
    let mut bad = file.clone();
    let at = text(&bad, b"5x4\0");
    bad[at] = b'9';
    let view = ktx2::read(&bad).unwrap();
    assert_eq!(
        view.desc(),
        Err(Ktx2Error::BadMetadata("disagrees with the header"))
    );
    let mut out = vec![0.0; 64];
    assert!(view.read_map(DataMut::F32(&mut out)).is_err());
    assert!(out.iter().all(|&v| v == 0.0), "written on error");
    // Keys out of order.
    let mut bad = file.clone();
    let at = text(&bad, b"hfcast.field");
    bad[at..at + 6].copy_from_slice(b"zzzzzz");
    assert_eq!(
        ktx2::read(&bad).unwrap_err(),
        Ktx2Error::Invalid("keys not sorted or repeated")
    );
    // Every single-byte corruption: an error or a valid file, never a panic.
    let mut flips = 0;
    for at in 0..file.len() {
        let mut bad = file.clone();
        bad[at] ^= 0x5A;
        if let Ok(view) = ktx2::read(&bad) {
            let mut out = vec![0.0; 64];
            let _ = view.read_map(DataMut::F32(&mut out));
        } else {
            flips += 1;
        }
    }
    assert!(flips > 100, "{flips} corruptions refused");
    // Wrong data for the writer.
    let d = Desc::new(MapKind::Radius, 5, 4);
    let mut out = vec![0; 4096];
    assert_eq!(
        ktx2::write(&d, Data::F32(&[0.0; 20]), &mut out),
        Err(Ktx2Error::WrongData)
    );
    assert_eq!(
        ktx2::write(&d, Data::U8(&[0; 19]), &mut out),
        Err(Ktx2Error::DataTooShort { needed: 20 })
    );
    let empty = Desc {
        classes: RayClasses::NONE,
        ..Desc::new(MapKind::Cc, 5, 4)
    };
    assert_eq!(ktx2::len(&empty), Err(Ktx2Error::BadDesc));
    assert_eq!(
        ktx2::len(&Desc::new(MapKind::Cone, 1, 4)),
        Err(Ktx2Error::BadDesc)
    );
}

#[test]
fn cli_bake_writes_the_bake() {
    let dir = std::env::temp_dir().join(format!("hfcast-ktx2-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("cc.ktx2");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args([
            "bake",
            "--method",
            "cc",
            "--classes",
            "x+,y-",
            "--cap",
            "32",
        ])
        .args(["--threads", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let file = std::fs::read(&out).unwrap();
    let map = load_map(bundled_map(), None).unwrap();
    let hf = map.field();
    let desc = descs(hf.width(), hf.height())
        .into_iter()
        .find(|d| d.map == MapKind::Cc)
        .unwrap();
    // The CLI records the fingerprint of the heights, which the C API's map
    // descriptors name (`hfcast::mapdesc`).
    let desc = Desc {
        fingerprint: Some(hfcast::mapdesc::fingerprint(hf.samples())),
        ..desc
    };
    assert_eq!(ktx2::read(&file).unwrap().desc().unwrap(), desc);
    assert_eq!(
        file,
        check_map(&hf, &desc),
        "the CLI's row-range bake is the whole bake"
    );
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args(["bake", "--method", "nope", "--out"])
        .arg(dir.join("x.ktx2"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("unknown method"));
    std::fs::remove_dir_all(&dir).unwrap();
}
