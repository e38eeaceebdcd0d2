//! The one bake interface (`hfcast::bake::Spec`) against each method's own bake: the
//! same bytes for every map, whole or baked in row ranges, and clear errors for bad
//! buffers, rows and fields.

mod common;

use common::{fractal_field, Rng};
use hfcast::bake::{Error, Spec};
use hfcast::buffer::BufferError;
use hfcast::ktx2::{DataMut, Desc, MapKind};
use hfcast::safety::{self, cc, AllRays, Options, Variant};
use hfcast::scene::RayClasses;
use hfcast::{cone, maxmip, qdm, radius, relaxed, HeightField};

/// A baked map of either element type.
#[derive(Debug, PartialEq)]
enum Map {
    F32(Vec<f32>),
    U8(Vec<u8>),
}

impl Map {
    fn zeroed(spec: &Spec) -> Map {
        let n = spec.map_len().unwrap();
        match spec.is_float() {
            true => Map::F32(vec![0.0; n]),
            false => Map::U8(vec![0; n]),
        }
    }
    fn data(&mut self) -> DataMut<'_> {
        match self {
            Map::F32(m) => DataMut::F32(m),
            Map::U8(m) => DataMut::U8(m),
        }
    }
    /// Elements `from..` as a row bake's output.
    fn rows_from(&mut self, from: usize) -> DataMut<'_> {
        match self {
            Map::F32(m) => DataMut::F32(&mut m[from..]),
            Map::U8(m) => DataMut::U8(&mut m[from..]),
        }
    }
}

/// The map of `spec` baked by its own module's functions.
fn own_bake(hf: &HeightField, spec: &Spec) -> Map {
    let (w, h, cap) = (hf.width(), hf.height(), spec.desc.cap);
    let mut strips = vec![0.0; safety::scratch_len(w, h)];
    let mut pyramid = vec![0.0; cone::scratch_len(w, h)];
    let n = spec.map_len().unwrap();
    let (mut f, mut b) = (vec![0.0f32; n], vec![0u8; n]);
    let classes = spec.desc.classes;
    match spec.desc.map {
        MapKind::Heights => {
            for (k, v) in f.iter_mut().enumerate() {
                *v = hf.at(k as u32 % w, k as u32 / w);
            }
        }
        MapKind::MaxMip => maxmip::bake(hf, &mut f).unwrap(),
        MapKind::Cone => cone::bake::<cone::Cone>(hf, &mut pyramid, &mut f).unwrap(),
        MapKind::Relaxed => cone::bake::<relaxed::Relaxed>(hf, &mut pyramid, &mut f).unwrap(),
        MapKind::Qdm => cone::bake::<qdm::Qdm>(hf, &mut pyramid, &mut f).unwrap(),
        MapKind::Safety => b = safety_bake(hf, spec, Variant::Directional),
        MapKind::SafetyIsotropic => b = safety_bake(hf, spec, Variant::Isotropic),
        MapKind::Cc => {
            let mut nb = vec![0.0; cc::nbuffer_len(w, h, cap)];
            let slope = match spec.nbuffer_slope {
                true => cc::Slope::NBuffer,
                false => cc::Slope::Exact,
            };
            let opts = cc::CcOptions { slope, cap };
            safety::prepare(hf, &mut strips).unwrap();
            cc::prepare_nbuffer(hf, cap, &mut nb).unwrap();
            cc::bake_rows_classes(hf, &strips, &nb, classes, 0..h, opts, &mut b).unwrap()
        }
        MapKind::Radius => {
            let opts = radius::BakeOptions {
                tolerance: spec.desc.tolerance,
                cap,
            };
            radius::bake(hf, &mut strips, opts, &mut b).unwrap()
        }
    }
    match spec.is_float() {
        true => Map::F32(f),
        false => Map::U8(b),
    }
}

/// `spec`'s safety-distance map of `variant`, baked by `safety`'s own functions.
fn safety_bake(hf: &HeightField, spec: &Spec, variant: Variant) -> Vec<u8> {
    let (w, h) = (hf.width(), hf.height());
    let mut strips = vec![0.0; safety::scratch_len(w, h)];
    safety::prepare(hf, &mut strips).unwrap();
    let opts = Options {
        variant,
        positive: spec.positive,
        cap: spec.desc.cap,
    };
    let mut out = vec![0; spec.map_len().unwrap()];
    let classes = spec.desc.classes;
    safety::bake_rows_classes(hf, &strips, &AllRays, classes, 0..h, opts, &mut out).unwrap();
    out
}

