//! Baked maps as KTX 2.0 files (Khronos Texture 2.0): a writer into a caller-owned
//! buffer and a validating reader, both without allocation.
//!
//! **Use.** [`len`] sizes the file of a [`Desc`] (which map, of which field, baked with
//! which cap, ray classes and ray set); [`write()`] writes the baked map (the slice the
//! bake filled, [`Data`]) into a buffer of that size; [`read`] validates a file and
//! gives each level's bytes ([`View::level`]), the metadata ([`View::desc`],
//! [`View::text`]) and the baked map back ([`View::read_map`], the exact inverse of
//! [`write()`]). The `ktx2` crate reads the files too (the tests of `hfcast-tools` check
//! every map with it); libktx's tools are not packaged by Debian bookworm, so it is the
//! independent reader.
//!
//! **Formats.** One explicit Vulkan format per map, the texture the shaders upload
//! (`c_tests/render_common.c`); `W × H` is the field's samples, `n` the number of
//! ray classes the map holds:
//!
//! | map (`hfcast.method`) | `vkFormat` | texture | levels |
//! |---|---|---|---|
//! | `heights` | `R32_SFLOAT` (100) | `W × H` | 1 |
//! | `maxmip` | `R32_SFLOAT` (100) | `P × Q` (see below) | the pyramid's |
//! | `safety`, directional | `R8_UINT` (13) | `W × nH` (texel `(i, n·j + slot)`) | 1 |
//! | `safety`, isotropic | `R8_UINT` (13) | `W × H` | 1 |
//! | `cc` | `R8G8_UINT` (20) `[r, s]` | `W × nH` | 1 |
//! | `cone` | `R32G32_SFLOAT` (103) `[top, ratio]` | `(W−1) × (H−1)` | 1 |
//! | `relaxed` | `R32_SFLOAT` (100) | `W × H` | 1 |
//! | `qdm` | `R32G32B32A32_SFLOAT` (109) `[a, b, c, h]` | `(W−1) × (H−1)` | 1 |
//! | `radius` | `R8_UINT` (13) | `W × H` | 1 |
//!
//! **The pyramid as mip levels.** The maximum-mipmap pyramid (`crate::maxmip`) halves
//! each level rounding up ((W−1) × (H−1), then ⌈·/2⌉ down to 1 × 1); KTX mip level `k`
//! of a `P × Q` texture is `max(1, ⌊P/2^k⌋) × max(1, ⌊Q/2^k⌋)`, and at most
//! `⌊log₂ max(P, Q)⌋ + 1` levels. So `P × Q` are the next powers of two of
//! `(W−1) × (H−1)` (the same sizes when those are powers of two, as for the usual
//! `2^k + 1` height maps): pyramid level `k` sits in the top-left corner of mip level `k`
//! and the rest is `−∞`, the maximum of nothing, so every mip level is still the
//! maximum of the 2 × 2 texels under it.
//!
//! **Layout** (KTX 2.0 spec): identifier, header (`vkFormat`, `typeSize`,
//! `pixelWidth/Height`, depth 0, layers 0, faces 1, `levelCount`, supercompression 0),
//! index, level index (level 0 first), a Basic Data Format Descriptor matching the
//! format (RGBSDA; float formats BT.709 / linear, integer formats unspecified, as the
//! spec asks), key/value data (sorted by key, each entry padded to 4 bytes), then the
//! levels smallest first, each aligned to `lcm(texel size, 4)`. Little-endian.
//!
//! **Metadata** (NUL-terminated UTF-8 strings): `KTXwriter` (`hfcast <version>`),
//! `hfcast.method` (the map name above), `hfcast.version` (the crate version that
//! wrote it), `hfcast.field` (`WxH`, the field's samples), `hfcast.fingerprint` (16
//! lower-case hex digits, `crate::mapdesc::fingerprint` of the heights baked from;
//! written when the description has one, optional on reading), and for the safety-distance,
//! cylinder–cone and radius maps `hfcast.cap` (the bake's cap), `hfcast.ray_classes`
//! (`x+,x-,y+,y-`, those the map holds) and `hfcast.ray_set` (`all`: every ray of each
//! class; `lowered:E`: the radius bake's tolerance `E`; `exterior`, `angle:A` or
//! `exterior,angle:A`: the safety and cylinder–cone maps' [`Rays`]); `hfcast.variant`
//! (`directional` / `isotropic`) for the safety map.

use core::fmt::{self, Write as _};

use crate::field::MAX_SIDE;
use crate::rayset::Rays;
use crate::scene::RayClasses;

/// The 12-byte file identifier, `«KTX 20»\r\n\x1A\n`.
pub const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// Most levels a file holds (the pyramid of a field `2^24` samples wide).
pub const MAX_LEVELS: usize = 25;

/// The `KTXwriter` value of the files [`write()`] writes.
pub const WRITER: &str = concat!("hfcast ", env!("CARGO_PKG_VERSION"));

/// Bytes of the identifier, header and index: where the level index starts.
const HEADER_LEN: usize = 80;

/// Bytes of one level index entry.
const LEVEL_ENTRY_LEN: usize = 24;

named_enum! {
    /// The Vulkan formats of the maps, by their `VkFormat` values.
    pub enum Format: u32 {
        /// `VK_FORMAT_R8_UINT`.
        R8Uint = 13 => "R8_UINT" ((1, 1)),
        /// `VK_FORMAT_R8G8_UINT`.
        R8G8Uint = 20 => "R8G8_UINT" ((2, 1)),
        /// `VK_FORMAT_R32_SFLOAT`.
        R32Sfloat = 100 => "R32_SFLOAT" ((1, 4)),
        /// `VK_FORMAT_R32G32_SFLOAT`.
        R32G32Sfloat = 103 => "R32G32_SFLOAT" ((2, 4)),
        /// `VK_FORMAT_R32G32B32A32_SFLOAT`.
        R32G32B32A32Sfloat = 109 => "R32G32B32A32_SFLOAT" ((4, 4)),
    }
    /// `(channels per texel, bytes per channel)`: 8-bit unsigned integers or 32-bit
    /// floats.
    pub fn layout(self) -> (usize, usize);
}

