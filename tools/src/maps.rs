//! Height maps on disk: grayscale PNGs (16-bit, 8-bit accepted) with an optional JSON
//! sidecar of the same name, as in `../shared/data` (see its README).
//!
//! Heights are `png / 65535 × depth` in grid units, the conversion of
//! [`HeightField::from_u16`] (8-bit values are first widened exactly, `v × 257`);
//! `depth` is the relief depth in grid units.
//! The image order is kept: image row 0 (the top, north for DEMs) is grid row y = 0,
//! so y grows southwards and x eastwards.

use hfcast::{FieldError, HeightField};
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
}

impl Map {
    /// The height field over [`Map::heights`] (stride = width).
    pub fn field(&self) -> HeightField<'_> {
        HeightField::new(&self.heights, self.width, self.height, self.width as usize)
            .expect("validated when the map was loaded")
    }
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
/// missing). Reads only the PNG headers and sidecars.
pub fn list_maps() -> Vec<MapInfo> {
    let Ok(entries) = std::fs::read_dir(shared_data_dir()) else {
        return Vec::new();
    };
    let mut maps: Vec<MapInfo> = entries
        .filter_map(|e| {
            let path = e.ok()?.path();
            if path.extension()? != "png" {
                return None;
            }
            let reader = png_reader(&path).ok()?;
            let (width, height) = reader.info().size();
            Some(MapInfo {
                name: path.file_stem()?.to_string_lossy().into_owned(),
                width,
                height,
                h_range: sidecar_range(&path),
                path,
            })
        })
        .collect();
    maps.sort_by(|a, b| a.name.cmp(&b.name));
    maps
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
    })
}
