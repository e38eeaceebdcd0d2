//! Map descriptors at the C boundary: every bake writes one after the map's texels,
//! every trace checks it against the field and the trace's arguments (the core's
//! `mapdesc` module has the layout).

use crate::detail::fail;
use crate::hf_result::{self, *};
use crate::ktx2::hf_ktx2_desc;
use crate::{guard, hf_field, ptr};
use hfcore::ktx2::{Desc, MapKind};
use hfcore::mapdesc::{DescriptorError, MapDescriptor, FINGERPRINT_KNOWN, LEN};
use hfcore::scene::RayClasses;

/// Bytes of the descriptor that follows the texels of every baked map: the map
/// functions' `_len` queries count it, so a buffer of their size holds both. Upload the
/// texels only (the first `len − HF_MAP_DESC_BYTES` bytes, `/ 4` floats for float
/// maps); the descriptor stays on the CPU side with the map.
pub const HF_MAP_DESC_BYTES: usize = 64;
const _: () = assert!(HF_MAP_DESC_BYTES == LEN);

/// Flag of `hf_map_desc::flags`: the fingerprint names the heights baked from (a map
/// restored from a KTX2 file without `hfcast.fingerprint` lacks it and matches no
/// field).
pub const HF_MAP_FINGERPRINT_KNOWN: u32 = 1;
const _: () = assert!(HF_MAP_FINGERPRINT_KNOWN == FINGERPRINT_KNOWN);

/// What a baked map belongs to, as `hf_map_read_desc` reads it from the descriptor
/// after the map's texels.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_map_desc {
    /// The map and its bake (kind `HF_KTX2_*`, the field's size, cap, ray classes,
    /// tolerance), as the KTX2 functions describe it.
    pub map: hf_ktx2_desc,
    /// `HF_MAP_FINGERPRINT_KNOWN` or 0.
    pub flags: u32,
    /// The fingerprint of the heights baked from (`hf_field_get_fingerprint`).
    pub fingerprint: u64,
    /// Bytes of the map's texels (the descriptor starts there).
    pub texel_bytes: u64,
}

/// An element type of a map: bytes or floats.
pub(crate) trait Texel: Copy {
    /// Bytes of one element.
    const SIZE: usize;
    /// Writes the descriptor's bytes into `LEN / SIZE` elements.
    fn put(out: &mut [Self], bytes: &[u8; LEN]);
    /// Reads `LEN / SIZE` elements back as bytes.
    fn get(src: &[Self]) -> [u8; LEN];
}

impl Texel for u8 {
    const SIZE: usize = 1;
    fn put(out: &mut [u8], bytes: &[u8; LEN]) {
        out.copy_from_slice(bytes);
    }
    fn get(src: &[u8]) -> [u8; LEN] {
        let mut b = [0; LEN];
        b.copy_from_slice(src);
        b
    }
}

impl Texel for f32 {
    const SIZE: usize = 4;
    fn put(out: &mut [f32], bytes: &[u8; LEN]) {
        for (o, w) in out.iter_mut().zip(bytes.chunks_exact(4)) {
            *o = f32::from_bits(u32::from_le_bytes([w[0], w[1], w[2], w[3]]));
        }
    }
    fn get(src: &[f32]) -> [u8; LEN] {
        let mut b = [0; LEN];
        for (w, v) in b.chunks_exact_mut(4).zip(src) {
            w.copy_from_slice(&v.to_bits().to_le_bytes());
        }
        b
    }
}

/// Elements of `T` the descriptor takes.
pub(crate) const fn elems<T: Texel>() -> usize {
    LEN / T::SIZE
}

/// What a map's user (a trace, a refresh) expects of it: the map, and the cap and ray
/// classes when the call names them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Expect {
    pub map: MapKind,
    pub cap: Option<u8>,
    pub classes: Option<RayClasses>,
}

impl Expect {
    /// A map of kind `map` whatever its cap and classes.
    #[cfg(feature = "maxmip")]
    pub fn map(map: MapKind) -> Expect {
        Expect {
            map,
            cap: None,
            classes: None,
        }
    }
}

