//! Six-field impostors of a triangle mesh (issue 22; `hfcast::impostor`): read an OBJ
//! (`tobj`) or PLY (`ply-rs-bw`) mesh, capture its six fields with colour and normal
//! textures at their own side, write and read a capture directory, and render it on
//! the CPU.
//!
//! A capture directory holds `impostor.json` (side, colour side, frustum, the cube and
//! each face's unit map by rows, as `hf_impostor_layout`), and per face `F` of `px nx
//! py ny pz nz` (the faces of `hfcast::impostor::FACES`): `heights-F.f32` (`side²`
//! little-endian `f32`, rows of grid y, the padded capture), `colour-F.png` and
//! `normal-F.png` (`colour_side²` RGB; a normal `n` is stored as `(n + 1) / 2`).

use crate::render::Image;
use hfcast::camera::Pinhole;
use hfcast::impostor::{
    pad_silhouettes, procedural_tower, rasterize, Combine, Frustum, Impostor, Layout, Mesh,
    NO_TRIANGLE,
};
use hfcast::math::{cross3, dot3, sub3};
use hfcast::projective::Mat4;
use hfcast::{dda, HeightField, Query, Surface};
use std::path::Path;

/// The file-name tags of the six faces, in `FACES` order.
pub const FACE_TAGS: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// The mesh name that [`load_mesh`] reads as `hfcast::impostor::procedural_tower(64)`.
pub const TOWER: &str = "tower";

/// A triangle mesh read from a file: positions, triangles and, when the file has them,
/// vertex colours (`[0, 1]` RGB).
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Per-vertex colours, if the file has them.
    pub colours: Option<Vec<[f32; 3]>>,
}

impl MeshData {
    /// The checked mesh (NaN positions, no triangles and bad indices are errors).
    pub fn mesh(&self) -> Result<Mesh<'_>, String> {
        Mesh::new(&self.positions, &self.triangles).map_err(|e| format!("mesh: {e}"))
    }
}

/// Reads `path` by its extension (`.obj` or `.ply`, polygons triangulated), or the
/// procedural tower when `path` is [`TOWER`].
pub fn load_mesh(path: &Path) -> Result<MeshData, String> {
    if path.as_os_str() == TOWER {
        let (positions, triangles) = procedural_tower(64);
        return Ok(MeshData {
            positions,
            triangles,
            colours: None,
        });
    }
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    match ext.to_ascii_lowercase().as_str() {
        "obj" => load_obj(path).map_err(|e| err(&e)),
        "ply" => load_ply(path).map_err(|e| err(&e)),
        _ => Err(err(&"not a mesh (want .obj or .ply)")),
    }
}

