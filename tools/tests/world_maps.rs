//! Maps in their real units: the PNG sidecars' heights and spacing, GeoTIFF DEMs (a
//! real one from a Debian package, and written ones for nodata), raw f32 grids; world
//! rays through them land at the real heights.

use hfcast::{dda, Query, Surface, WorldTransform};
use hfcast_tools::maps::{
    bundled_map, load_any, load_geotiff, load_map, load_raw_f32, Map, Nodata,
};
use hfcast_tools::render::{render, RenderOptions};
use std::path::{Path, PathBuf};
use tiff::encoder::{colortype, TiffEncoder};
use tiff::tags::Tag;

/// The real GeoTIFF: `elev.tif` (elevation of Luxembourg, 95 × 90, 30″ geographic,
/// int16 with nodata outside the country) of Debian's `r-cran-terra` 1.7-3 (GPL ≥ 3),
/// extracted by scripts/test.sh into `target/testdata/terra_elev.tif`
/// (`HFCAST_GEOTIFF` overrides).
fn terra_elev() -> Option<PathBuf> {
    let path = std::env::var_os("HFCAST_GEOTIFF").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/testdata/terra_elev.tif"),
        PathBuf::from,
    );
    if path.exists() {
        return Some(path);
    }
    // CI always provides it: a missing file there is a failure, not a skip.
    assert!(
        std::env::var_os("CI").is_none(),
        "{} missing",
        path.display()
    );
    eprintln!(
        "{} missing: run scripts/test.sh once to fetch it",
        path.display()
    );
    None
}

/// Writes a float GeoTIFF: `w × h` samples, pixel scale `scale`, model type
/// `model` (1 projected, 2 geographic), optional GDAL nodata.
fn write_geotiff(
    path: &Path,
    w: u32,
    h: u32,
    data: &[f32],
    scale: [f64; 3],
    model: u16,
    nodata: Option<&str>,
) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = TiffEncoder::new(file).unwrap();
    let mut img = enc.new_image::<colortype::Gray32Float>(w, h).unwrap();
    img.encoder()
        .write_tag(Tag::ModelPixelScaleTag, &scale[..])
        .unwrap();
    let tie = [0.0, 0.0, 0.0, 6.0, 50.0, 0.0];
    img.encoder()
        .write_tag(Tag::ModelTiepointTag, &tie[..])
        .unwrap();
    let keys: [u16; 8] = [1, 1, 0, 1, 1024, 0, 1, model];
    img.encoder()
        .write_tag(Tag::GeoKeyDirectoryTag, &keys[..])
        .unwrap();
    if let Some(v) = nodata {
        img.encoder().write_tag(Tag::GdalNodata, v).unwrap();
    }
    img.write_data(data).unwrap();
}

/// Traces a vertical world ray down onto the world point over sample (i, j).
fn height_over(map: &Map, i: u32, j: u32) -> f64 {
    let hf = map.field();
    let xf = hf.transform();
    let p = xf.point_to_world([f64::from(i), f64::from(j), 0.0]);
    let top = xf.point_to_world([0.0, 0.0, f64::from(hf.max_height()) + 10.0])[2];
    let q =
        Query::<f64>::from_arrays([p[0], p[1], top], [0.0, 0.0, -1.0], 0.0, f64::INFINITY).unwrap();
    let tr = xf
        .trace(&q, |g| dda::trace(&hf, Surface::Triangles, g))
        .unwrap();
    hfcast::math::Real::xyz(tr.hit.expect("a vertical ray over the field hits").point)[2]
}

/// The georeferenced origin of a GeoTIFF (nodata filled).
fn map_georef(path: &Path) -> [f64; 2] {
    load_geotiff(path, None, Nodata::FillLowest)
        .unwrap()
        .georef
        .expect("a tie point")
}

/// Width and height in pixels of the field's footprint in a straight-down render.
fn footprint_pixels(map: &Map) -> (f64, f64) {
    let opts = RenderOptions {
        elevation: 90.0,
        azimuth: 0.0,
        width: 200,
        height: 200,
        threads: 1,
        progress: false,
        ..RenderOptions::default()
    };
    let frame = render(&map.field(), &opts).unwrap();
    let hit = |x: usize, y: usize| frame.depth[y * 200 + x].is_some();
    let cols = (0..200).filter(|&x| (0..200).any(|y| hit(x, y))).count();
    let rows = (0..200).filter(|&y| (0..200).any(|x| hit(x, y))).count();
    (cols as f64, rows as f64)
}