impl Format {
    /// Channels per texel.
    pub fn channels(self) -> usize {
        self.layout().0
    }

    /// Whether the channels are 32-bit floats (else 8-bit unsigned integers).
    pub fn is_float(self) -> bool {
        self.type_size() == 4
    }

    /// Bytes per channel: the header's `typeSize`.
    pub fn type_size(self) -> usize {
        self.layout().1
    }

    /// Bytes per texel.
    pub fn texel_size(self) -> usize {
        self.channels() * self.type_size()
    }

    /// What every level's byte offset is a multiple of: `lcm(texel size, 4)`.
    fn alignment(self) -> usize {
        self.texel_size().max(4)
    }
}

/// What a map kind's texture holds ([`MapKind::info`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MapInfo {
    /// The Vulkan format of the map's texture.
    pub format: Format,
    /// The bake's default cap, for the maps baked for a cap, ray classes and a ray set
    /// (the safety distances, cylinder–cone shapes and radii, which the metadata then
    /// records); `None` for the others.
    pub default_cap: Option<u8>,
}

/// A map without a cap or ray classes, in `format`.
const fn plain(format: Format) -> MapInfo {
    MapInfo {
        format,
        default_cap: None,
    }
}

/// A map baked for a cap (default `cap`) and ray classes, in `format`.
const fn with_rays(format: Format, cap: u8) -> MapInfo {
    MapInfo {
        format,
        default_cap: Some(cap),
    }
}

named_enum! {
    /// Which baked map a file holds, with its texture's format and default cap.
    pub enum MapKind: u32 {
        /// The height field itself (`f32` samples).
        Heights = 0 => "heights" (plain(Format::R32Sfloat)),
        /// The maximum-mipmap pyramid.
        MaxMip = 1 => "maxmip" (plain(Format::R32Sfloat)),
        /// The directional safety-distance map (a row block per ray class).
        Safety = 2 => "safety" (with_rays(Format::R8Uint, u8::MAX)),
        /// The isotropic safety-distance map (one byte per texel).
        SafetyIsotropic = 3 => "safety-isotropic" (with_rays(Format::R8Uint, u8::MAX)),
        /// The cylinder–cone map.
        Cc = 4 => "cc" (with_rays(Format::R8G8Uint, 64)),
        /// The cone map.
        Cone = 5 => "cone" (plain(Format::R32G32Sfloat)),
        /// The relaxed cone map.
        Relaxed = 6 => "relaxed" (plain(Format::R32Sfloat)),
        /// The quadratic displacement map.
        Qdm = 7 => "qdm" (plain(Format::R32G32B32A32Sfloat)),
        /// The safety-radius map.
        Radius = 8 => "radius" (with_rays(Format::R8Uint, u8::MAX)),
    }
    /// The map's texture format and default cap.
    pub fn info(self) -> MapInfo;
}

impl MapKind {
    /// The `hfcast.method` value: the map's [`name`](Self::name), but `safety` for
    /// both safety-distance variants (`hfcast.variant` tells them apart).
    pub fn method(self) -> &'static str {
        match self {
            MapKind::SafetyIsotropic => "safety",
            k => k.name(),
        }
    }

    /// The Vulkan format of the map's texture.
    pub fn format(self) -> Format {
        self.info().format
    }

    /// Whether the map was baked for a cap, ray classes and a ray set (the safety
    /// distances, cylinder–cone shapes and radii), which the metadata then records.
    pub fn has_rays(self) -> bool {
        self.info().default_cap.is_some()
    }

    /// The bake's default cap: 255 for safety distances and radii, 64 for the
    /// cylinder–cone shapes, 0 for maps without one.
    pub fn default_cap(self) -> u8 {
        self.info().default_cap.unwrap_or(0)
    }
}

/// A baked map to store: which map, of which field, baked how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Desc {
    /// Which map.
    pub map: MapKind,
    /// The field's samples along x (2 to `MAX_SIDE`).
    pub width: u32,
    /// The field's samples along y (2 to `MAX_SIDE`).
    pub height: u32,
    /// The bake's cap (safety distances, cylinder–cone shapes, radii; else ignored).
    pub cap: u8,
    /// The ray classes the map holds (directional safety and cylinder–cone maps: its
    /// rows; isotropic safety: the classes minimised over; radius: always all four).
    pub classes: RayClasses,
    /// The radius bake's tolerance (grid units, finite, ≥ 0; else ignored): the ray
    /// set is the rays meeting the surface lowered by it (`lowered:E`), 0 is `all`.
    pub tolerance: f32,
    /// The rays the safety-distance and cylinder–cone maps are baked for (else
    /// ignored): `exterior`, `angle:A`, both (`exterior,angle:A`), or `all`. Their
    /// marches check every ray against it ([`Rays::holds`]).
    pub rays: Rays,
    /// The fingerprint of the heights the map was baked from
    /// ([`crate::mapdesc::fingerprint`]; `hfcast.fingerprint`, 16 hex digits), if known.
    pub fingerprint: Option<u64>,
}

impl Desc {
    /// The map `map` of a `width × height` field with the bake's defaults: its default
    /// cap ([`MapKind::default_cap`]), every ray class, tolerance 0.
    pub fn new(map: MapKind, width: u32, height: u32) -> Desc {
        Desc {
            map,
            width,
            height,
            cap: map.default_cap(),
            classes: RayClasses::ALL,
            tolerance: 0.0,
            rays: Rays::ALL,
            fingerprint: None,
        }
    }