/// `BUFFER_TOO_SMALL` unless `len` elements hold `texels` and the descriptor.
pub(crate) fn room<T: Texel>(len: usize, texels: usize, what: &str) -> Result<(), hf_result> {
    let needed = texels + elems::<T>();
    if len < needed {
        return Err(fail(
            HF_ERR_BUFFER_TOO_SMALL,
            format_args!("{what}: {len} elements, the map and its descriptor need {needed}"),
        ));
    }
    Ok(())
}

/// The descriptor of the map `desc` baked now from `f`, `texels` elements of `T`.
fn descriptor_of<T: Texel>(f: &hf_field, mut desc: Desc, texels: usize) -> [u8; LEN] {
    desc.fingerprint = Some(f.fingerprint());
    MapDescriptor {
        desc,
        texel_bytes: (texels * T::SIZE) as u64,
    }
    .encode()
}

/// Writes the descriptor of the map `desc` of `f` (`texels` elements) into `slot`, the
/// `elems::<T>()` elements after the texels.
pub(crate) fn stamp<T: Texel>(f: &hf_field, desc: Desc, texels: usize, slot: &mut [T]) {
    T::put(
        &mut slot[..elems::<T>()],
        &descriptor_of::<T>(f, desc, texels),
    );
}

/// The descriptor after `texels` elements of `data`, decoded.
pub(crate) fn read<T: Texel>(data: &[T], texels: usize) -> Result<MapDescriptor, hf_result> {
    room::<T>(data.len(), texels, "map")?;
    let bytes = T::get(&data[texels..texels + elems::<T>()]);
    MapDescriptor::decode(&bytes).map_err(|e| {
        let why = match e {
            DescriptorError::Missing => "none (a map baked before maps had descriptors, or read at the length of another size or class set)",
            DescriptorError::Version(_) => "of another layout version",
            DescriptorError::Corrupt => "damaged (its hash disagrees, or a field holds no valid value)",
        };
        fail(
            HF_ERR_MAP_MISMATCH,
            format_args!(
                "map: the descriptor after its {} texel bytes is {why}",
                texels * T::SIZE
            ),
        )
    })
}

/// The name of a map kind in messages.
fn name(map: MapKind) -> &'static str {
    match map {
        MapKind::SafetyIsotropic => "isotropic safety",
        MapKind::Safety => "directional safety",
        m => m.method(),
    }
}

/// Checks the descriptor after `texels` elements of `data` against `f` and `want`:
/// `HF_ERR_MAP_MISMATCH` for another map, size, cap, class set or other heights,
/// `HF_ERR_STALE_MAP` for heights this field had before an update.
pub(crate) fn check<T: Texel>(
    f: &hf_field,
    want: Expect,
    data: &[T],
    texels: usize,
) -> Result<MapDescriptor, hf_result> {
    let got = check_shape(f, want, data, texels)?;
    match got.desc.fingerprint {
        Some(fp) if fp == f.fingerprint() => Ok(got),
        _ => Err(heights_error(f, &got)),
    }
}

