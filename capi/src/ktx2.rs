//! Baked maps as KTX 2.0 files (the core's `ktx2` module): sizes, write into a
//! caller buffer, and the validating reader (file info, one level's bytes, the baked
//! map back). Every map of every method, whatever the cargo features: the container
//! needs no bake.

use crate::hf_result::{self, *};
use crate::mapdesc::{elems, Texel, HF_MAP_DESC_BYTES};
use crate::{guard, ptr, HF_MAX_SIDE};
use hfcore::ktx2::{self, Data, DataMut, Desc, Ktx2Error, MapKind, View};
use hfcore::mapdesc::MapDescriptor;
use std::ffi::c_void;

/// Which baked map a KTX 2 file holds, of which field, baked how: what the file's
/// metadata records (`hfcast.method`, `hfcast.field`, `hfcast.cap`,
/// `hfcast.ray_classes`, `hfcast.ray_set`, `hfcast.variant`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_ktx2_desc {
    /// The map: `HF_KTX2_*`.
    pub map: u32,
    /// The field's samples along x (2 to `HF_MAX_SIDE`).
    pub width: u32,
    /// The field's samples along y (2 to `HF_MAX_SIDE`).
    pub height: u32,
    /// The bake's cap, 0..=255 (safety, cylinder–cone and radius maps; else ignored).
    pub cap: u32,
    /// The ray classes the map holds, `HF_RAYS_*` bits, not 0 (safety and
    /// cylinder–cone maps; else ignored, and the radius map's are all four).
    pub ray_classes: u32,
    /// The radius bake's tolerance, finite and ≥ 0 (radius map; else ignored).
    pub tolerance: f32,
}

/// What `hf_ktx2_read_info` finds in a valid file.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_ktx2_info {
    /// The map, from the metadata (fields the map ignores read as
    /// `hf_ktx2_desc_default`'s).
    pub desc: hf_ktx2_desc,
    /// The `VkFormat` of the texture (13 `R8_UINT`, 20 `R8G8_UINT`, 100 `R32_SFLOAT`,
    /// 103 `R32G32_SFLOAT`, 109 `R32G32B32A32_SFLOAT`).
    pub vk_format: u32,
    /// Texels of level 0 along x.
    pub pixel_width: u32,
    /// Texels of level 0 along y.
    pub pixel_height: u32,
    /// Number of mip levels (1 except for the pyramid).
    pub levels: u32,
    /// Bytes per texel.
    pub texel_size: u32,
    /// Bytes of the baked map (`hf_ktx2_read_map`), as `hf_ktx2_map_len`.
    pub map_len: usize,
}

/// The C code of a container error: sizes of buffers are `HF_ERR_BUFFER_TOO_SMALL`, a
/// bad description `HF_ERR_INVALID_ARGUMENT`, and so is every file that is not a valid
/// hfcast KTX 2 file (truncated, wrong identifier, bad header, index or metadata).
fn code(e: Ktx2Error) -> hf_result {
    match e {
        Ktx2Error::DataTooShort { .. } | Ktx2Error::OutputTooShort { .. } => {
            HF_ERR_BUFFER_TOO_SMALL
        }
        _ => HF_ERR_INVALID_ARGUMENT,
    }
}

/// Checks an `hf_ktx2_desc` and turns it into the core's [`Desc`].
fn desc_of(d: &hf_ktx2_desc) -> Result<Desc, hf_result> {
    let map = MapKind::from_u32(d.map).ok_or(HF_ERR_INVALID_ENUM)?;
    let ok = |n: u32| (2..=HF_MAX_SIDE).contains(&n);
    if !ok(d.width) || !ok(d.height) {
        return Err(HF_ERR_INVALID_SIZE);
    }
    let mut desc = Desc::new(map, d.width, d.height);
    if map.has_rays() {
        desc.cap = u8::try_from(d.cap).map_err(|_| HF_ERR_INVALID_ARGUMENT)?;
    }
    if matches!(
        map,
        MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Cc
    ) {
        desc.classes = crate::scene::classes_of(d.ray_classes)?;
    }
    if map == MapKind::Radius {
        desc.tolerance = d.tolerance;
    }
    ktx2::len(&desc).map_err(code)?;
    Ok(desc)
}