#[test]
fn png_sidecar_gives_metres() {
    let map = load_map(bundled_map(), None).unwrap();
    let xf = map.transform;
    // 3″ spacing at 36.59° N: ~74.4 m east, ~92.7 m north (row 0 is north: y flips).
    let [sx, sy] = xf.spacing();
    assert!(
        (sx - 74.40).abs() < 0.05 && (sy + 92.66).abs() < 0.05,
        "{sx} {sy}"
    );
    assert_eq!(xf.height_offset(), 236.0);
    assert!((xf.height_scale() * f64::from(map.depth) - 840.0).abs() < 1e-9);
    // The grid heights are unchanged (png / 65535 × depth), the field carries the transform.
    let plain = load_map(bundled_map(), Some(map.depth)).unwrap();
    assert_eq!(plain.heights, map.heights);
    assert_eq!(*map.field().transform(), xf);
    assert_eq!(map.georef, Some([-84.41375, 36.73291666666667]));
    // A world ray over the highest sample lands at the sidecar's h_max, 1076 m.
    let k = map
        .heights
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .unwrap()
        .0;
    let (i, j) = ((k as u32) % map.width, (k as u32) / map.width);
    assert!((height_over(&map, i, j) - 1076.0).abs() < 1e-6);
    // The real proportion: relief / mean spacing.
    let real = map.real_depth().unwrap();
    assert!((f64::from(real) - 840.0 / (sx * -sy).sqrt()).abs() < 1e-3);
}

#[test]
fn real_geotiff_dem_renders_in_metres() {
    let Some(path) = terra_elev() else { return };
    // Georeferenced: sample (0, 0) is the centre of the north-west pixel.
    let [lon, lat] = map_georef(&path);
    assert!(
        (5.5..6.0).contains(&lon) && (50.0..50.3).contains(&lat),
        "{lon} {lat}"
    );
    // Nodata outside Luxembourg: refused by default, with the count.
    let err = load_any(&path, None).unwrap_err().to_string();
    assert!(err.contains("nodata"), "{err}");
    let map = load_geotiff(&path, None, Nodata::FillLowest).unwrap();
    assert_eq!((map.width, map.height), (95, 90));
    let (lo, hi) = map.h_range.unwrap();
    assert!((lo, hi) == (141.0, 547.0), "{lo} {hi}");
    // 30″ at ~49.8° N: ~598 m east, ~927 m north.
    let [sx, sy] = map.transform.spacing();
    assert!(
        (sx - 598.0).abs() < 2.0 && (sy + 926.6).abs() < 0.5,
        "{sx} {sy}"
    );
    // Real proportion by default: the relief is 406 m over ~744 m samples.
    assert!((f64::from(map.depth) - 406.0 / (sx * -sy).sqrt()).abs() < 1e-4);
    // World rays land at the DEM's metres: every 7th sample, vertical rays.
    let filled = load_geotiff(&path, None, Nodata::Fill(141.0)).unwrap();
    assert_eq!(filled.heights, map.heights);
    let mut n = 0;
    for j in (0..map.height).step_by(7) {
        for i in (0..map.width).step_by(7) {
            let want = lo
                + f64::from(map.heights[(j * map.width + i) as usize])
                    * map.transform.height_scale();
            let got = height_over(&map, i, j);
            assert!((got - want).abs() < 1e-3, "({i}, {j}): {got} vs {want}");
            n += 1;
        }
    }
    assert!(n > 150);
    // The render frames the world box: looking straight down, the footprint's image
    // has the real east-west : north-south ratio (56.2 : 82.5 km), not the grid's
    // 94 : 89.
    let (w, h) = footprint_pixels(&map);
    let want = (94.0 * sx) / (89.0 * -sy);
    assert!(
        ((w / h) - want).abs() < 0.03,
        "footprint {w} x {h} px, want ratio {want}"
    );
    let grid = Map {
        transform: WorldTransform::IDENTITY,
        ..map.clone()
    };
    let (gw, gh) = footprint_pixels(&grid);
    assert!(
        ((gw / gh) - 94.0 / 89.0).abs() < 0.03,
        "grid footprint {gw} x {gh}"
    );
    // And the CLI renders it with that spacing.
    let out = std::env::temp_dir().join("hfcast_world_maps_render.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_hfcast"))
        .args([
            "render", "--width", "64", "--height", "48", "--nodata", "lowest", "--map",
        ])
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&status.stderr);
    assert!(status.status.success(), "{stderr}");
    assert!(stderr.contains("spacing 597.8 x 926.6 m"), "{stderr}");
    assert!(out.exists());
    // --exaggerate scales the picture's heights (a different image), and must be
    // positive.
    let picture = |ex: &str| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_hfcast"))
            .args(["render", "--width", "64", "--height", "48", "--no-heatmaps"])
            .args(["--nodata", "lowest", "--exaggerate", ex, "--out"])
            .arg(&out)
            .arg("--map")
            .arg(&path)
            .output()
            .unwrap();
        (o.status.success(), std::fs::read(&out).ok())
    };
    let (ok1, one) = picture("1");
    let (ok4, four) = picture("4");
    assert!(ok1 && ok4 && one.is_some() && one != four);
    assert!(!picture("0").0);
}