    /// The description with the fields its map ignores set to their defaults (what
    /// [`View::desc`] reads back).
    pub fn normalized(self) -> Desc {
        let mut d = Desc::new(self.map, self.width, self.height);
        d.fingerprint = self.fingerprint;
        if self.map.has_rays() {
            d.cap = self.cap;
        }
        if matches!(
            self.map,
            MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Cc
        ) {
            d.classes = RayClasses(self.classes.0 & RayClasses::ALL.0);
            d.rays = self.rays;
        }
        if self.map == MapKind::Radius {
            d.tolerance = self.tolerance;
        }
        d
    }
}

/// Why a file could not be written or read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ktx2Error {
    /// The description is invalid: a field side outside 2 to `MAX_SIDE`, no ray class
    /// for a map of class rows, or a tolerance that is negative or not finite.
    BadDesc,
    /// The baked data holds fewer elements than the map.
    DataTooShort {
        /// Elements needed (`f32`s or bytes).
        needed: usize,
    },
    /// The baked data is of the wrong element type (`f32` for an 8-bit map or back).
    WrongData,
    /// The output buffer is too small.
    OutputTooShort {
        /// Elements needed (bytes of the file, or elements of the map).
        needed: usize,
    },
    /// The bytes end before a part of the file its header or index points to (a
    /// truncated file, or an offset past the end).
    Truncated,
    /// Not a KTX 2 file: the identifier is wrong.
    BadIdentifier,
    /// A KTX 2 feature this reader does not handle: another format, 1D or 3D, arrays,
    /// cube maps, supercompression.
    Unsupported,
    /// The header, level index, data format descriptor or key/value data break a rule
    /// of the KTX 2 spec (which one is said).
    Invalid(&'static str),
    /// The hfcast metadata is missing, malformed or disagrees with the header (which
    /// key is said).
    BadMetadata(&'static str),
}

impl fmt::Display for Ktx2Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ktx2Error::BadDesc => write!(f, "invalid map description"),
            Ktx2Error::DataTooShort { needed } => {
                write!(f, "baked data too short: {needed} elements needed")
            }
            Ktx2Error::WrongData => write!(f, "baked data of the wrong element type"),
            Ktx2Error::OutputTooShort { needed } => {
                write!(f, "output too short: {needed} elements needed")
            }
            Ktx2Error::Truncated => write!(f, "truncated KTX2 file"),
            Ktx2Error::BadIdentifier => write!(f, "not a KTX2 file (bad identifier)"),
            Ktx2Error::Unsupported => write!(f, "unsupported KTX2 feature"),
            Ktx2Error::Invalid(what) => write!(f, "invalid KTX2 file: {what}"),
            Ktx2Error::BadMetadata(key) => write!(f, "bad hfcast metadata: {key}"),
        }
    }
}