/// The C form of a core [`Desc`].
pub(crate) fn c_desc(d: &Desc) -> hf_ktx2_desc {
    hf_ktx2_desc {
        map: d.map as u32,
        width: d.width,
        height: d.height,
        cap: d.cap.into(),
        ray_classes: d.classes.0.into(),
        tolerance: d.tolerance,
    }
}

/// Bytes of an element of `desc`'s map: 4 for float maps, 1 for 8-bit ones.
fn element_size(desc: &Desc) -> usize {
    desc.map.format().type_size()
}

/// Whether `desc`'s map is a bake (every map but the heights), which carries a
/// descriptor after its texels and its fingerprint in the file.
fn baked(desc: &Desc) -> bool {
    desc.map != MapKind::Heights
}

/// Bytes of the map of `desc` as the bakes write it: texels, then the descriptor.
fn map_bytes(desc: &Desc) -> Result<usize, hf_result> {
    let texels = ktx2::map_len(desc).map_err(code)? * element_size(desc);
    Ok(texels + if baked(desc) { HF_MAP_DESC_BYTES } else { 0 })
}

/// `desc` as the files of the C API store it: a bake's with its fingerprint (a
/// placeholder for sizing when unknown).
fn with_fingerprint(mut desc: Desc) -> Desc {
    if baked(&desc) {
        desc.fingerprint = desc.fingerprint.or(Some(0));
    }
    desc
}

/// The fingerprint of the baked map `data` (`texels` elements, then its descriptor),
/// whose descriptor must describe `desc`'s map.
fn fingerprint_of<T: Texel>(desc: &Desc, data: &[T], texels: usize) -> Result<u64, hf_result> {
    let got = crate::mapdesc::read(data, texels)?;
    let mut d = got.desc.normalized();
    let fp = d.fingerprint.take();
    if d != desc.normalized() {
        return Err(crate::detail::fail(
            HF_ERR_MAP_MISMATCH,
            format_args!(
                "data: its descriptor describes a {} map of a {} x {} field (cap {}, classes {:#x}, ray set {}), not desc's",
                d.map.method(),
                d.width,
                d.height,
                d.cap,
                d.classes.0,
                d.rays
            ),
        ));
    }
    fp.ok_or_else(|| {
        crate::detail::fail(
            HF_ERR_MAP_MISMATCH,
            "data: its descriptor names no heights (restored from a file without hfcast.fingerprint)",
        )
    })
}

/// Writes the description of map `map` (`HF_KTX2_*`) of a `width × height` field
/// with the bakes' defaults to `*out_desc`: cap 255 (safety, radius), 64
/// (cylinder–cone) or 0 (maps without one), every ray class, tolerance 0. Thread safe.
///
/// # Safety
/// `out_desc` is NULL (an error) or valid for writing one `hf_ktx2_desc`.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_desc_default(
    map: u32,
    width: u32,
    height: u32,
    out_desc: *mut hf_ktx2_desc,
) -> hf_result {
    let default = |()| {
        let kind = MapKind::from_u32(map).ok_or(HF_ERR_INVALID_ENUM)?;
        Ok(c_desc(&desc_of(&c_desc(&Desc::new(kind, width, height)))?))
    };
    // SAFETY: the caller's promise, passed on.
    unsafe { ptr::answer(|| Ok(()), out_desc, default) }
}