/// Checks a map whose texel count depends on how it was baked: one of `kinds` (the
/// variants of a safety map) holding some set of ray classes, `len(kind, classes)`
/// texels. The descriptor is looked for after each such layout; the one found (or,
/// when none is, the layout of `kinds[0]` with `classes`, or all four classes, for
/// the error) is checked for `f` and, when named, `classes`. Returns the descriptor
/// and the texel count.
pub(crate) fn check_layout<T: Texel>(
    f: &hf_field,
    data: &[T],
    kinds: &[MapKind],
    classes: Option<RayClasses>,
    len: impl Fn(MapKind, RayClasses) -> usize,
) -> Result<(MapDescriptor, usize), hf_result> {
    let found = kinds.iter().find_map(|&kind| {
        (1..=4).find_map(|count| {
            let held = RayClasses((1 << count) - 1);
            let n = len(kind, held);
            let bytes = T::get(data.get(n..n.checked_add(elems::<T>())?)?);
            let d = MapDescriptor::decode(&bytes).ok()?;
            let fits = d.desc.map == kind && d.texel_bytes == (n * T::SIZE) as u64;
            (fits && d.desc.classes.count() == count).then_some((kind, d.desc.classes))
        })
    });
    // No descriptor found: report on the layout that ends where the buffer does (its
    // descriptor is damaged), else on the smallest the buffer falls short of (it is too
    // short), else on the largest (a buffer longer than any layout).
    let (kind, held) = found.unwrap_or_else(|| {
        let layouts = kinds.iter().flat_map(|&kind| {
            let sets = (1..=4).map(|count| RayClasses((1 << count) - 1));
            let sets = sets.filter(|c| classes.is_none_or(|want| want.count() == c.count()));
            sets.map(move |c| (kind, c))
        });
        let layouts: Vec<_> = layouts
            .map(|(k, c)| (len(k, c) + elems::<T>(), (k, c)))
            .collect();
        let exact = layouts.iter().find(|(end, _)| *end == data.len());
        let short = layouts
            .iter()
            .filter(|(end, _)| *end > data.len())
            .min_by_key(|(e, _)| *e);
        let largest = layouts.iter().max_by_key(|(end, _)| *end);
        exact
            .or(short)
            .or(largest)
            .map_or((kinds[0], RayClasses::ALL), |(_, l)| *l)
    });
    let n = len(kind, held);
    let want = Expect {
        map: kind,
        cap: None,
        classes: Some(classes.unwrap_or(held)),
    };
    Ok((check(f, want, data, n)?, n))
}

#[cfg(feature = "maxmip")]
/// Checks the descriptor of a pyramid about to be refreshed over the samples
/// `rect` (`[x0, y0, x1, y1]`): it must name the current heights, or heights the field
/// had before updates that all lie inside `rect`.
pub(crate) fn check_refresh(
    f: &hf_field,
    data: &[f32],
    texels: usize,
    rect: [u32; 4],
) -> Result<(), hf_result> {
    let got = check_shape(f, Expect::map(MapKind::MaxMip), data, texels)?;
    let Some(fp) = got.desc.fingerprint.filter(|&fp| fp != f.fingerprint()) else {
        return match got.desc.fingerprint {
            Some(_) => Ok(()),
            None => Err(heights_error(f, &got)),
        };
    };
    let updates = f.updates_since(fp).ok_or_else(|| heights_error(f, &got))?;
    let inside =
        |r: [u32; 4]| rect[0] <= r[0] && rect[1] <= r[1] && r[2] <= rect[2] && r[3] <= rect[3];
    match updates.iter().find(|u| !inside(u.rect)) {
        None => Ok(()),
        Some(u) => Err(fail(
            HF_ERR_STALE_MAP,
            format_args!(
                "[{}, {}) x [{}, {}): update {} of the field changed [{}, {}) x [{}, {}), outside this rectangle; refresh over a rectangle covering every update since the bake, or rebake",
                rect[0], rect[2], rect[1], rect[3], u.generation, u.rect[0], u.rect[2], u.rect[1], u.rect[3]
            ),
        )),
    }
}

/// Everything but the heights: the kind, the size, the cap and classes `want` names.
fn check_shape<T: Texel>(
    f: &hf_field,
    want: Expect,
    data: &[T],
    texels: usize,
) -> Result<MapDescriptor, hf_result> {
    let got = read(data, texels)?;
    let d = got.desc;
    let mismatch = |msg: core::fmt::Arguments| Err(fail(HF_ERR_MAP_MISMATCH, msg));
    let hf = f.view();
    if d.map != want.map {
        return mismatch(format_args!(
            "map: a {} map, a {} map expected",
            name(d.map),
            name(want.map)
        ));
    }
    let bytes = (texels * T::SIZE) as u64;
    if (d.width, d.height) != (hf.width(), hf.height()) || got.texel_bytes != bytes {
        return mismatch(format_args!(
            "map: baked for a {} x {} field, this one is {} x {}",
            d.width,
            d.height,
            hf.width(),
            hf.height()
        ));
    }
    if let Some(cap) = want.cap.filter(|&c| c != d.cap) {
        return mismatch(format_args!("cap: {cap}, the map was baked with {}", d.cap));
    }
    if let Some(c) = want.classes.filter(|&c| c != d.classes) {
        return mismatch(format_args!(
            "ray_classes: {:#x}, the map holds {:#x}",
            c.0, d.classes.0
        ));
    }
    Ok(got)
}