/// Every map kind, with a few non-default choices.
fn specs(w: u32, h: u32) -> Vec<Spec> {
    let mut out: Vec<Spec> = MapKind::ALL
        .into_iter()
        .map(|m| Spec::new(Desc::new(m, w, h)))
        .collect();
    let two = RayClasses(0b0101);
    let with = |map, f: &dyn Fn(&mut Spec)| {
        let mut s = Spec::new(Desc::new(map, w, h));
        f(&mut s);
        s
    };
    out.push(with(MapKind::Safety, &|s| s.desc.classes = two));
    out.push(with(MapKind::SafetyIsotropic, &|s| s.positive = true));
    out.push(with(MapKind::Cc, &|s| {
        s.nbuffer_slope = true;
        s.desc.cap = 9;
        s.desc.classes = two;
    }));
    out.push(with(MapKind::Radius, &|s| {
        s.desc.tolerance = 0.25;
        s.desc.cap = 7;
    }));
    out
}

#[test]
fn every_map_bakes_as_its_own_module_does_whole_and_by_rows() {
    let mut rng = Rng::new(51);
    let field = fractal_field(&mut rng, 23, 17, 25, 6.0);
    let hf = field.hf();
    for spec in specs(hf.width(), hf.height()) {
        let want = own_bake(&hf, &spec);
        let mut scratch = vec![0.0; spec.scratch_len()];
        let mut whole = Map::zeroed(&spec);
        spec.bake(&hf, &mut scratch, whole.data()).unwrap();
        assert_eq!(whole, want, "{:?}", spec);
        // Three row ranges, out of order, from one prepared scratch.
        let rows = spec.rows();
        let row = spec.row_len().unwrap();
        let cuts = [0, rows / 3, rows / 2, rows];
        let mut parts = Map::zeroed(&spec);
        for k in [2, 0, 1] {
            let r = cuts[k]..cuts[k + 1];
            let from = r.start as usize * row;
            spec.bake_rows(&hf, &scratch, r, parts.rows_from(from))
                .unwrap();
        }
        assert_eq!(parts, want, "{:?} by rows", spec);
        // An empty range bakes nothing, even the pyramid's one row.
        let mut untouched = Map::zeroed(&spec);
        spec.bake_rows(&hf, &scratch, rows..rows, untouched.rows_from(0))
            .unwrap();
        assert_eq!(untouched, Map::zeroed(&spec), "{:?} empty range", spec);
    }
}

#[test]
fn bad_buffers_rows_and_fields_are_errors() {
    let mut rng = Rng::new(52);
    let field = fractal_field(&mut rng, 9, 8, 9, 3.0);
    let hf = field.hf();
    let spec = Spec::new(Desc::new(MapKind::Cone, 9, 8));
    let mut scratch = vec![0.0; spec.scratch_len()];
    spec.prepare(&hf, &mut scratch).unwrap();
    let mut out = vec![0.0f32; spec.map_len().unwrap()];
    let mut bytes = vec![0u8; out.len()];
    let rows = spec.rows();
    assert_eq!(
        spec.bake_rows(&hf, &scratch, 0..rows + 1, DataMut::F32(&mut out)),
        Err(Error::Buffer(BufferError::BadRows))
    );
    assert!(matches!(
        spec.bake_rows(&hf, &scratch[1..], 0..rows, DataMut::F32(&mut out)),
        Err(Error::Buffer(BufferError::TooShort {
            what: "scratch",
            ..
        }))
    ));
    let short = out.len() - 1;
    assert!(matches!(
        spec.bake_rows(&hf, &scratch, 0..rows, DataMut::F32(&mut out[..short])),
        Err(Error::Buffer(BufferError::TooShort { what: "output", .. }))
    ));
    assert_eq!(
        spec.bake_rows(&hf, &scratch, 0..rows, DataMut::U8(&mut bytes)),
        Err(Error::WrongType)
    );
    let other = Spec::new(Desc::new(MapKind::Cone, 10, 8));
    assert_eq!(
        other.bake(&hf, &mut scratch, DataMut::F32(&mut out)),
        Err(Error::WrongField)
    );
    let bad = Spec::new(Desc::new(MapKind::Cone, 1, 8));
    assert_eq!(bad.map_len(), Err(Error::BadDesc));
}