#[test]
fn written_geotiffs_nodata_and_models() {
    let dir = std::env::temp_dir().join(format!("hfcast_geotiff_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (w, h) = (6u32, 5u32);
    let mut data: Vec<f32> = (0..w * h).map(|k| 100.0 + k as f32).collect();
    data[7] = -9999.0;
    data[12] = f32::NAN;
    // Projected, 25 m pixels, nodata -9999 (and NaN always missing).
    let p = dir.join("proj.tif");
    write_geotiff(&p, w, h, &data, [25.0, 25.0, 0.0], 1, Some("-9999"));
    let e = load_geotiff(&p, None, Nodata::Refuse)
        .unwrap_err()
        .to_string();
    assert!(e.contains("2 nodata samples"), "{e}");
    let m = load_geotiff(&p, None, Nodata::Fill(50.0)).unwrap();
    assert_eq!(m.transform.spacing(), [25.0, -25.0]);
    assert_eq!(m.h_range, Some((50.0, 129.0)));
    let at = |m: &Map, k: usize| {
        m.transform.height_offset() + f64::from(m.heights[k]) * m.transform.height_scale()
    };
    assert!((at(&m, 7) - 50.0).abs() < 1e-4 && (at(&m, 29) - 129.0).abs() < 1e-3);
    let low = load_geotiff(&p, Some(10.0), Nodata::FillLowest).unwrap();
    assert_eq!(low.depth, 10.0);
    assert_eq!(low.h_range, Some((100.0, 129.0)));
    assert_eq!(low.heights[7], 0.0);
    assert!(load_geotiff(&p, None, Nodata::Fill(f64::NAN)).is_err());
    // Geographic: degrees become metres at the centre latitude (tie point 50° N).
    let g = dir.join("geo.tif");
    let clean: Vec<f32> = (0..w * h).map(|k| k as f32).collect();
    write_geotiff(&g, w, h, &clean, [0.01, 0.01, 0.0], 2, None);
    let m = load_geotiff(&g, None, Nodata::Refuse).unwrap();
    // The tie point (0, 0) -> (6°, 50°) is the pixel corner: the first centre is half
    // a pixel in.
    assert_eq!(m.georef, Some([6.005, 49.995]));
    let [sx, sy] = m.transform.spacing();
    let lat = (50.0 - 0.5 * 0.01 * 4.0f64).to_radians();
    assert!(
        (sx - 1111.95 * lat.cos()).abs() < 0.01 && (sy + 1111.95).abs() < 0.01,
        "{sx} {sy}"
    );
    // All nodata, no pixel scale, garbage: clear errors.
    write_geotiff(&g, 2, 2, &[-1.0; 4], [1.0, 1.0, 0.0], 1, Some("-1"));
    let e = load_geotiff(&g, None, Nodata::FillLowest)
        .unwrap_err()
        .to_string();
    assert!(e.contains("every sample is nodata"), "{e}");
    std::fs::write(&g, b"II*\0garbage").unwrap();
    assert!(load_geotiff(&g, None, Nodata::Refuse).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn raw_f32_grids() {
    let dir = std::env::temp_dir().join(format!("hfcast_raw_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let heights: Vec<f32> = (0..12).map(|k| (k as f32).sin()).collect();
    let bytes: Vec<u8> = heights.iter().flat_map(|v| v.to_le_bytes()).collect();
    let p = dir.join("m.f32");
    std::fs::write(&p, &bytes).unwrap();
    let m = load_raw_f32(&p, 4, 3).unwrap();
    assert_eq!(m.heights, heights);
    assert_eq!(m.transform, WorldTransform::IDENTITY);
    assert!(load_raw_f32(&p, 4, 4)
        .unwrap_err()
        .to_string()
        .contains("48 bytes"));
    let mut nan = bytes.clone();
    nan[4..8].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(&p, &nan).unwrap();
    assert!(load_raw_f32(&p, 4, 3).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}