/// The error for a descriptor that does not name `f`'s current heights.
fn heights_error(f: &hf_field, got: &MapDescriptor) -> hf_result {
    match got.desc.fingerprint {
        Some(fp) if f.updates_since(fp).is_some() => fail(
            HF_ERR_STALE_MAP,
            format_args!(
                "map: baked from the heights before update {} of the field, which has had {}: rebake or refresh it",
                f.updates_since(fp).map_or(0, |u| u[0].generation),
                f.generation()
            ),
        ),
        Some(fp) => fail(
            HF_ERR_MAP_MISMATCH,
            format_args!(
                "map: baked from other heights (fingerprint {fp:016x}, the field's {:016x}), or from heights this field had before its last {} updates",
                f.fingerprint(),
                crate::field::HISTORY
            ),
        ),
        None => fail(
            HF_ERR_MAP_MISMATCH,
            "map: its descriptor names no heights (restored from a KTX2 file without hfcast.fingerprint)",
        ),
    }
}

/// Reads the descriptor of a baked map: the last `HF_MAP_DESC_BYTES` bytes of the
/// `map_len` bytes at `map` (pass the map function's `_len` value, in bytes: 4 per
/// float for float maps). `HF_ERR_MAP_MISMATCH` when they are no descriptor (with
/// `hf_last_error_detail` saying why). Thread safe.
///
/// # Safety
/// `map` is NULL (an error) or valid for reading `map_len` bytes; `out_desc` is NULL
/// (an error) or valid for writing one `hf_map_desc`.
#[no_mangle]
pub unsafe extern "C" fn hf_map_read_desc(
    map: *const core::ffi::c_void,
    map_len: usize,
    out_desc: *mut hf_map_desc,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `map_len` readable bytes.
        let bytes = unsafe { ptr::slice(map.cast::<u8>(), map_len) }?;
        let out = ptr::out(out_desc)?;
        let texels = map_len.checked_sub(LEN).ok_or_else(|| {
            fail(
                HF_ERR_BUFFER_TOO_SMALL,
                format_args!("map_len: {map_len} bytes, a descriptor takes {LEN}"),
            )
        })?;
        let got = read(bytes, texels)?;
        let desc = hf_map_desc {
            map: crate::ktx2::c_desc(&got.desc),
            flags: if got.desc.fingerprint.is_some() {
                HF_MAP_FINGERPRINT_KNOWN
            } else {
                0
            },
            fingerprint: got.desc.fingerprint.unwrap_or(0),
            texel_bytes: got.texel_bytes,
        };
        // SAFETY: the caller promises `out_desc` is writable.
        unsafe { out.set(desc) };
        Ok(())
    })
}

/// Writes the fingerprint of the field's heights (the core's
/// `mapdesc::fingerprint`, what a map's descriptor must name) to `*out_fingerprint`
/// and the number of updates the handle has had (`hf_field_update_rect` calls that
/// changed a non-empty rectangle) to `*out_generation`. Thread safe.
///
/// # Safety
/// `field` is NULL (an error) or a live handle; `out_fingerprint` and
/// `out_generation` are NULL (an error) or valid for writing one `uint64_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_field_get_fingerprint(
    field: *const hf_field,
    out_fingerprint: *mut u64,
    out_generation: *mut u64,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises a live handle.
        let f = unsafe { ptr::get(field) }?;
        let (fp, generation) = (ptr::out(out_fingerprint)?, ptr::out(out_generation)?);
        // SAFETY: the caller promises both outputs writable.
        unsafe {
            fp.set(f.fingerprint());
            generation.set(f.generation());
        }
        Ok(())
    })
}