/// Writes the size in bytes of the KTX 2 file of `desc` to `*out_len`: the buffer
/// `hf_ktx2_write` needs. An unknown map is `HF_ERR_INVALID_ENUM`, a size outside 2 to
/// `HF_MAX_SIDE` `HF_ERR_INVALID_SIZE`, a cap above 255, no ray class (or bits above
/// `HF_RAYS_ALL`) or a negative or non-finite tolerance `HF_ERR_INVALID_ARGUMENT`.
/// Thread safe.
///
/// # Safety
/// `desc` is NULL (an error) or valid; `out_len` NULL (an error) or valid for writing
/// one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_len(desc: *const hf_ktx2_desc, out_len: *mut usize) -> hf_result {
    let len = |d| ktx2::len(&with_fingerprint(d)).map_err(code);
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| desc_of(ptr::get(desc)?), out_len, len) }
}

/// Writes the size in bytes of the baked map of `desc` to `*out_len`: what its bake
/// writes (for the pyramid every level, `hf_map_len` floats), descriptor included
/// (every map but `HF_KTX2_HEIGHTS`), which `hf_ktx2_write` reads and
/// `hf_ktx2_read_map` writes. Errors as `hf_ktx2_len`. Thread safe.
///
/// # Safety
/// As `hf_ktx2_len`.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_map_len(
    desc: *const hf_ktx2_desc,
    out_len: *mut usize,
) -> hf_result {
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| desc_of(ptr::get(desc)?), out_len, |d| map_bytes(&d)) }
}

/// Writes the KTX 2 file of the baked map `data` (`data_len` bytes, at least
/// `hf_ktx2_map_len`: the buffer its bake filled, floats for float maps, aligned for
/// them) described by `desc` into `out` (`out_len ≥ hf_ktx2_len` bytes; the file is
/// the first `hf_ktx2_len` of them). A baked map's descriptor must describe `desc`'s
/// map and name its heights (`HF_ERR_MAP_MISMATCH` otherwise); its fingerprint is
/// stored as `hfcast.fingerprint`. Errors as `hf_ktx2_len`, plus
/// `HF_ERR_BUFFER_TOO_SMALL` for a short `data` or `out`. Thread safe.
///
/// # Safety
/// `desc` is NULL (an error) or valid; `data` NULL (an error) or valid for reading
/// `data_len` bytes; `out` NULL (an error) or valid for writing `out_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_write(
    desc: *const hf_ktx2_desc,
    data: *const c_void,
    data_len: usize,
    out: *mut u8,
    out_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `desc` is valid.
        let mut desc = desc_of(unsafe { ptr::get(desc) }?)?;
        let texels = ktx2::map_len(&desc).map_err(code)?;
        let data = if desc.map.format().is_float() {
            // SAFETY: the caller promises `data_len` readable bytes; `slice` checks the
            // alignment of the floats.
            let d = unsafe { ptr::slice(data.cast::<f32>(), data_len / 4) }?;
            if baked(&desc) {
                desc.fingerprint = Some(fingerprint_of(&desc, d, texels)?);
            }
            Data::F32(d)
        } else {
            // SAFETY: as above.
            let d = unsafe { ptr::slice(data.cast::<u8>(), data_len) }?;
            desc.fingerprint = Some(fingerprint_of(&desc, d, texels)?);
            Data::U8(d)
        };
        // SAFETY: the caller promises `out_len` writable bytes.
        let out = unsafe { ptr::slice_mut(out, out_len) }?;
        ktx2::write(&desc, data, out).map_err(code)?;
        Ok(())
    })
}

/// Writes the descriptor of a map read from a file (`desc`, with its fingerprint if the
/// file has one) into `slot`, after its `texels` elements.
fn restore<T: Texel>(desc: &Desc, texels: usize, slot: &mut [T]) {
    let d = MapDescriptor {
        desc: *desc,
        texel_bytes: (texels * T::SIZE) as u64,
    };
    T::put(&mut slot[..elems::<T>()], &d.encode());
}

/// The validated file at `bytes` and its description.
///
/// # Safety
/// `bytes` NULL (an error) or valid for reading `len` bytes.
unsafe fn open<'a>(bytes: *const u8, len: usize) -> Result<(View<'a>, Desc), hf_result> {
    // SAFETY: the caller's promise.
    let bytes = unsafe { ptr::slice(bytes, len) }?;
    let view = ktx2::read(bytes).map_err(code)?;
    let desc = view.desc().map_err(code)?;
    Ok((view, desc))
}

