//! Height maps on disk: grayscale PNGs (16-bit, 8-bit accepted) with an optional JSON
//! sidecar of the same name, as in `../shared/data` (see its README); GeoTIFF DEMs
//! ([`load_geotiff`]); raw little-endian `f32` grids ([`load_raw_f32`]). Every loaded
//! [`Map`] carries the [`WorldTransform`] to its real units when its file says them
//! (the sidecar's `h_min`/`h_max` and horizontal spacing, the GeoTIFF's pixel scale):
//! x east and y north in metres from sample (0, 0), z in metres.
//!
//! Heights are `png / 65535 × depth` in grid units, the conversion of
//! [`HeightField::from_u16`] (8-bit values are first widened exactly, `v × 257`);
//! `depth` is the relief depth in grid units.
//! The image order is kept: image row 0 (the top, north for DEMs) is grid row y = 0,
//! so y grows southwards and x eastwards.

use hfcast::rayset::Occluder;
use hfcast::{FieldError, HeightField, WorldTransform};
use std::fmt;
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

/// File name of the map bundled in the repository's `data/` folder, the default of
/// `hfcast render` and `hfcast trace`.
pub const DEFAULT_MAP: &str = "dem_jacksboro_fault_403x344.png";

/// Why a map could not be read or written.
#[derive(Debug)]
pub struct Error(pub String);

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

impl From<FieldError> for Error {
    fn from(e: FieldError) -> Self {
        Error(e.to_string())
    }
}

impl Error {
    /// An error about `path`: its message prefixed with the path.
    pub fn at(path: &Path, e: impl fmt::Display) -> Error {
        Error(format!("{}: {e}", path.display()))
    }
}

/// A loaded height map: heights in grid units, row-major, row 0 = image top = y 0.
#[derive(Clone, Debug)]
pub struct Map {
    /// Samples along x (image columns).
    pub width: u32,
    /// Samples along y (image rows).
    pub height: u32,
    /// `width × height` heights in grid units; sample (i, j) is `heights[j * width + i]`.
    pub heights: Vec<f32>,
    /// The relief depth used: a PNG value of 65535 (255 for 8-bit) is this high.
    pub depth: f32,
    /// The sidecar's `png.h_min` and `png.h_max` (the original units of the PNG's 0 and
    /// full-scale values), when there is a sidecar that has them.
    pub h_range: Option<(f64, f64)>,
    /// Grid space to the map's real units (metres), when its file gives them; else
    /// the identity.
    pub transform: WorldTransform,
    /// Where sample (0, 0) lies in the file's coordinate reference system (x, y:
    /// longitude and latitude in degrees for geographic data, metres for projected),
    /// when the file says. [`Map::transform`] keeps world (0, 0) at sample (0, 0), so
    /// `f32` world rays near the field stay precise; add this to place it on the globe.
    pub georef: Option<[f64; 2]>,
}

impl Map {
    /// The height field over [`Map::heights`] (stride = width), carrying
    /// [`Map::transform`].
    pub fn field(&self) -> HeightField<'_> {
        HeightField::new(&self.heights, self.width, self.height, self.width as usize)
            .expect("validated when the map was loaded")
            .with_transform(self.transform)
    }

    /// The relief depth (grid units) at which this map's heights have their real
    /// proportion to its horizontal spacing: `(h_max − h_min) / √(|sx · sy|)`. `None`
    /// without real units.
    pub fn real_depth(&self) -> Option<f32> {
        let (lo, hi) = self.h_range?;
        let [sx, sy] = self.transform.spacing();
        (!self.transform.is_identity() && hi > lo)
            .then(|| ((hi - lo) / (sx * sy).abs().sqrt()) as f32)
    }
}

/// Metres per degree of latitude (and of longitude at the equator), mean Earth radius.
const METRES_PER_DEGREE: f64 = 111_195.0;