/// An OBJ file's models, joined.
fn load_obj(path: &Path) -> Result<MeshData, String> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(path, &opts).map_err(|e| e.to_string())?;
    let mut out = MeshData {
        positions: Vec::new(),
        triangles: Vec::new(),
        colours: Some(Vec::new()),
    };
    for m in models {
        let base = out.positions.len() as u32;
        let mesh = m.mesh;
        let n = mesh.positions.len() / 3;
        out.positions
            .extend(mesh.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        match (&mut out.colours, mesh.vertex_color.len() == 3 * n) {
            (Some(c), true) => c.extend(
                mesh.vertex_color
                    .chunks_exact(3)
                    .map(|p| [p[0], p[1], p[2]]),
            ),
            (c, _) => *c = None,
        }
        out.triangles.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    Ok(out)
}

/// A PLY file's `vertex` (`x y z`, optional `red green blue`) and `face`
/// (`vertex_indices` or `vertex_index`, polygons fanned) elements.
fn load_ply(path: &Path) -> Result<MeshData, String> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut file)
        .map_err(|e| e.to_string())?;
    let scalar = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Float(v) => f64::from(*v),
            Property::Double(v) => *v,
            Property::UChar(v) => f64::from(*v) / 255.0,
            Property::UShort(v) => f64::from(*v) / 65535.0,
            Property::Char(v) => f64::from(*v),
            Property::Short(v) => f64::from(*v),
            Property::Int(v) => f64::from(*v),
            Property::UInt(v) => f64::from(*v),
            _ => return None,
        })
    };
    let empty = Vec::new();
    let vertices = ply.payload.get("vertex").unwrap_or(&empty);
    let mut positions = Vec::with_capacity(vertices.len());
    let mut colours = Some(Vec::with_capacity(vertices.len()));
    for v in vertices {
        let p = ["x", "y", "z"].map(|k| scalar(v.get(k)));
        let [Some(x), Some(y), Some(z)] = p else {
            return Err("a vertex without a numeric x, y and z".into());
        };
        positions.push([x as f32, y as f32, z as f32]);
        let c = ["red", "green", "blue"].map(|k| scalar(v.get(k)));
        match (&mut colours, c) {
            (Some(list), [Some(r), Some(g), Some(b)]) => list.push([r as f32, g as f32, b as f32]),
            (c, _) => *c = None,
        }
    }
    let mut triangles = Vec::new();
    for f in ply.payload.get("face").unwrap_or(&empty) {
        let list = f.get("vertex_indices").or_else(|| f.get("vertex_index"));
        let idx: Vec<i64> = match list {
            Some(Property::ListInt(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListUInt(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListShort(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListUShort(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListChar(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListUChar(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            _ => return Err("a face without a vertex index list".into()),
        };
        let bad = || "a face index is negative or too large".to_string();
        let idx: Vec<u32> = idx
            .into_iter()
            .map(|i| u32::try_from(i).map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        for k in 2..idx.len() {
            triangles.push([idx[0], idx[k - 1], idx[k]]);
        }
    }
    Ok(MeshData {
        positions,
        triangles,
        colours,
    })
}

/// A capture: the layout, the six padded height fields, and colour and normal
/// textures at their own side.
pub struct Capture {
    /// The cube and the faces' maps.
    pub layout: Layout,
    /// The fields' side.
    pub side: u32,
    /// The textures' side.
    pub colour_side: u32,
    /// Six `side²` fields, in `FACES` order.
    pub heights: Vec<Vec<f32>>,
    /// Six `colour_side²` RGB textures.
    pub colour: Vec<Vec<[u8; 3]>>,
    /// Six `colour_side²` unit normals (world space).
    pub normal: Vec<Vec<[f32; 3]>>,
}

/// Captures `data` with `frustum`: fields of `side` (padded, `pad_silhouettes`), and
/// textures of `colour_side` whose texel is the mesh's colour and normal where the
/// texel's projector line first meets it (vertex colours when the mesh has them, else
/// a checkerboard of eight cells across the cube, so that colour detail shows apart
/// from the fields' side).
pub fn capture(
    data: &MeshData,
    frustum: Frustum,
    side: u32,
    colour_side: u32,
) -> Result<Capture, String> {
    let mesh = data.mesh()?;
    let layout = Layout::around(&mesh, frustum).map_err(|e| e.to_string())?;
    let mut out = Capture::empty(layout, side, colour_side);
    for face in 0..6 {
        let map = layout.face_map(face, side).map_err(|e| e.to_string())?;
        let mut h = vec![0.0; (side * side) as usize];
        rasterize(&mesh, &map, side, &mut h, None).map_err(|e| e.to_string())?;
        pad_silhouettes(&mut h, side).map_err(|e| e.to_string())?;
        out.heights.push(h);
        let map = layout
            .face_map(face, colour_side)
            .map_err(|e| e.to_string())?;
        let n = (colour_side * colour_side) as usize;
        let (mut h, mut tri) = (vec![0.0; n], vec![0u32; n]);
        rasterize(&mesh, &map, colour_side, &mut h, Some(&mut tri)).map_err(|e| e.to_string())?;
        let (mut colour, mut normal) = (vec![[0u8; 3]; n], vec![[0f32; 3]; n]);
        for at in 0..n {
            if tri[at] == NO_TRIANGLE {
                continue;
            }
            let (i, j) = (at as u32 % colour_side, at as u32 / colour_side);
            let p = map.to_world([f64::from(i), f64::from(j), f64::from(h[at])]);
            let line = map.to_world([f64::from(i), f64::from(j), f64::from(colour_side)]);
            let towards = [0, 1, 2].map(|k| line[k] - p[k]);
            let (c, nrm) = surface_at(data, &mesh, &layout, tri[at] as usize, p, towards);
            colour[at] = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
            normal[at] = nrm;
        }
        // Texels next to the object take a neighbour's colour and normal, as the
        // fields' silhouettes are padded.
        let filled: Vec<bool> = tri.iter().map(|&t| t != NO_TRIANGLE).collect();
        let cs = colour_side as usize;
        for at in (0..n).filter(|&at| !filled[at]) {
            let (i, j) = (at % cs, at / cs);
            let near = (j.saturating_sub(1)..(j + 2).min(cs))
                .flat_map(|jj| (i.saturating_sub(1)..(i + 2).min(cs)).map(move |ii| jj * cs + ii))
                .find(|&b| filled[b]);
            if let Some(b) = near {
                (colour[at], normal[at]) = (colour[b], normal[b]);
            }
        }
        out.colour.push(colour);
        out.normal.push(normal);
    }
    Ok(out)
}

/// The colour and unit normal (turned to face `towards`) of triangle `k` at `p`.
fn surface_at(
    data: &MeshData,
    mesh: &Mesh,
    layout: &Layout,
    k: usize,
    p: [f64; 3],
    towards: [f64; 3],
) -> ([f32; 3], [f32; 3]) {
    let [a, b, c] = mesh.triangle(k);
    let n = cross3(sub3(b, a), sub3(c, a));
    let area = dot3(n, n);
    let len = area.sqrt().max(f64::MIN_POSITIVE);
    let sign = if dot3(n, towards) < 0.0 { -1.0 } else { 1.0 };
    let normal = n.map(|v| (sign * v / len) as f32);
    let colour = match &data.colours {
        Some(cols) if area > 0.0 => {
            // Barycentric weights of p in the triangle.
            let wa = dot3(cross3(sub3(b, p), sub3(c, p)), n) / area;
            let wb = dot3(cross3(sub3(c, p), sub3(a, p)), n) / area;
            let wc = 1.0 - wa - wb;
            let [ia, ib, ic] = data.triangles[k].map(|i| cols[i as usize]);
            [0, 1, 2].map(|i| {
                (wa * f64::from(ia[i]) + wb * f64::from(ib[i]) + wc * f64::from(ic[i])) as f32
            })
        }
        _ => {
            let (c0, s) = (layout.center(), layout.half());
            let cell = |i: usize| ((p[i] - c0[i] + s) / (s / 4.0)).floor() as i64;
            if (cell(0) + cell(1) + cell(2)).rem_euclid(2) == 0 {
                [0.85, 0.72, 0.52]
            } else {
                [0.45, 0.55, 0.75]
            }
        }
    };
    (colour, normal)
}

impl Capture {
    /// A capture of `layout` without fields or textures yet.
    fn empty(layout: Layout, side: u32, colour_side: u32) -> Capture {
        Capture {
            layout,
            side,
            colour_side,
            heights: Vec::new(),
            colour: Vec::new(),
            normal: Vec::new(),
        }
    }

    /// The impostor over the six fields.
    pub fn impostor(&self) -> Result<Impostor<'_>, String> {
        let fields: Result<Vec<HeightField>, _> = self
            .heights
            .iter()
            .map(|h| HeightField::new(h, self.side, self.side, self.side as usize))
            .collect();
        let fields: [HeightField; 6] = fields
            .map_err(|e| e.to_string())?
            .try_into()
            .map_err(|_| "a capture has six fields".to_string())?;
        Impostor::new(self.layout, fields).map_err(|e| e.to_string())
    }

    /// Writes the capture directory (see the module).
    pub fn write(&self, dir: &Path) -> Result<(), String> {
        let err = |e: &dyn std::fmt::Display| format!("{}: {e}", dir.display());
        std::fs::create_dir_all(dir).map_err(|e| err(&e))?;
        let (frustum, apex) = match self.layout.frustum() {
            Frustum::Orthographic => ("orthographic", 0.0),
            Frustum::ReversePerspective { apex } => ("reverse-perspective", apex),
        };
        let units: Vec<Vec<f64>> = (0..6)
            .map(|k| self.layout.face_unit(k).iter().flatten().copied().collect())
            .collect();
        let json = serde_json::json!({
            "format": "hfcast impostor 1",
            "side": self.side,
            "colour_side": self.colour_side,
            "frustum": frustum,
            "apex": apex,
            "center": self.layout.center(),
            "half": self.layout.half(),
            "units": units,
            "faces": FACE_TAGS,
        });
        let text = serde_json::to_string_pretty(&json).map_err(|e| err(&e))?;
        std::fs::write(dir.join("impostor.json"), text).map_err(|e| err(&e))?;
        for (k, tag) in FACE_TAGS.iter().enumerate() {
            let bytes: Vec<u8> = self.heights[k]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect();
            std::fs::write(dir.join(format!("heights-{tag}.f32")), bytes).map_err(|e| err(&e))?;
            let image = |rgb: Vec<u8>| Image {
                width: self.colour_side,
                height: self.colour_side,
                rgb,
            };
            let colour = image(self.colour[k].iter().flatten().copied().collect());
            crate::render::write_png(dir.join(format!("colour-{tag}.png")), &colour)
                .map_err(|e| e.to_string())?;
            let normal = image(
                self.normal[k]
                    .iter()
                    .flatten()
                    .map(|v| ((v + 1.0) * 127.5).round() as u8)
                    .collect(),
            );
            crate::render::write_png(dir.join(format!("normal-{tag}.png")), &normal)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// Reads a capture directory [`Capture::write`] wrote; a missing, short or
    /// inconsistent file is an error that names it.
    pub fn read(dir: &Path) -> Result<Capture, String> {
        let path = dir.join("impostor.json");
        let err = |p: &Path, e: &dyn std::fmt::Display| format!("{}: {e}", p.display());
        let text = std::fs::read_to_string(&path).map_err(|e| err(&path, &e))?;
        let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| err(&path, &e))?;
        let num = |k: &str| {
            json[k]
                .as_f64()
                .ok_or(err(&path, &format!("no number {k:?}")))
        };
        let side = num("side")? as u32;
        let colour_side = num("colour_side")? as u32;
        let frustum = match json["frustum"].as_str() {
            Some("orthographic") => Frustum::Orthographic,
            Some("reverse-perspective") => Frustum::ReversePerspective { apex: num("apex")? },
            _ => {
                return Err(err(
                    &path,
                    &"frustum: want orthographic or reverse-perspective",
                ))
            }
        };
        let floats = |v: &serde_json::Value, n: usize| -> Option<Vec<f64>> {
            let list: Vec<f64> = v.as_array()?.iter().filter_map(|x| x.as_f64()).collect();
            (list.len() == n).then_some(list)
        };
        let c = floats(&json["center"], 3).ok_or(err(&path, &"center: want 3 numbers"))?;
        let mut units: [Mat4; 6] = [[[0.0; 4]; 4]; 6];
        for (k, unit) in units.iter_mut().enumerate() {
            let m =
                floats(&json["units"][k], 16).ok_or(err(&path, &"units: want 6 x 16 numbers"))?;
            *unit = std::array::from_fn(|r| std::array::from_fn(|c| m[4 * r + c]));
        }
        let layout = Layout::from_parts([c[0], c[1], c[2]], num("half")?, frustum, units)
            .map_err(|e| err(&path, &e))?;
        let mut out = Capture::empty(layout, side, colour_side);
        for tag in FACE_TAGS {
            let p = dir.join(format!("heights-{tag}.f32"));
            let bytes = std::fs::read(&p).map_err(|e| err(&p, &e))?;
            if bytes.len() != 4 * (side as usize).pow(2) {
                return Err(err(&p, &format!("want {side} x {side} f32 samples")));
            }
            out.heights.push(
                bytes
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect(),
            );
            let rgb = |name: &str| -> Result<Vec<[u8; 3]>, String> {
                let p = dir.join(format!("{name}-{tag}.png"));
                let (w, h, data) = read_rgb(&p).map_err(|e| err(&p, &e))?;
                if (w, h) != (colour_side, colour_side) {
                    return Err(err(
                        &p,
                        &format!("want {colour_side} x {colour_side} pixels"),
                    ));
                }
                Ok(data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
            };
            out.colour.push(rgb("colour")?);
            out.normal.push(
                rgb("normal")?
                    .into_iter()
                    .map(|c| c.map(|v| f32::from(v) / 127.5 - 1.0))
                    .collect(),
            );
        }
        out.impostor()?;
        Ok(out)
    }
}

/// An 8-bit RGB PNG's width, height and bytes.
fn read_rgb(path: &Path) -> Result<(u32, u32, Vec<u8>), String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("image too large")?];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    if info.color_type != png::ColorType::Rgb || info.bit_depth != png::BitDepth::Eight {
        return Err("want an 8-bit RGB PNG".into());
    }
    buf.truncate(info.buffer_size());
    Ok((info.width, info.height, buf))
}

/// A camera orbiting the cube's centre: compass azimuth and elevation (degrees), at
/// `distance` half sides, with a vertical field of view of `fov_deg`.
#[derive(Clone, Copy, Debug)]
pub struct Orbit {
    /// Degrees above the horizon (+z up).
    pub elevation: f64,
    /// Compass degrees (0 = +y, 90 = +x).
    pub azimuth: f64,
    /// Distance from the centre in half sides.
    pub distance: f64,
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
}

impl Orbit {
    /// The camera of a `w × h` image looking at the centre of `layout`'s cube, +z up.
    pub fn pinhole(&self, layout: &Layout, w: u32, h: u32) -> Result<Pinhole, String> {
        let (el, az) = (self.elevation.to_radians(), self.azimuth.to_radians());
        let back = [el.cos() * az.sin(), el.cos() * az.cos(), el.sin()];
        let c = layout.center();
        let eye = [0, 1, 2].map(|k| c[k] + self.distance * layout.half() * back[k]);
        let forward = back.map(|v| -v);
        Pinhole::new(eye, forward, [0.0, 0.0, 1.0], self.fov_deg, w, h).map_err(|e| e.to_string())
    }
}

/// Six cameras of `px × px` pixels three half sides from the centre of `layout`'s
/// cube, looking at it from around the object (from +x, +y, −x, −y, +z and −z, each
/// off the axis), the cube filling the frame: the views the impostor tests share.
pub fn six_views(layout: &Layout, px: u32) -> Vec<Pinhole> {
    let backs: [[f64; 3]; 6] = [
        [1.0, 0.3, 0.2],
        [-0.4, 1.0, 0.5],
        [-1.0, -0.6, 0.1],
        [0.2, -1.0, -0.7],
        [0.3, 0.4, 1.0],
        [-0.2, 0.1, -1.0],
    ];
    let c = layout.center();
    backs
        .iter()
        .map(|b| {
            let l = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
            let eye = [0, 1, 2].map(|k| c[k] + 3.0 * layout.half() * b[k] / l);
            let up = if b[2].abs() < 0.9 * l {
                [0.0, 0.0, 1.0]
            } else {
                [1.0, 0.0, 0.0]
            };
            let fov = 2.0 * 0.6f64.atan().to_degrees();
            Pinhole::new(eye, b.map(|v| -v), up, fov, px, px).expect("a camera around the cube")
        })
        .collect()
}

/// The origin and direction of `q` in `f64` (a camera's ray, for the mesh's own hit).
pub fn world_ray(q: &Query<f32>) -> ([f64; 3], [f64; 3]) {
    (q.origin().map(f64::from), q.dir().map(f64::from))
}

impl Default for Orbit {
    /// 30° up, azimuth 30°, four half sides away, 40° field of view (the cube fills
    /// about two thirds of the frame).
    fn default() -> Orbit {
        Orbit {
            elevation: 30.0,
            azimuth: 30.0,
            distance: 4.0,
            fov_deg: 40.0,
        }
    }
}

/// A CPU render of a capture: the shaded image and each pixel's hit distance along its
/// unit ray (`∞` for a miss).
pub struct Rendered {
    /// The shaded image (background grey).
    pub image: Image,
    /// Distance to the hit per pixel, row-major.
    pub depth: Vec<f64>,
    /// Field traces made.
    pub traces: u64,
    /// The colour texel each hit pixel shows (unlit), row-major.
    pub albedo: Vec<[u8; 3]>,
}

/// Renders `cap` from `orbit` with `combine`, the exact traversal on every field:
/// colour texel × (ambient 0.25 + 0.75 × Lambert) with the normal texel (both nearest,
/// from the face that sees the hit best, `Impostor::texture_face`), light from over
/// the camera's left shoulder.
pub fn render(
    cap: &Capture,
    combine: Combine,
    orbit: Orbit,
    w: u32,
    h: u32,
) -> Result<Rendered, String> {
    let imp = cap.impostor()?;
    let cam = orbit.pinhole(&cap.layout, w, h)?;
    let light = {
        let v = cam.forward;
        let l = [-v[0] - 0.5 * v[1], -v[1] + 0.5 * v[0], -v[2] + 0.8];
        let n = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        l.map(|x| x / n)
    };
    let mut out = Rendered {
        image: Image {
            width: w,
            height: h,
            rgb: vec![0; (w * h * 3) as usize],
        },
        depth: vec![f64::INFINITY; (w * h) as usize],
        traces: 0,
        albedo: vec![[0; 3]; (w * h) as usize],
    };
    for y in 0..h {
        for x in 0..w {
            let at = (y * w + x) as usize;
            let q = cam.ray(x, y, f32::INFINITY).map_err(|e| e.to_string())?;
            let dir = world_ray(&q).1;
            let r = imp
                .trace(combine, &q, |hf, g| dda::trace(hf, Surface::Triangles, g))
                .map_err(|e| e.to_string())?;
            out.traces += u64::from(r.traces);
            let rgb = match (r.trace.hit, r.face) {
                (Some(hit), Some(face)) => {
                    let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
                    out.depth[at] = f64::from(hit.t) * len;
                    let p = [hit.point.x, hit.point.y, hit.point.z].map(f64::from);
                    let n = [hit.normal.x, hit.normal.y, hit.normal.z].map(f64::from);
                    let face = imp.texture_face(p, n, face);
                    let [u, v] = imp.texcoord(face, p);
                    let last = f64::from(cap.colour_side - 1);
                    let texel = |c: f64| (c * last).round().clamp(0.0, last) as usize;
                    let t = texel(v) * cap.colour_side as usize + texel(u);
                    out.albedo[at] = cap.colour[face][t];
                    let n = cap.normal[face][t];
                    let lambert = (0..3)
                        .map(|k| f64::from(n[k]) * light[k])
                        .sum::<f64>()
                        .max(0.0);
                    cap.colour[face][t]
                        .map(|c| (f64::from(c) * (0.25 + 0.75 * lambert)).round() as u8)
                }
                _ => [40, 40, 48],
            };
            out.image.rgb[3 * at..3 * at + 3].copy_from_slice(&rgb);
        }
    }
    Ok(out)
}

/// A render's colours against the mesh's own: of the pixels both hit, those whose
/// colour texel differs from the mesh's colour at its first hit (any channel by more
/// than 8 of 255), and the mean absolute difference per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColourError {
    /// Pixels both the impostor and the mesh hit.
    pub both: usize,
    /// Of those, the pixels whose colours differ.
    pub wrong: usize,
    /// Mean absolute difference per channel (of 255).
    pub mean_abs: f64,
}

/// [`ColourError`] of `r` (a render of `cap`, a capture of `data`, from `orbit`).
pub fn colour_error(
    data: &MeshData,
    cap: &Capture,
    r: &Rendered,
    orbit: Orbit,
) -> Result<ColourError, String> {
    let mesh = data.mesh()?;
    let (w, h) = (r.image.width, r.image.height);
    let cam = orbit.pinhole(&cap.layout, w, h)?;
    let mut e = ColourError {
        both: 0,
        wrong: 0,
        mean_abs: 0.0,
    };
    for y in 0..h {
        for x in 0..w {
            let at = (y * w + x) as usize;
            if !r.depth[at].is_finite() {
                continue;
            }
            let q = cam.ray(x, y, f32::INFINITY).map_err(|e| e.to_string())?;
            let (eye, dir) = world_ray(&q);
            let Some((t, k)) = mesh.first_hit(eye, dir, 0.0, f64::INFINITY) else {
                continue;
            };
            let p = [0, 1, 2].map(|i| eye[i] + t * dir[i]);
            let back = dir.map(|v| -v);
            let truth = surface_at(data, &mesh, &cap.layout, k as usize, p, back)
                .0
                .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
            let d: Vec<f64> = (0..3)
                .map(|i| (f64::from(truth[i]) - f64::from(r.albedo[at][i])).abs())
                .collect();
            e.both += 1;
            e.wrong += usize::from(d.iter().any(|&v| v > 8.0));
            e.mean_abs += d.iter().sum::<f64>() / 3.0;
        }
    }
    e.mean_abs /= e.both.max(1) as f64;
    Ok(e)
}