/// Validates the KTX 2 file `bytes` (`len` bytes: identifier, header, level index,
/// data format descriptor, key/value data, hfcast metadata agreeing with the header)
/// and writes what it holds to `*out_info`. A file that is not a valid hfcast KTX 2
/// file (truncated, another identifier, an index pointing past the end, other
/// metadata) is `HF_ERR_INVALID_ARGUMENT`. Thread safe.
///
/// # Safety
/// `bytes` is NULL (an error) or valid for reading `len` bytes; `out_info` NULL (an
/// error) or valid for writing one `hf_ktx2_info`.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_read_info(
    bytes: *const u8,
    len: usize,
    out_info: *mut hf_ktx2_info,
) -> hf_result {
    let info = |(view, desc): (View, Desc)| {
        let [pixel_width, pixel_height] = view.pixel_size();
        Ok(hf_ktx2_info {
            desc: c_desc(&desc),
            vk_format: view.format() as u32,
            pixel_width,
            pixel_height,
            levels: view.level_count(),
            texel_size: view.format().texel_size() as u32,
            map_len: map_bytes(&desc)?,
        })
    };
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| open(bytes, len), out_info, info) }
}

/// Writes the size in bytes of mip level `level` of the KTX 2 file `bytes` to
/// `*out_len`: `max(1, pixel_width >> level) · max(1, pixel_height >> level) ·
/// texel_size`. A level past the last is `HF_ERR_INVALID_ARGUMENT`; errors of the
/// file as `hf_ktx2_read_info`. Thread safe.
///
/// # Safety
/// As `hf_ktx2_read_info`, with `out_len` valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_level_len(
    bytes: *const u8,
    len: usize,
    level: u32,
    out_len: *mut usize,
) -> hf_result {
    let level_len =
        |(view, _): (View, Desc)| Ok(view.level(level).ok_or(HF_ERR_INVALID_ARGUMENT)?.len());
    // SAFETY: the caller's promises, passed on.
    unsafe { ptr::answer(|| open(bytes, len), out_len, level_len) }
}

/// Copies mip level `level` of the KTX 2 file `bytes` into `out` (`out_len ≥
/// hf_ktx2_level_len` bytes): texel rows tightly packed, little-endian, ready for a
/// GPU upload of that level (a padded pyramid level with its `−∞` padding). Errors as
/// `hf_ktx2_level_len`, plus `HF_ERR_BUFFER_TOO_SMALL`. Thread safe.
///
/// # Safety
/// As `hf_ktx2_read_info`, with `out` valid for writing `out_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_read_level(
    bytes: *const u8,
    len: usize,
    level: u32,
    out: *mut u8,
    out_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promise, passed on.
        let (view, _) = unsafe { open(bytes, len) }?;
        // SAFETY: the caller promises `out_len` writable bytes.
        let out = unsafe { ptr::slice_mut(out, out_len) }?;
        let data = view.level(level).ok_or(HF_ERR_INVALID_ARGUMENT)?;
        let out = out.get_mut(..data.len()).ok_or(HF_ERR_BUFFER_TOO_SMALL)?;
        out.copy_from_slice(data);
        Ok(())
    })
}