/// Horizontal spacing in metres per sample `[east, north]` (north negative: row 0 is
/// the north row, so grid y grows southwards) from a spacing of `value` in `units`
/// (`degrees` at latitude `lat`, or metres); `None` for unitless textures.
fn spacing_metres(value: f64, units: &str, lat: Option<f64>) -> Option<[f64; 2]> {
    if !(value.is_finite() && value > 0.0) {
        return None;
    }
    if units.contains("degree") {
        let cos = lat.map_or(1.0, |l| l.to_radians().cos());
        let m = value * METRES_PER_DEGREE;
        Some([m * cos, -m])
    } else if units.contains("metre") || units.contains("meter") {
        Some([value, -value])
    } else {
        None
    }
}

/// The transform of a map whose grid heights are `(h − h_min) / (h_max − h_min) ×
/// depth` with sample spacing `spacing` (metres): z in metres, x east and y north from
/// sample (0, 0).
fn real_transform(spacing: [f64; 2], (lo, hi): (f64, f64), depth: f32) -> Option<WorldTransform> {
    let scale = if depth > 0.0 && hi > lo {
        (hi - lo) / f64::from(depth)
    } else {
        1.0
    };
    WorldTransform::new([0.0, 0.0], spacing, scale, lo).ok()
}

/// The sidecar's transform for a PNG loaded at `depth` (see [`real_transform`]):
/// its `png.h_min`/`png.h_max` and `horizontal_spacing`, the latitude from `georef`.
fn sidecar_transform(png_path: &Path, depth: f32) -> Option<WorldTransform> {
    let text = std::fs::read_to_string(png_path.with_extension("json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    let range = (
        json["png"]["h_min"].as_f64()?,
        json["png"]["h_max"].as_f64()?,
    );
    let spacing = &json["horizontal_spacing"];
    let georef = &json["georef"];
    let lats = ["ymin_lat_row0", "ymax_lat_lastrow"].map(|k| georef[k].as_f64());
    let lat = match lats {
        [Some(a), Some(b)] => Some(0.5 * (a + b)),
        [a, b] => a.or(b),
    };
    let s = spacing_metres(spacing["value"].as_f64()?, spacing["units"].as_str()?, lat)?;
    real_transform(s, range, depth)
}

/// Four walls one texel around `hf`, two thick, as eight occluders (each top two
/// triangles): the tops rise from the middle of the height range at the field's
/// first corner to a fifth of the range above its highest sample at the last, so rays
/// come in over them at every height and some pass under them. The walls of the
/// report's `occluder` settings and of the shader parity tests.
pub fn walls_around(hf: &HeightField) -> Vec<Occluder> {
    let (xm, ym) = (f64::from(hf.width() - 1), f64::from(hf.height() - 1));
    let zlo = f64::from(hf.min_height());
    let zr = (f64::from(hf.max_height()) - zlo).max(1e-3);
    let top = |x: f64, y: f64| zlo + 0.5 * zr + 0.35 * zr * (x / xm + y / ym);
    let (x0, x1, y0, y1) = (-3.0, xm + 3.0, -3.0, ym + 3.0);
    [
        ([x0, -1.0], [y0, y1]),
        ([xm + 1.0, x1], [y0, y1]),
        ([x0, x1], [y0, -1.0]),
        ([x0, x1], [ym + 1.0, y1]),
    ]
    .into_iter()
    .flat_map(|(x, y)| Occluder::rectangle(x, y, top))
    .collect()
}

/// The default relief depth of a `width × height` map: 0.1 × max(W, H) grid units.
pub fn default_depth(width: u32, height: u32) -> f32 {
    0.1 * width.max(height) as f32
}

/// A map found by [`list_maps`]: where it is, its size and its sidecar's height range.
#[derive(Clone, Debug)]
pub struct MapInfo {
    /// File name without the `.png` extension.
    pub name: String,
    /// Path of the PNG.
    pub path: PathBuf,
    /// Samples along x.
    pub width: u32,
    /// Samples along y.
    pub height: u32,
    /// The sidecar's `png.h_min` / `png.h_max`, if present.
    pub h_range: Option<(f64, f64)>,
}

/// `path` without `..` detours when it exists.
fn tidy(path: PathBuf) -> PathBuf {
    std::fs::canonicalize(&path).unwrap_or(path)
}

/// The shared test data folder: `$HFCAST_DATA` when set, else `../shared/data` next
/// to the workspace root (found from this crate's `CARGO_MANIFEST_DIR`).
pub fn shared_data_dir() -> PathBuf {
    match std::env::var_os("HFCAST_DATA") {
        Some(dir) => PathBuf::from(dir),
        None => tidy(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data")),
    }
}

/// The bundled default map: `data/` of the workspace this crate was built from, else
/// `data/` under the current directory. When neither exists, the first candidate (so
/// loading it reports a useful path).
pub fn bundled_map() -> PathBuf {
    let built = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(DEFAULT_MAP);
    let local = Path::new("data").join(DEFAULT_MAP);
    tidy(if !built.exists() && local.exists() {
        local
    } else {
        built
    })
}

/// Every `*.png` in [`shared_data_dir`], sorted by name (empty when the folder is
/// missing). Reads only the PNG headers and sidecars; a PNG whose header cannot be
/// read is left out ([`scan_maps`] reports it).
pub fn list_maps() -> Vec<MapInfo> {
    scan_maps(|_| true).0
}

/// The maps of [`list_maps`] whose name (file stem) `keep` accepts, sorted by name,
/// and an error for each accepted `*.png` whose header cannot be read. The files of
/// names `keep` refuses are never opened.
pub fn scan_maps(keep: impl Fn(&str) -> bool) -> (Vec<MapInfo>, Vec<Error>) {
    let Ok(entries) = std::fs::read_dir(shared_data_dir()) else {
        return (Vec::new(), Vec::new());
    };
    let mut paths: Vec<(String, PathBuf)> = entries
        .filter_map(|e| {
            let path = e.ok()?.path();
            if path.extension()? != "png" {
                return None;
            }
            let name = path.file_stem()?.to_string_lossy().into_owned();
            keep(&name).then_some((name, path))
        })
        .collect();
    paths.sort();
    let (mut maps, mut errors) = (Vec::new(), Vec::new());
    for (name, path) in paths {
        match png_reader(&path) {
            Ok(reader) => {
                let (width, height) = reader.info().size();
                maps.push(MapInfo {
                    name,
                    width,
                    height,
                    h_range: sidecar_range(&path),
                    path,
                });
            }
            Err(e) => errors.push(e),
        }
    }
    (maps, errors)
}

/// Opens a PNG and reads its header (with a memory limit large enough for any map).
fn png_reader(path: &Path) -> Result<png::Reader<BufReader<File>>, Error> {
    let file = File::open(path).map_err(|e| Error::at(path, e))?;
    let limits = png::Limits { bytes: 1 << 31 };
    png::Decoder::new_with_limits(BufReader::new(file), limits)
        .read_info()
        .map_err(|e| Error::at(path, e))
}

/// `png.h_min` and `png.h_max` from the sidecar next to `png_path`, if any.
fn sidecar_range(png_path: &Path) -> Option<(f64, f64)> {
    let text = std::fs::read_to_string(png_path.with_extension("json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some((
        json["png"]["h_min"].as_f64()?,
        json["png"]["h_max"].as_f64()?,
    ))
}

/// The sidecar's `georef.xmin_lon` and `georef.ymin_lat_row0`: sample (0, 0)'s
/// longitude and latitude.
fn sidecar_georef(png_path: &Path) -> Option<[f64; 2]> {
    let text = std::fs::read_to_string(png_path.with_extension("json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    let g = &json["georef"];
    Some([g["xmin_lon"].as_f64()?, g["ymin_lat_row0"].as_f64()?])
}

/// Loads a grayscale PNG height map (16-bit, or 8-bit) and its sidecar. `depth` is the
/// relief depth in grid units; `None` takes [`default_depth`].
pub fn load_map(path: impl AsRef<Path>, depth: Option<f32>) -> Result<Map, Error> {
    let path = path.as_ref();
    let mut reader = png_reader(path)?;
    let (width, height) = reader.info().size();
    let depth = depth.unwrap_or_else(|| default_depth(width, height));
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| Error::at(path, "image too large"))?;
    let mut buf = vec![0u8; size];
    let frame = reader
        .next_frame(&mut buf)
        .map_err(|e| Error::at(path, e))?;
    if frame.color_type != png::ColorType::Grayscale {
        return Err(Error::at(path, "not a grayscale PNG"));
    }
    let samples: Vec<u16> = match frame.bit_depth {
        png::BitDepth::Sixteen => buf
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect(),
        // Widen 8-bit codes exactly: v × 257 / 65535 = v / 255.
        png::BitDepth::Eight => buf.iter().map(|&v| u16::from(v) * 257).collect(),
        other => return Err(Error::at(path, format!("unsupported bit depth {other:?}"))),
    };
    let mut heights = vec![0f32; width as usize * height as usize];
    HeightField::from_u16(&samples, width, height, width as usize, depth, &mut heights)
        .map_err(|e| Error::at(path, e))?;
    Ok(Map {
        width,
        height,
        heights,
        depth,
        h_range: sidecar_range(path),
        transform: sidecar_transform(path, depth).unwrap_or_default(),
        georef: sidecar_georef(path),
    })
}

/// The relief depth a map is loaded at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Depth {
    /// The format's default: [`default_depth`] for PNGs, the real proportion for
    /// GeoTIFFs.
    Default,
    /// This many grid units.
    Grid(f32),
    /// The real proportion of heights to spacing ([`Map::real_depth`]); PNGs without
    /// real units fall back to [`default_depth`].
    Real,
}

/// How to find and read a map: what `--map`, `--depth`, `--nodata` and `--raw-size`
/// say on the command line.
#[derive(Clone, Debug)]
pub struct MapSpec {
    /// The file: `.png`, `.tif`/`.tiff`, or raw `f32` with [`MapSpec::raw_size`].
    pub path: PathBuf,
    /// The relief depth.
    pub depth: Depth,
    /// GeoTIFF nodata policy.
    pub nodata: Nodata,
    /// `W × H` of a raw little-endian `f32` file (which has no header).
    pub raw_size: Option<(u32, u32)>,
}

impl MapSpec {
    /// The map at `path` with the defaults.
    pub fn new(path: impl Into<PathBuf>) -> MapSpec {
        MapSpec {
            path: path.into(),
            depth: Depth::Default,
            nodata: Nodata::Refuse,
            raw_size: None,
        }
    }

    /// Reads the map.
    pub fn load(&self) -> Result<Map, Error> {
        if let Some((w, h)) = self.raw_size {
            return load_raw_f32(&self.path, w, h);
        }
        let grid = match self.depth {
            Depth::Grid(d) => Some(d),
            Depth::Default | Depth::Real => None,
        };
        let ext = self
            .path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if matches!(ext.as_deref(), Some("tif" | "tiff")) {
            let depth = match self.depth {
                Depth::Default | Depth::Real => None,
                Depth::Grid(d) => Some(d),
            };
            return load_geotiff(&self.path, depth, self.nodata);
        }
        let map = load_map(&self.path, grid)?;
        match (self.depth, map.real_depth()) {
            (Depth::Real, Some(real)) => load_map(&self.path, Some(real)),
            _ => Ok(map),
        }
    }
}

/// Loads the map at `path` by its extension: `.tif`/`.tiff` as a GeoTIFF
/// ([`load_geotiff`], nodata refused), anything else as a PNG ([`load_map`]).
pub fn load_any(path: impl AsRef<Path>, depth: Option<f32>) -> Result<Map, Error> {
    let path = path.as_ref();
    match path.extension().and_then(|e| e.to_str()) {
        Some("tif" | "tiff" | "TIF" | "TIFF") => load_geotiff(path, depth, Nodata::Refuse),
        _ => load_map(path, depth),
    }
}

/// The `width × height` map of metres `h` with sample spacing `spacing`: grid heights
/// `(h − lo) / (hi − lo) × depth` (`lo`, `hi` their range), at the real-proportion
/// depth `(hi − lo) / √|sx·sy|` when `depth` is `None`, and the transform back to
/// metres.
fn metres_map(
    metres: &[f64],
    (width, height): (u32, u32),
    spacing: [f64; 2],
    depth: Option<f32>,
) -> Result<Map, String> {
    let lo = metres.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = metres.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let real = ((hi - lo) / (spacing[0] * spacing[1]).abs().sqrt()) as f32;
    let depth = depth.unwrap_or(real);
    if !depth.is_finite() || depth < 0.0 {
        return Err(format!("bad relief depth {depth}"));
    }
    let per = if hi > lo {
        f64::from(depth) / (hi - lo)
    } else {
        0.0
    };
    let heights: Vec<f32> = metres.iter().map(|&h| ((h - lo) * per) as f32).collect();
    let transform = real_transform(spacing, (lo, hi), depth)
        .ok_or_else(|| format!("bad spacing {spacing:?}"))?;
    HeightField::new(&heights, width, height, width as usize).map_err(|e| e.to_string())?;
    Ok(Map {
        width,
        height,
        heights,
        depth,
        h_range: Some((lo, hi)),
        transform,
        georef: None,
    })
}

/// What [`load_geotiff`] does with nodata samples (the `GDAL_NODATA` tag's value, and
/// NaN).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Nodata {
    /// A map with any nodata sample is an error naming how many there are.
    Refuse,
    /// Nodata samples take this height (metres).
    Fill(f64),
    /// Nodata samples take the lowest valid height.
    FillLowest,
}

/// Loads a single-band GeoTIFF DEM (8/16/32-bit integers or 32/64-bit floats, LZW or
/// Deflate): heights in metres, the spacing from `ModelPixelScaleTag` (degrees, for a
/// geographic model (`GTModelTypeGeoKey` = 2), become metres at the centre latitude
/// from `ModelTiepointTag`). `depth` in grid units, or `None` for the real
/// proportion. Nodata samples as `nodata` says.
pub fn load_geotiff(
    path: impl AsRef<Path>,
    depth: Option<f32>,
    nodata: Nodata,
) -> Result<Map, Error> {
    use tiff::decoder::{Decoder, DecodingResult};
    use tiff::tags::Tag;
    let path = path.as_ref();
    let at = |e: &dyn fmt::Display| Error::at(path, e);
    let file = File::open(path).map_err(|e| at(&e))?;
    let mut dec = Decoder::new(BufReader::new(file)).map_err(|e| at(&e))?;
    let (width, height) = dec.dimensions().map_err(|e| at(&e))?;
    let scale = dec
        .get_tag_f64_vec(Tag::ModelPixelScaleTag)
        .map_err(|e| at(&format!("no ModelPixelScaleTag ({e}): not a GeoTIFF")))?;
    let tie = dec
        .get_tag_f64_vec(Tag::ModelTiepointTag)
        .unwrap_or_default();
    let keys = dec
        .get_tag_u16_vec(Tag::GeoKeyDirectoryTag)
        .unwrap_or_default();
    let no_value = match dec.get_tag_ascii_string(Tag::GdalNodata) {
        Ok(s) => Some(
            s.trim_matches(char::from(0))
                .trim()
                .parse::<f64>()
                .map_err(|_| at(&format!("bad GDAL_NODATA {s:?}")))?,
        ),
        Err(_) => None,
    };
    let mut metres: Vec<f64> = match dec.read_image().map_err(|e| at(&e))? {
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        _ => return Err(at(&"unsupported sample type")),
    };
    if metres.len() != width as usize * height as usize {
        return Err(at(&format!(
            "{} samples for {width} x {height}: not a single band",
            metres.len()
        )));
    }
    let missing = |h: f64| !h.is_finite() || no_value == Some(h);
    let count = metres.iter().filter(|&&h| missing(h)).count();
    if count == metres.len() {
        return Err(at(&"every sample is nodata"));
    }
    if count > 0 {
        let fill = match nodata {
            Nodata::Refuse => {
                return Err(at(&format!(
                    "{count} nodata samples (fill them: Nodata::Fill / FillLowest)"
                )))
            }
            Nodata::Fill(v) if v.is_finite() => v,
            Nodata::Fill(v) => return Err(at(&format!("nodata fill {v} is not finite"))),
            Nodata::FillLowest => metres
                .iter()
                .copied()
                .filter(|&h| !missing(h))
                .fold(f64::INFINITY, f64::min),
        };
        metres
            .iter_mut()
            .filter(|h| missing(**h))
            .for_each(|h| *h = fill);
    }
    // GTModelTypeGeoKey (1024) in the key directory (4 shorts per key after a header
    // of 4): 2 = geographic (degrees).
    let geographic = keys
        .chunks_exact(4)
        .skip(1)
        .any(|k| k[0] == 1024 && k[3] == 2);
    let (sx, sy) = match scale.as_slice() {
        [sx, sy, ..] if *sx > 0.0 && *sy > 0.0 => (*sx, *sy),
        _ => return Err(at(&format!("bad ModelPixelScaleTag {scale:?}"))),
    };
    let spacing = if geographic {
        let top = tie.get(4).copied().unwrap_or(0.0);
        let lat = top - 0.5 * sy * f64::from(height - 1);
        let cos = lat.to_radians().cos();
        [sx * METRES_PER_DEGREE * cos, -sy * METRES_PER_DEGREE]
    } else {
        [sx, -sy]
    };
    let mut map = metres_map(&metres, (width, height), spacing, depth).map_err(|e| at(&e))?;
    // The tie point (I, J, K, X, Y, Z) puts raster point (I, J) at (X, Y); a sample's
    // centre is half a pixel in unless GTRasterTypeGeoKey (1025) says PixelIsPoint (2).
    let point = keys
        .chunks_exact(4)
        .skip(1)
        .any(|k| k[0] == 1025 && k[3] == 2);
    let half = if point { 0.0 } else { 0.5 };
    if let [i, j, _, x, y, ..] = tie[..] {
        map.georef = Some([x + (half - i) * sx, y - (half - j) * sy]);
    }
    Ok(map)
}

/// Loads `width × height` little-endian `f32` heights (row-major, row 0 first) in
/// grid units, exactly as stored (`depth` is their range); no real units.
pub fn load_raw_f32(path: impl AsRef<Path>, width: u32, height: u32) -> Result<Map, Error> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| Error::at(path, e))?;
    let n = width as usize * height as usize;
    if bytes.len() != n * 4 {
        return Err(Error::at(
            path,
            format!(
                "{} bytes, {width} x {height} f32 need {}",
                bytes.len(),
                n * 4
            ),
        ));
    }
    let heights: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let hf = HeightField::new(&heights, width, height, width as usize)
        .map_err(|e| Error::at(path, e))?;
    let depth = hf.max_height() - hf.min_height();
    Ok(Map {
        width,
        height,
        heights,
        depth,
        h_range: None,
        transform: WorldTransform::IDENTITY,
        georef: None,
    })
}