/// The baked map to write: the slice its bake filled.
#[derive(Clone, Copy, Debug)]
pub enum Data<'a> {
    /// An 8-bit map (safety, cylinder–cone, radius).
    U8(&'a [u8]),
    /// A float map (heights, pyramid, cone, relaxed, QDM).
    F32(&'a [f32]),
}

/// Where [`View::read_map`] puts the baked map.
#[derive(Debug)]
pub enum DataMut<'a> {
    /// An 8-bit map.
    U8(&'a mut [u8]),
    /// A float map.
    F32(&'a mut [f32]),
}

/// The texture a map is stored as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Texture {
    format: Format,
    /// Level 0 texels: the header's `pixelWidth`, `pixelHeight`.
    pixel: [u32; 2],
    levels: u32,
    /// The map's level 0 texels (smaller than `pixel` only for a padded pyramid).
    base: [u32; 2],
    /// Whether the map halves its levels rounding up (the pyramid).
    pyramid: bool,
}

impl Texture {
    /// The texture of `desc`'s map.
    fn of(desc: &Desc) -> Result<Texture, Ktx2Error> {
        let ok = |n: u32| (2..=MAX_SIDE).contains(&n);
        if !ok(desc.width) || !ok(desc.height) {
            return Err(Ktx2Error::BadDesc);
        }
        let d = desc.normalized();
        let (w, h) = (d.width, d.height);
        let rows = d.classes.count();
        let class_rows = matches!(d.map, MapKind::Safety | MapKind::Cc);
        let bad_rays = d.rays.validate().is_err();
        if (class_rows && rows == 0) || !(d.tolerance >= 0.0 && d.tolerance.is_finite()) || bad_rays
        {
            return Err(Ktx2Error::BadDesc);
        }
        let base = match d.map {
            MapKind::MaxMip | MapKind::Cone | MapKind::Qdm => [w - 1, h - 1],
            MapKind::Safety | MapKind::Cc => [w, rows * h],
            _ => [w, h],
        };
        let pyramid = d.map == MapKind::MaxMip;
        let pixel = if pyramid {
            base.map(u32::next_power_of_two)
        } else {
            base
        };
        let levels = if pyramid {
            pixel[0].max(pixel[1]).trailing_zeros() + 1
        } else {
            1
        };
        Ok(Texture {
            format: d.map.format(),
            pixel,
            levels,
            base,
            pyramid,
        })
    }

    /// Texels of KTX level `k`.
    fn dims(&self, k: u32) -> [u32; 2] {
        self.pixel.map(|n| (n >> k).max(1))
    }

    /// Texels of the map's level `k`: the pyramid's ⌈·/2^k⌉, else level 0.
    fn map_dims(&self, k: u32) -> [u32; 2] {
        if self.pyramid {
            self.base
                .map(|n| ((u64::from(n) + (1 << k) - 1) >> k) as u32)
        } else {
            self.base
        }
    }

    /// Bytes of KTX level `k`.
    fn level_len(&self, k: u32) -> usize {
        let [w, h] = self.dims(k);
        w as usize * h as usize * self.format.texel_size()
    }

    /// Elements (channels) of the map's level `k`.
    fn map_level_len(&self, k: u32) -> usize {
        let [w, h] = self.map_dims(k);
        w as usize * h as usize * self.format.channels()
    }

    /// Elements of the whole map.
    fn map_len(&self) -> usize {
        (0..self.levels).map(|k| self.map_level_len(k)).sum()
    }
}

/// The metadata of a file: `(key, value)` sorted by key.
type Metadata = heapless::Vec<(&'static str, heapless::String<96>), 9>;

/// A metadata value from its display form (always fits: the longest is a ray set with
/// a tiny angle, under 80 bytes).
fn text(v: impl fmt::Display) -> heapless::String<96> {
    let mut s = heapless::String::new();
    let _ = write!(s, "{v}");
    s
}

/// The names of the ray classes of `set`, comma-separated in class order
/// (`x+,x-,y+,y-` for all four; the `hfcast shader --rays` syntax).
pub fn class_names(set: RayClasses) -> heapless::String<16> {
    let mut s = heapless::String::new();
    for (bit, name) in CLASS_NAMES.iter().enumerate() {
        if set.0 & (1 << bit) != 0 {
            if !s.is_empty() {
                let _ = s.push(',');
            }
            let _ = s.push_str(name);
        }
    }
    s
}

/// The ray-class set named by `list` ([`class_names`]'s form); `None` for an unknown
/// or repeated name.
pub fn parse_class_names(list: &str) -> Option<RayClasses> {
    let mut set = RayClasses::NONE;
    for word in list.split(',').filter(|w| !w.is_empty()) {
        let bit = CLASS_NAMES.iter().position(|n| *n == word.trim())?;
        if set.0 & (1 << bit) != 0 {
            return None;
        }
        set = RayClasses(set.0 | 1 << bit);
    }
    Some(set)
}

/// The class names in class order (bit `1 << class`).
const CLASS_NAMES: [&str; 4] = ["x+", "x-", "y+", "y-"];

/// The metadata [`write()`] stores for `d` (normalized), sorted by key.
fn metadata(d: &Desc) -> Metadata {
    let mut m = Metadata::new();
    let mut put = |k: &'static str, v: heapless::String<96>| {
        let _ = m.push((k, v));
    };
    put("KTXwriter", text(WRITER));
    if d.map.has_rays() {
        put("hfcast.cap", text(d.cap));
    }
    put(
        "hfcast.field",
        text(format_args!("{}x{}", d.width, d.height)),
    );
    if let Some(f) = d.fingerprint {
        put("hfcast.fingerprint", text(format_args!("{f:016x}")));
    }
    put("hfcast.method", text(d.map.method()));
    if d.map.has_rays() {
        put("hfcast.ray_classes", text(class_names(d.classes)));
        let set = if d.tolerance > 0.0 {
            text(format_args!("lowered:{}", d.tolerance))
        } else {
            text(d.rays)
        };
        put("hfcast.ray_set", set);
    }
    match d.map {
        MapKind::Safety => put("hfcast.variant", text("directional")),
        MapKind::SafetyIsotropic => put("hfcast.variant", text("isotropic")),
        _ => {}
    }
    put("hfcast.version", text(env!("CARGO_PKG_VERSION")));
    m
}

/// `n` rounded up to a multiple of `a`.
fn align(n: usize, a: usize) -> usize {
    n.div_ceil(a) * a
}

/// Bytes of the data format descriptor of `f` (its total size field included).
fn dfd_len(f: Format) -> usize {
    4 + 24 + 16 * f.channels()
}

/// Bytes of a key/value entry, its length field and padding included.
fn entry_len(key: &str, value: &str) -> usize {
    4 + align(key.len() + value.len() + 2, 4)
}

/// Where everything of a file lies.
struct Plan {
    tex: Texture,
    meta: Metadata,
    dfd: usize,
    kvd: usize,
    kvd_len: usize,
    /// Byte offset of each level.
    levels: [usize; MAX_LEVELS],
    total: usize,
}

impl Plan {
    fn of(desc: &Desc) -> Result<Plan, Ktx2Error> {
        let tex = Texture::of(desc)?;
        let meta = metadata(&desc.normalized());
        let dfd = HEADER_LEN + LEVEL_ENTRY_LEN * tex.levels as usize;
        let kvd = dfd + dfd_len(tex.format);
        let kvd_len = meta.iter().map(|(k, v)| entry_len(k, v)).sum::<usize>();
        let mut levels = [0; MAX_LEVELS];
        let mut at = kvd + kvd_len;
        for k in (0..tex.levels).rev() {
            at = align(at, tex.format.alignment());
            levels[k as usize] = at;
            at = at.checked_add(tex.level_len(k)).ok_or(Ktx2Error::BadDesc)?;
        }
        Ok(Plan {
            tex,
            meta,
            dfd,
            kvd,
            kvd_len,
            levels,
            total: at,
        })
    }
}

/// Bytes of the file of `desc` (what [`write()`] needs).
pub fn len(desc: &Desc) -> Result<usize, Ktx2Error> {
    Ok(Plan::of(desc)?.total)
}

/// Elements (`f32`s or bytes, [`Data`]) of the baked map of `desc`: what [`write()`]
/// reads and [`View::read_map`] writes (for the pyramid all its levels, as the bake
/// lays them out).
pub fn map_len(desc: &Desc) -> Result<usize, Ktx2Error> {
    Ok(Texture::of(desc)?.map_len())
}

/// Little-endian writes at byte `at`.
fn put_u32(out: &mut [u8], at: usize, v: u32) {
    out[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

fn put_u64(out: &mut [u8], at: usize, v: usize) {
    out[at..at + 8].copy_from_slice(&(v as u64).to_le_bytes());
}

/// Writes the data format descriptor of `f` at `out[at..]`: one Basic block (RGBSDA,
/// one sample per channel).
fn put_dfd(out: &mut [u8], at: usize, f: Format) {
    let (block, n) = (dfd_len(f) - 4, f.channels());
    put_u32(out, at, dfd_len(f) as u32);
    put_u32(out, at + 4, 0); // vendor 0 (Khronos), descriptor type 0 (Basic)
    put_u32(out, at + 8, 2 | (block as u32) << 16); // version 2, block size
                                                    // Colour model RGBSDA; float formats BT.709 primaries and linear transfer, integer
                                                    // formats unspecified (the spec asks so); flags 0 (straight alpha).
    let space = u8::from(f.is_float());
    out[at + 12..at + 16].copy_from_slice(&[1, space, space, 0]);
    // texelBlockDimension 0..3 = 0 (1 × 1 × 1 × 1); bytesPlane0 = texel size.
    out[at + 20] = f.texel_size() as u8;
    let bits = 8 * f.type_size();
    let (qualifiers, lower, upper) = if f.is_float() {
        (0xC0, (-1.0f32).to_bits(), 1.0f32.to_bits()) // FLOAT | SIGNED, [−1, 1]
    } else {
        (0, 0, 1) // unsigned integers
    };
    for c in 0..n {
        let s = at + 28 + 16 * c;
        out[s..s + 2].copy_from_slice(&((c * bits) as u16).to_le_bytes());
        out[s + 2] = (bits - 1) as u8;
        out[s + 3] = c as u8 | qualifiers; // channel R, G, B, then A = 15
        if c == 3 {
            out[s + 3] = 15 | qualifiers;
        }
        put_u32(out, s + 8, lower);
        put_u32(out, s + 12, upper);
    }
}

impl Data<'_> {
    /// Elements held.
    fn len(&self) -> usize {
        match self {
            Data::U8(d) => d.len(),
            Data::F32(d) => d.len(),
        }
    }

    /// Writes elements `from..from + n` as little-endian bytes to the start of `out`.
    fn put(&self, from: usize, n: usize, out: &mut [u8]) {
        match self {
            Data::U8(d) => out[..n].copy_from_slice(&d[from..from + n]),
            Data::F32(d) => {
                for (o, v) in out.chunks_exact_mut(4).zip(&d[from..from + n]) {
                    o.copy_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
}

impl DataMut<'_> {
    fn len(&self) -> usize {
        match self {
            DataMut::U8(d) => d.len(),
            DataMut::F32(d) => d.len(),
        }
    }

    /// Reads `n` elements from the little-endian bytes `src` into elements `to..`.
    fn get(&mut self, to: usize, n: usize, src: &[u8]) {
        match self {
            DataMut::U8(d) => d[to..to + n].copy_from_slice(&src[..n]),
            DataMut::F32(d) => {
                for (v, b) in d[to..to + n].iter_mut().zip(src.chunks_exact(4)) {
                    *v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                }
            }
        }
    }
}

/// Whether `data`'s element type is the format's.
fn matches_type(float: bool, format: Format) -> Result<(), Ktx2Error> {
    if float == format.is_float() {
        Ok(())
    } else {
        Err(Ktx2Error::WrongData)
    }
}

/// Writes the KTX 2 file of the map `data` described by `desc` into `out` (at least
/// [`len`] bytes; the file is `out[..len]`). `data` is the slice the bake filled, at
/// least [`map_len`] elements of the map's type (`f32` for float formats, bytes for
/// 8-bit ones). Writes nothing on error.
pub fn write(desc: &Desc, data: Data, out: &mut [u8]) -> Result<usize, Ktx2Error> {
    let plan = Plan::of(desc)?;
    let tex = plan.tex;
    matches_type(matches!(data, Data::F32(_)), tex.format)?;
    let needed = tex.map_len();
    if data.len() < needed {
        return Err(Ktx2Error::DataTooShort { needed });
    }
    if out.len() < plan.total {
        return Err(Ktx2Error::OutputTooShort { needed: plan.total });
    }
    let out = &mut out[..plan.total];
    out.fill(0);
    out[..12].copy_from_slice(&IDENTIFIER);
    let f = tex.format;
    let header = [
        f as u32,
        f.type_size() as u32,
        tex.pixel[0],
        tex.pixel[1],
        0, // pixelDepth
        0, // layerCount
        1, // faceCount
        tex.levels,
        0, // supercompressionScheme
        plan.dfd as u32,
        dfd_len(f) as u32,
        plan.kvd as u32,
        plan.kvd_len as u32,
    ];
    for (i, v) in header.into_iter().enumerate() {
        put_u32(out, 12 + 4 * i, v);
    }
    // sgdByteOffset and sgdByteLength stay 0.
    for k in 0..tex.levels {
        let at = HEADER_LEN + LEVEL_ENTRY_LEN * k as usize;
        let (offset, len) = (plan.levels[k as usize], tex.level_len(k));
        put_u64(out, at, offset);
        put_u64(out, at + 8, len);
        put_u64(out, at + 16, len);
    }
    put_dfd(out, plan.dfd, f);
    let mut at = plan.kvd;
    for (key, value) in &plan.meta {
        put_u32(out, at, (key.len() + value.len() + 2) as u32);
        out[at + 4..at + 4 + key.len()].copy_from_slice(key.as_bytes());
        let v = at + 4 + key.len() + 1;
        out[v..v + value.len()].copy_from_slice(value.as_bytes());
        at += entry_len(key, value);
    }
    let mut from = 0;
    for k in 0..tex.levels {
        let level = &mut out[plan.levels[k as usize]..][..tex.level_len(k)];
        put_level(&tex, k, &data, from, level);
        from += tex.map_level_len(k);
    }
    Ok(plan.total)
}

/// Writes the map's level `k` (elements `from..` of `data`) into KTX level `level`:
/// row by row, the texels past the map's (a padded pyramid) `−∞`.
fn put_level(tex: &Texture, k: u32, data: &Data, from: usize, level: &mut [u8]) {
    let f = tex.format;
    let ([w, h], [kw, _]) = (tex.map_dims(k), tex.dims(k));
    let (row, ktx_row) = (w as usize * f.channels(), kw as usize * f.texel_size());
    let pad = f32::NEG_INFINITY.to_le_bytes();
    for (j, dst) in level.chunks_exact_mut(ktx_row).enumerate() {
        let texels = if j < h as usize {
            data.put(from + j * row, row, dst);
            w as usize * f.texel_size()
        } else {
            0
        };
        if f.is_float() {
            for p in dst[texels..].chunks_exact_mut(4) {
                p.copy_from_slice(&pad);
            }
        }
    }
}

// ---------------------------------------------------------------------------------
// Reader
// ---------------------------------------------------------------------------------

/// A validated KTX 2 file over caller-owned bytes ([`read`]).
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    bytes: &'a [u8],
    format: Format,
    pixel: [u32; 2],
    levels: u32,
    kvd: &'a [u8],
}

/// Little-endian reads at byte `at` (callers check the bounds first).
fn get_u32(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn get_u64(b: &[u8], at: usize) -> u64 {
    u64::from(get_u32(b, at)) | u64::from(get_u32(b, at + 4)) << 32
}

/// `bytes[at..at + len]`, or `Truncated`.
fn section(bytes: &[u8], at: u64, len: u64) -> Result<&[u8], Ktx2Error> {
    let end = at.checked_add(len).ok_or(Ktx2Error::Truncated)?;
    let (at, end) = (usize::try_from(at), usize::try_from(end));
    match (at, end) {
        (Ok(at), Ok(end)) if end <= bytes.len() => Ok(&bytes[at..end]),
        _ => Err(Ktx2Error::Truncated),
    }
}

/// `Invalid(what)` unless `ok`.
fn require(ok: bool, what: &'static str) -> Result<(), Ktx2Error> {
    if ok {
        Ok(())
    } else {
        Err(Ktx2Error::Invalid(what))
    }
}

/// Validates `bytes` as a KTX 2 file of one of the [`Format`]s, 2D, without arrays,
/// faces or supercompression: the identifier, the header, the index, the level index
/// (every level inside the bytes, of its size, aligned), the data format descriptor
/// (a Basic block matching the format) and the key/value data (well formed, sorted,
/// unique keys). Never panics; the metadata is checked by [`View::desc`].
pub fn read(bytes: &[u8]) -> Result<View<'_>, Ktx2Error> {
    if bytes.len() < HEADER_LEN {
        return Err(
            if bytes.starts_with(&IDENTIFIER) || IDENTIFIER.starts_with(bytes) {
                Ktx2Error::Truncated
            } else {
                Ktx2Error::BadIdentifier
            },
        );
    }
    if bytes[..12] != IDENTIFIER {
        return Err(Ktx2Error::BadIdentifier);
    }
    let h = |i: usize| get_u32(bytes, 12 + 4 * i);
    let format = Format::from_u32(h(0)).ok_or(Ktx2Error::Unsupported)?;
    require(h(1) as usize == format.type_size(), "typeSize")?;
    let pixel = [h(2), h(3)];
    require(pixel[0] > 0, "pixelWidth is 0")?;
    let (depth, layers, faces, scheme) = (h(4), h(5), h(6), h(8));
    if pixel[1] == 0 || depth != 0 || layers != 0 || faces != 1 || scheme != 0 {
        return Err(Ktx2Error::Unsupported);
    }
    let levels = h(7).max(1);
    let most = 32 - pixel[0].max(pixel[1]).leading_zeros();
    require(levels <= most, "levelCount above log2(size) + 1")?;
    let [dfd_at, dfd_len_, kvd_at, kvd_len] = [h(9), h(10), h(11), h(12)].map(u64::from);
    let (sgd_at, sgd_len) = (get_u64(bytes, 64), get_u64(bytes, 72));
    require(sgd_at == 0 && sgd_len == 0, "supercompression global data")?;
    let index_end = HEADER_LEN + LEVEL_ENTRY_LEN * levels as usize;
    section(bytes, HEADER_LEN as u64, (index_end - HEADER_LEN) as u64)?;
    require(
        dfd_at >= index_end as u64 && dfd_at % 4 == 0,
        "dfdByteOffset",
    )?;
    let dfd = section(bytes, dfd_at, dfd_len_)?;
    check_dfd(dfd, format)?;
    let kvd = if kvd_len == 0 {
        require(kvd_at == 0, "kvdByteOffset of empty key/value data")?;
        &[][..]
    } else {
        require(kvd_at == dfd_at + dfd_len_, "kvdByteOffset")?;
        section(bytes, kvd_at, kvd_len)?
    };
    check_kvd(kvd)?;
    let data_start = dfd_at + dfd_len_ + kvd_len;
    let view = View {
        bytes,
        format,
        pixel,
        levels,
        kvd,
    };
    for k in 0..levels {
        let at = HEADER_LEN + LEVEL_ENTRY_LEN * k as usize;
        let (offset, len, full) = (
            get_u64(bytes, at),
            get_u64(bytes, at + 8),
            get_u64(bytes, at + 16),
        );
        section(bytes, offset, len)?;
        let [w, h] = view.level_dims(k);
        let expected = u64::from(w) * u64::from(h) * format.texel_size() as u64;
        require(
            len == full,
            "byteLength differs from uncompressedByteLength",
        )?;
        require(len == expected, "level byteLength is not the level's size")?;
        require(offset % format.alignment() as u64 == 0, "level misaligned")?;
        require(offset >= data_start, "level overlaps the header")?;
    }
    Ok(view)
}

/// Checks the data format descriptor: one Basic block (version 2, RGBSDA, 1 × 1 texel
/// blocks, one plane of the texel size) with one sample per channel of `f` (bit
/// offsets and lengths, channel ids, the float and signed qualifiers of `f`).
fn check_dfd(dfd: &[u8], f: Format) -> Result<(), Ktx2Error> {
    const WHAT: &str = "data format descriptor does not match vkFormat";
    require(dfd.len() == dfd_len(f), WHAT)?;
    require(get_u32(dfd, 0) as usize == dfd.len(), "dfdTotalSize")?;
    let block = get_u32(dfd, 8);
    require(
        get_u32(dfd, 4) == 0 && block == (2 | ((dfd.len() - 4) as u32) << 16),
        WHAT,
    )?;
    require(dfd[12] == 1 && dfd[16..20] == [0; 4], WHAT)?;
    require(
        dfd[20] as usize == f.texel_size() && dfd[21..28] == [0; 7],
        WHAT,
    )?;
    let bits = 8 * f.type_size();
    for c in 0..f.channels() {
        let s = 28 + 16 * c;
        let id = if c == 3 { 15 } else { c as u8 };
        let qualifiers = if f.is_float() { 0xC0 } else { 0 };
        let offset = u16::from_le_bytes([dfd[s], dfd[s + 1]]) as usize;
        require(offset == c * bits && dfd[s + 2] as usize == bits - 1, WHAT)?;
        require(dfd[s + 3] & 0xCF == id | qualifiers, WHAT)?;
    }
    Ok(())
}

/// The key/value entries of `kvd` in file order; stops at the first malformed one
/// (which [`read`] rejects).
#[derive(Clone, Debug)]
pub struct KeyValues<'a> {
    rest: &'a [u8],
}

impl<'a> Iterator for KeyValues<'a> {
    type Item = (&'a str, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        let (entry, rest) = split_entry(self.rest).ok()??;
        self.rest = rest;
        Some(entry)
    }
}

/// The first entry of `kvd` (`None` when empty) and what follows it.
#[allow(clippy::type_complexity)]
fn split_entry(kvd: &[u8]) -> Result<Option<((&str, &[u8]), &[u8])>, Ktx2Error> {
    if kvd.is_empty() {
        return Ok(None);
    }
    const WHAT: &str = "key/value data";
    require(kvd.len() >= 4, WHAT)?;
    let n = get_u32(kvd, 0) as usize;
    require(n >= 2 && n <= kvd.len() - 4, WHAT)?;
    let pair = &kvd[4..4 + n];
    let nul = pair
        .iter()
        .position(|&b| b == 0)
        .ok_or(Ktx2Error::Invalid(WHAT))?;
    let key = core::str::from_utf8(&pair[..nul]).map_err(|_| Ktx2Error::Invalid(WHAT))?;
    require(!key.is_empty(), WHAT)?;
    let next = align(4 + n, 4);
    require(next <= kvd.len(), WHAT)?;
    Ok(Some(((key, &pair[nul + 1..]), &kvd[next..])))
}

/// Checks the key/value data: well-formed entries filling it exactly, keys sorted
/// and unique.
fn check_kvd(mut kvd: &[u8]) -> Result<(), Ktx2Error> {
    let mut last: Option<&str> = None;
    while let Some(((key, _), rest)) = split_entry(kvd)? {
        require(last.is_none_or(|l| l < key), "keys not sorted or repeated")?;
        last = Some(key);
        kvd = rest;
    }
    Ok(())
}

impl<'a> View<'a> {
    /// The texture's format.
    pub fn format(&self) -> Format {
        self.format
    }

    /// Level 0 texels: `[pixelWidth, pixelHeight]`.
    pub fn pixel_size(&self) -> [u32; 2] {
        self.pixel
    }

    /// Number of levels (at least 1).
    pub fn level_count(&self) -> u32 {
        self.levels
    }

    /// Texels of level `k`: `max(1, pixel >> k)` each way.
    pub fn level_dims(&self, k: u32) -> [u32; 2] {
        self.pixel.map(|n| (n >> k).max(1))
    }

    /// The bytes of level `k` (`None` past the last level): texel rows, tightly
    /// packed, little-endian, as a GPU upload takes them.
    pub fn level(&self, k: u32) -> Option<&'a [u8]> {
        if k >= self.levels {
            return None;
        }
        let at = HEADER_LEN + LEVEL_ENTRY_LEN * k as usize;
        section(
            self.bytes,
            get_u64(self.bytes, at),
            get_u64(self.bytes, at + 8),
        )
        .ok()
    }

    /// The key/value entries, in file (sorted) order.
    pub fn key_values(&self) -> KeyValues<'a> {
        KeyValues { rest: self.kvd }
    }

    /// The value of `key`, if present, as stored (a string's NUL included).
    pub fn value(&self, key: &str) -> Option<&'a [u8]> {
        self.key_values().find(|(k, _)| *k == key).map(|(_, v)| v)
    }

    /// The value of `key` as a string (without its NUL), if present and UTF-8.
    pub fn text(&self, key: &str) -> Option<&'a str> {
        let v = self.value(key)?;
        core::str::from_utf8(v.strip_suffix(&[0]).unwrap_or(v)).ok()
    }

    /// The hfcast description of the map from the metadata ([`write()`]'s keys),
    /// checked against the header (format, size, levels). A key a map does not use
    /// reads as [`Desc::new`]'s default.
    pub fn desc(&self) -> Result<Desc, Ktx2Error> {
        let bad = Ktx2Error::BadMetadata;
        let method = self.text("hfcast.method").ok_or(bad("hfcast.method"))?;
        let field = self.text("hfcast.field").ok_or(bad("hfcast.field"))?;
        let (w, h) = field.split_once('x').ok_or(bad("hfcast.field"))?;
        let (w, h) = match (w.parse(), h.parse()) {
            (Ok(w), Ok(h)) => (w, h),
            _ => return Err(bad("hfcast.field")),
        };
        let map = match (method, self.text("hfcast.variant")) {
            ("safety", None | Some("directional")) => MapKind::Safety,
            ("safety", Some("isotropic")) => MapKind::SafetyIsotropic,
            (_, Some(_)) => return Err(bad("hfcast.variant")),
            (m, None) => MapKind::ALL
                .into_iter()
                .find(|k| k.method() == m && *k != MapKind::SafetyIsotropic)
                .ok_or(bad("hfcast.method"))?,
        };
        let mut d = Desc::new(map, w, h);
        if let Some(f) = self.text("hfcast.fingerprint") {
            let hex = f.len() == 16 && f.bytes().all(|b| b.is_ascii_hexdigit());
            let value = u64::from_str_radix(f, 16).ok().filter(|_| hex);
            d.fingerprint = Some(value.ok_or(bad("hfcast.fingerprint"))?);
        }
        if map.has_rays() {
            let cap = self.text("hfcast.cap").and_then(|c| c.parse().ok());
            d.cap = cap.ok_or(bad("hfcast.cap"))?;
            let classes = self.text("hfcast.ray_classes").and_then(parse_class_names);
            d.classes = classes.ok_or(bad("hfcast.ray_classes"))?;
            let set = self.text("hfcast.ray_set").ok_or(bad("hfcast.ray_set"))?;
            let lowered = set.strip_prefix("lowered:").map(str::parse::<f32>);
            let narrowed = (map != MapKind::Radius)
                .then(|| set.parse::<Rays>().ok())
                .flatten();
            match (set, lowered, narrowed) {
                ("all", _, _) => {}
                (_, Some(Ok(e)), _) if map == MapKind::Radius && e > 0.0 => d.tolerance = e,
                (_, _, Some(rays)) => d.rays = rays,
                _ => return Err(bad("hfcast.ray_set")),
            }
            if map == MapKind::Radius && d.classes != RayClasses::ALL {
                return Err(bad("hfcast.ray_classes"));
            }
        }
        let tex = Texture::of(&d).map_err(|_| bad("hfcast.field"))?;
        let header = (self.format, self.pixel, self.levels);
        if header != (tex.format, tex.pixel, tex.levels) {
            return Err(bad("disagrees with the header"));
        }
        Ok(d)
    }

    /// Copies the baked map out of the levels into `out`, exactly as its bake laid it
    /// out (the inverse of [`write()`]): at least [`map_len`] elements of the map's type.
    /// Writes nothing on error.
    pub fn read_map(&self, mut out: DataMut) -> Result<(), Ktx2Error> {
        let tex = Texture::of(&self.desc()?).map_err(|_| Ktx2Error::BadMetadata("field"))?;
        let f = tex.format;
        matches_type(matches!(out, DataMut::F32(_)), f)?;
        let needed = tex.map_len();
        if out.len() < needed {
            return Err(Ktx2Error::OutputTooShort { needed });
        }
        let mut to = 0;
        for k in 0..tex.levels {
            let level = self.level(k).ok_or(Ktx2Error::Truncated)?;
            let ([w, h], [kw, _]) = (tex.map_dims(k), tex.dims(k));
            let (row, ktx_row) = (w as usize * f.channels(), kw as usize * f.texel_size());
            for src in level.chunks_exact(ktx_row).take(h as usize) {
                out.get(to, row, src);
                to += row;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pyramid_levels_fit_the_mip_chain() {
        let d = Desc::new(MapKind::MaxMip, 403, 344);
        let tex = Texture::of(&d).unwrap();
        assert_eq!(tex.pixel, [512, 512]);
        assert_eq!(tex.levels, 10);
        assert_eq!(tex.map_dims(1), [201, 172]);
        assert_eq!(tex.map_dims(9), [1, 1]);
        for k in 0..tex.levels {
            let ([w, h], [kw, kh]) = (tex.map_dims(k), tex.dims(k));
            assert!(w <= kw && h <= kh, "level {k}");
        }
        let exact = Texture::of(&Desc::new(MapKind::MaxMip, 9, 5)).unwrap();
        assert_eq!((exact.pixel, exact.levels), ([8, 4], 4));
        assert_eq!(exact.map_dims(3), exact.dims(3));
    }

    #[test]
    fn small_map_round_trips() {
        let d = Desc::new(MapKind::Cc, 3, 2);
        let data: [u8; 48] = core::array::from_fn(|i| i as u8);
        let mut file = [0u8; 512];
        let n = write(&d, Data::U8(&data), &mut file).unwrap();
        assert_eq!(n, len(&d).unwrap());
        let view = read(&file[..n]).unwrap();
        assert_eq!(view.desc(), Ok(d));
        assert_eq!(view.level(0), Some(&data[..]));
        let mut back = [0u8; 48];
        view.read_map(DataMut::U8(&mut back)).unwrap();
        assert_eq!(back, data);
        assert_eq!(view.text("KTXwriter"), Some(WRITER));
        assert_eq!(view.text("hfcast.ray_classes"), Some("x+,x-,y+,y-"));
        // A map of a narrower ray set says so, and reads back with it.
        let narrowed = Desc {
            rays: "exterior,angle:45".parse().unwrap(),
            ..d
        };
        let n = write(&narrowed, Data::U8(&data), &mut file).unwrap();
        let view = read(&file[..n]).unwrap();
        assert_eq!(view.text("hfcast.ray_set"), Some("exterior,angle:45"));
        assert_eq!(view.desc(), Ok(narrowed));
        // The longest set's text: a tiny angle (printed without an exponent) and
        // occluders.
        let longest = Desc {
            rays: Rays {
                max_view_angle_deg: f32::MIN_POSITIVE,
                occluders: 0xabcdef,
                ..Rays::EXTERIOR
            },
            ..d
        };
        let n = write(&longest, Data::U8(&data), &mut file).unwrap();
        assert_eq!(read(&file[..n]).unwrap().desc(), Ok(longest));
        // A radius map keeps no such set.
        let radius = Desc {
            rays: Rays::EXTERIOR,
            ..Desc::new(MapKind::Radius, 3, 2)
        };
        assert_eq!(radius.normalized().rays, Rays::ALL);
    }

    #[test]
    fn class_names_round_trip() {
        for bits in 0..16 {
            let set = RayClasses(bits);
            assert_eq!(parse_class_names(&class_names(set)), Some(set));
        }
        assert_eq!(parse_class_names("x+,x+"), None);
        assert_eq!(parse_class_names("z+"), None);
    }
}