/// Copies the baked map of the KTX 2 file `bytes` into `out` (`out_len ≥` the info's
/// `map_len` bytes; floats for float maps, aligned for them): exactly what its bake
/// wrote, descriptor included, ready for `hf_trace` with its method on a field
/// of the same heights (the pyramid with every level, unpadded; a file without
/// `hfcast.fingerprint` gives a descriptor that names no heights, which traces refuse).
/// Errors as `hf_ktx2_read_info`, plus `HF_ERR_BUFFER_TOO_SMALL`. Thread safe.
///
/// # Safety
/// As `hf_ktx2_read_info`, with `out` valid for writing `out_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hf_ktx2_read_map(
    bytes: *const u8,
    len: usize,
    out: *mut c_void,
    out_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller's promise, passed on.
        let (view, desc) = unsafe { open(bytes, len) }?;
        if out_len < map_bytes(&desc)? {
            return Err(HF_ERR_BUFFER_TOO_SMALL);
        }
        let texels = ktx2::map_len(&desc).map_err(code)?;
        if desc.map.format().is_float() {
            // SAFETY: the caller promises `out_len` writable bytes; `slice_mut` checks
            // the alignment of the floats.
            let out = unsafe { ptr::slice_mut(out.cast::<f32>(), out_len / 4) }?;
            view.read_map(DataMut::F32(&mut out[..texels]))
                .map_err(code)?;
            if baked(&desc) {
                restore(&desc, texels, &mut out[texels..]);
            }
        } else {
            // SAFETY: as above.
            let out = unsafe { ptr::slice_mut(out.cast::<u8>(), out_len) }?;
            view.read_map(DataMut::U8(&mut out[..texels]))
                .map_err(code)?;
            restore(&desc, texels, &mut out[texels..]);
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hfcore::scene::RayClasses;

    #[test]
    fn write_then_read_a_radius_map() {
        let mut d = std::mem::MaybeUninit::uninit();
        // SAFETY: `d` is writable.
        assert_eq!(
            unsafe { hf_ktx2_desc_default(MapKind::Radius as u32, 4, 3, d.as_mut_ptr()) },
            HF_OK
        );
        // SAFETY: written on HF_OK.
        let mut d = unsafe { d.assume_init() };
        assert_eq!(
            (d.cap, RayClasses(d.ray_classes as u8)),
            (255, RayClasses::ALL)
        );
        d.tolerance = 0.25;
        let mut n = 0;
        // SAFETY: valid pointers.
        assert_eq!(unsafe { hf_ktx2_len(&d, &mut n) }, HF_OK);
        let mut map: Vec<u8> = (0..12).collect();
        let mut file = vec![0u8; n];
        // SAFETY: valid pointers and lengths; a map without its descriptor.
        let r = unsafe { hf_ktx2_write(&d, map.as_ptr().cast(), 12, file.as_mut_ptr(), n) };
        assert_eq!(r, HF_ERR_BUFFER_TOO_SMALL);
        let mut core_desc = desc_of(&d).unwrap();
        core_desc.fingerprint = Some(0xfeed);
        let stamp = MapDescriptor {
            desc: core_desc,
            texel_bytes: 12,
        };
        map.extend_from_slice(&stamp.encode());
        let m = map.len();
        // SAFETY: valid pointers and lengths.
        let r = unsafe { hf_ktx2_write(&d, map.as_ptr().cast(), m, file.as_mut_ptr(), n) };
        assert_eq!(r, HF_OK);
        let mut slot = std::mem::MaybeUninit::uninit();
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { hf_ktx2_read_info(file.as_ptr(), n, slot.as_mut_ptr()) },
            HF_OK
        );
        // SAFETY: written on HF_OK.
        let info = unsafe { slot.assume_init() };
        assert_eq!((info.desc, info.vk_format, info.map_len), (d, 13, m));
        let mut back = vec![0u8; m];
        // SAFETY: valid pointers; a short buffer first.
        let r = unsafe { hf_ktx2_read_map(file.as_ptr(), n, back.as_mut_ptr().cast(), m - 1) };
        assert_eq!(r, HF_ERR_BUFFER_TOO_SMALL);
        // SAFETY: valid pointers.
        let r = unsafe { hf_ktx2_read_map(file.as_ptr(), n, back.as_mut_ptr().cast(), m) };
        assert_eq!((r, &back[..12]), (HF_OK, &map[..12]));
        // The descriptor comes back as written.
        assert_eq!(back, map);
        // SAFETY: a truncated file.
        let r = unsafe { hf_ktx2_read_info(file.as_ptr(), n - 1, slot.as_mut_ptr()) };
        assert_eq!(r, HF_ERR_INVALID_ARGUMENT);
    }
}
