//! Six-field impostors (Baboud & Décoret 2006, §4.1–4.2): an object replaced by six
//! projective height fields ([`crate::projective`]) on the faces of its bounding cube.
//!
//! **Fields.** Face `k` of the cube (outward normal `±x, ±y, ±z`, [`FACES`]) holds a
//! `side × side` field whose heights rise towards the face. Its frustum is either
//! orthographic (projector lines along the normal) or *reverse perspective*: the
//! centre of projection sits `apex` half sides behind the cube's centre, on the far
//! side, so the projector lines fan out towards the face and cross the object's sides
//! from outside; a field then holds the sides as well as the top. [`Layout::around`]
//! fits each face's footprint and height range to the mesh as that face projects it,
//! so no sample is spent outside the object ([`Layout::new`] spans the whole cube).
//!
//! **Capture** ([`rasterize`]): sample `(i, j)` holds the grid height of the mesh's
//! point nearest the face on its projector line (the line of grid points `(i, j, z)`),
//! found by rasterizing every triangle in grid space in `f64` (a projective map keeps
//! triangles planar, so the height is the plane's at the sample); [`EMPTY`] where the
//! line misses the mesh. [`pad_silhouettes`] then lifts the empty samples next to
//! the object to its height, so that no cell across a silhouette ramps down into it.
//! Colour and normal textures are the same rasterization at their own side, keeping
//! the triangle index.
//!
//! **The object** ([`Combine`]). By default it is the intersection of the six solids
//! (each field's solid is what lies under its surface and over its footprint, down to
//! the grid height [`FLOOR`]). [`Impostor::trace`] finds a
//! ray's first point in it inside the cube: from the cube's entry `t`, each field in
//! turn is traced from `t`; a field whose solid does not hold `t` moves `t` to where
//! the ray enters that solid (no point in between is in it), a miss of any field is a
//! miss, and the answer is the first `t` every field holds. With exact marches it is
//! the exact first point of the intersection; the hit's normal and face are those of
//! the field that set `t` last. After [`MAX_ROUNDS`] passes without settling the trace
//! stops there and says so ([`Flags::BUDGET_EXHAUSTED`]). [`Combine::FacingField`]
//! traces only the field the ray faces most directly, as Baboud & Décoret draw each
//! face with its own field.
//!
//! **Which frustum** (measured, `core/tests/impostor.rs` and docs/report/impostors.md):
//! with one field per ray the reverse perspective halves the silhouette error of the
//! orthographic fields (it sees the sides the ray crosses), as the paper says; in the
//! intersection every field's sampling error cuts into the object, a reverse
//! perspective sees more of the surface at grazing angles, and the orthographic
//! fields are the better ones there. The intersection beats either single field by
//! an order of magnitude.

use crate::math::{cross3, dot3, sub3, Real};
use crate::projective::{mul, Mat4, Projective, ProjectiveError};
use crate::ray::{Flags, Hit, Query, RayError, Trace};
use crate::HeightField;

/// The height [`rasterize`] stores where a sample's projector line misses the mesh:
/// one grid unit under the opposite face, so that no solid is there inside the cube.
pub const EMPTY: f32 = -1.0;

/// The grid height under which no field's solid reaches: half a grid unit under the
/// lowest captured height of a fitted layout (0, the object's far end along the
/// face's normal), above [`EMPTY`]. It bounds each solid to its frustum, so that one
/// field alone ([`Combine::FacingField`]) does not reach past the object's far side.
pub const FLOOR: f32 = -0.5;

/// The triangle index [`rasterize`] stores where a sample's projector line misses.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// Passes over the six fields [`Impostor::trace`] makes before it stops unsettled.
pub const MAX_ROUNDS: u32 = 64;

/// The six faces of the bounding cube: outward normal, then the two tangents that are
/// the field's grid x and y (right-handed: x × y = normal).
pub const FACES: [[[f64; 3]; 3]; 6] = [
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    [[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
];

named_enum! {
    /// How [`Impostor::trace`] combines the six fields.
    pub enum Combine: u32 {
        /// The first point in every field's solid (their intersection; a visual hull of
        /// six height fields): each field carves what it sees, so every face helps on
        /// every ray. About eight field traces per ray. The default.
        Intersection = 0 => "intersection",
        /// One field per ray: the face the ray looks at most directly (the largest
        /// `−d·n`), traced alone over the cube, as Baboud & Décoret draw each face with
        /// its own field. One trace per ray; only a reverse perspective shows it the
        /// object's sides.
        FacingField = 1 => "facing-field",
    }
}

impl Default for Combine {
    /// [`Combine::Intersection`].
    fn default() -> Combine {
        Combine::Intersection
    }
}

/// The face [`Combine::FacingField`] traces for direction `d`: the face whose outward
/// normal is most against `d` (the first axis of largest `|d|`).
pub fn facing_face(d: [f64; 3]) -> usize {
    let a = (0..3).fold(0, |a, k| if d[k].abs() > d[a].abs() { k } else { a });
    2 * a + usize::from(d[a] > 0.0)
}

/// Why a mesh, a layout or a set of fields is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImpostorError {
    /// The mesh has no triangles.
    NoTriangles,
    /// A vertex position, or a layout's centre or half side, is NaN or infinite.
    NotFinite,
    /// A triangle names a vertex past the end of the positions.
    IndexOutOfRange,
    /// The mesh (or a given cube) has no extent: every vertex is the same point.
    NoExtent,
    /// The centre of projection is not behind the cube (`apex` must be finite and > 1).
    BadApex,
    /// A field side under 2 or over the largest map side.
    BadSide,
    /// An output buffer is shorter than `side²`.
    BufferTooSmall,
    /// The six fields are not all square with one side.
    FieldsDiffer,
    /// A face's projective map is refused (never for a valid layout).
    Map(ProjectiveError),
}

impl core::fmt::Display for ImpostorError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ImpostorError::NoTriangles => f.write_str("the mesh has no triangles"),
            ImpostorError::NotFinite => {
                f.write_str("a vertex position, centre or half side is NaN or infinite")
            }
            ImpostorError::IndexOutOfRange => {
                f.write_str("a triangle names a vertex past the end of the positions")
            }
            ImpostorError::NoExtent => f.write_str("the mesh has no extent"),
            ImpostorError::BadApex => {
                f.write_str("the apex must be finite and more than one half side behind")
            }
            ImpostorError::BadSide => f.write_str("a field side must be 2 to the largest side"),
            ImpostorError::BufferTooSmall => f.write_str("an output buffer is too small"),
            ImpostorError::FieldsDiffer => {
                f.write_str("the six fields must be square with one side")
            }
            ImpostorError::Map(e) => write!(f, "a face's map: {e}"),
        }
    }
}

/// A triangle mesh, borrowed and checked: every position finite, every index in range,
/// at least one triangle.
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'a> {
    positions: &'a [[f32; 3]],
    triangles: &'a [[u32; 3]],
    lo: [f64; 3],
    hi: [f64; 3],
}

impl<'a> Mesh<'a> {
    /// Checks `positions` and `triangles` (vertex indices into `positions`).
    pub fn new(
        positions: &'a [[f32; 3]],
        triangles: &'a [[u32; 3]],
    ) -> Result<Mesh<'a>, ImpostorError> {
        if triangles.is_empty() {
            return Err(ImpostorError::NoTriangles);
        }
        if !positions.iter().flatten().all(|v| v.is_finite()) {
            return Err(ImpostorError::NotFinite);
        }
        if triangles
            .iter()
            .flatten()
            .any(|&i| i as usize >= positions.len())
        {
            return Err(ImpostorError::IndexOutOfRange);
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &i in triangles.iter().flatten() {
            for (k, v) in positions[i as usize].iter().enumerate() {
                lo[k] = lo[k].min(f64::from(*v));
                hi[k] = hi[k].max(f64::from(*v));
            }
        }
        Ok(Mesh {
            positions,
            triangles,
            lo,
            hi,
        })
    }

    /// The number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Never: a mesh has at least one triangle.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The corners of the box around the triangles' vertices.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        (self.lo, self.hi)
    }

    /// Triangle `k`'s vertices in `f64`.
    pub fn triangle(&self, k: usize) -> [[f64; 3]; 3] {
        self.triangles[k].map(|i| self.positions[i as usize].map(f64::from))
    }

    /// The reference: the first `t` in `[t_min, t_max]` where the line `o + t·d` meets
    /// a triangle (either side), and that triangle; brute force in `f64`
    /// (Möller–Trumbore), for tests and the report's ground truth.
    pub fn first_hit(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let mut best: Option<(f64, u32)> = None;
        for k in 0..self.triangles.len() {
            let [a, b, c] = self.triangle(k);
            let (e1, e2) = (sub3(b, a), sub3(c, a));
            let p = cross3(d, e2);
            let det = dot3(e1, p);
            if det == 0.0 {
                continue;
            }
            let s = sub3(o, a);
            let u = dot3(s, p) / det;
            let q = cross3(s, e1);
            let v = dot3(d, q) / det;
            let t = dot3(e2, q) / det;
            let inside = u >= 0.0 && v >= 0.0 && u + v <= 1.0;
            if inside && t >= t_min && t <= t_max && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, k as u32));
            }
        }
        best
    }
}

/// How a face's field projects the object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Frustum {
    /// Projector lines along the face's normal (an affine map).
    Orthographic,
    /// Projector lines from a centre `apex` half sides behind the cube's centre (on the
    /// side away from the face; finite and > 1): the reverse perspective of §4.
    ReversePerspective {
        /// Distance of the centre of projection from the cube's centre, in half sides.
        apex: f64,
    },
}

impl Frustum {
    /// The reverse perspective the CLI and the C API use unless told: the centre two
    /// half sides behind the cube's centre (projector lines up to 25° off the normal at
    /// the cube's corners; the lowest silhouette error of
    /// [`Combine::FacingField`] on the bunny among apexes 2 to 20, docs/report/impostors.md).
    pub const DEFAULT_REVERSE: Frustum = Frustum::ReversePerspective { apex: 2.0 };
}

/// The bounding cube and the frustum its six fields share.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    center: [f64; 3],
    half: f64,
    frustum: Frustum,
    unit: [Mat4; 6],
}

impl Layout {
    /// The cube centred on `center` with half side `half`; errors when either is not
    /// finite, `half ≤ 0`, or a reverse perspective's `apex` is not finite and > 1.
    pub fn new(center: [f64; 3], half: f64, frustum: Frustum) -> Result<Layout, ImpostorError> {
        if !center.iter().all(|v| v.is_finite()) || !half.is_finite() {
            return Err(ImpostorError::NotFinite);
        }
        if half <= 0.0 {
            return Err(ImpostorError::NoExtent);
        }
        if let Frustum::ReversePerspective { apex } = frustum {
            if !(apex.is_finite() && apex > 1.0) {
                return Err(ImpostorError::BadApex);
            }
        }
        let mut layout = Layout {
            center,
            half,
            frustum,
            unit: [[[0.0; 4]; 4]; 6],
        };
        for face in 0..6 {
            layout.unit[face] = layout.cube_unit(face);
        }
        Ok(layout)
    }

    /// The layout of `mesh`: the cube around its bounds (its half side 1 % over half
    /// the largest extent), and each face's footprint and height range fitted to the
    /// mesh's vertices as that face projects them (a convex frustum holding every
    /// vertex holds every triangle), so that no sample is spent outside the object.
    /// A reverse perspective magnifies the parts nearest the face; fitted, it still
    /// spends its samples on the object only.
    pub fn around(mesh: &Mesh, frustum: Frustum) -> Result<Layout, ImpostorError> {
        let (lo, hi) = mesh.bounds();
        let extent = (0..3).fold(0f64, |e, k| e.max(hi[k] - lo[k]));
        let center = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let mut layout = Layout::new(center, 0.505 * extent, frustum)?;
        for unit in layout.unit.iter_mut() {
            // The vertices' range in each unit coordinate, mapped to [0, 1].
            let mut range = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
            for k in 0..mesh.len() {
                for p in mesh.triangle(k) {
                    let g = mul(unit, [p[0], p[1], p[2], 1.0]);
                    for (r, v) in range.iter_mut().zip(&g[..3]) {
                        r[0] = r[0].min(v / g[3]);
                        r[1] = r[1].max(v / g[3]);
                    }
                }
            }
            let mut fit: Mat4 = [[0.0; 4]; 4];
            fit[3][3] = 1.0;
            for (a, [r0, r1]) in range.into_iter().enumerate() {
                // A flat range (a planar mesh seen edge-on) keeps a unit width.
                let w = if r1 > r0 { r1 - r0 } else { 1.0 };
                fit[a][a] = 1.0 / w;
                fit[a][3] = -r0 / w;
            }
            *unit = mat_mul(&fit, unit);
        }
        Ok(layout)
    }

    /// A layout from its parts, as [`Layout::center`], [`Layout::half`],
    /// [`Layout::frustum`] and [`Layout::face_unit`] give them (a layout kept or passed
    /// through C): the cube and frustum checked as [`Layout::new`] does, each unit map
    /// as [`Projective::new`] does.
    pub fn from_parts(
        center: [f64; 3],
        half: f64,
        frustum: Frustum,
        units: [Mat4; 6],
    ) -> Result<Layout, ImpostorError> {
        let mut layout = Layout::new(center, half, frustum)?;
        for unit in &units {
            Projective::new(*unit).map_err(ImpostorError::Map)?;
        }
        layout.unit = units;
        Ok(layout)
    }

    /// The cube's centre.
    pub fn center(&self) -> [f64; 3] {
        self.center
    }

    /// The cube's half side.
    pub fn half(&self) -> f64 {
        self.half
    }

    /// The frustum every face uses.
    pub fn frustum(&self) -> Frustum {
        self.frustum
    }

    /// Face `face`'s map from world points to its unit cube: grid x and y in `[0, 1]`
    /// across the footprint, z rising to 1 towards the face. Panics when `face ≥ 6`.
    pub fn face_unit(&self, face: usize) -> Mat4 {
        self.unit[face]
    }

    /// Face `face`'s unit map when it spans the cube: the footprint covers the cube at
    /// every depth, z runs from 0 at the opposite face to 1 at the face.
    fn cube_unit(&self, face: usize) -> Mat4 {
        let [n, tx, ty] = FACES[face];
        let s = self.half;
        // World to the face's frame: u, v along the tangents, z along the normal,
        // each from the cube's centre.
        let frame = [tx, ty, n].map(|a| [a[0], a[1], a[2], -dot3(a, self.center)]);
        let local: Mat4 = [frame[0], frame[1], frame[2], [0.0, 0.0, 0.0, 1.0]];
        let unit: Mat4 = match self.frustum {
            Frustum::Orthographic => [
                [0.5 / s, 0.0, 0.0, 0.5],
                [0.0, 0.5 / s, 0.0, 0.5],
                [0.0, 0.0, 0.5 / s, 0.5],
                [0.0, 0.0, 0.0, 1.0],
            ],
            Frustum::ReversePerspective { apex } => {
                // Distance from the centre of projection z' = z + d, in [d − s, d + s]
                // over the cube; x = (u·(d − s)/s + z') / 2z'; grid z rises from 0 at
                // z' = d − s to 1 at z' = d + s as 1/z' falls.
                let d = apex * s;
                let (near, far) = (d - s, d + s);
                let k = 1.0 / near - 1.0 / far;
                let a = near / (2.0 * s);
                [
                    [a, 0.0, 0.5, 0.5 * d],
                    [0.0, a, 0.5, 0.5 * d],
                    [0.0, 0.0, 1.0 / (near * k), d / (near * k) - 1.0 / k],
                    [0.0, 0.0, 1.0, d],
                ]
            }
        };
        mat_mul(&unit, &local)
    }

    /// Face `face`'s map to the grid of a `side × side` field whose heights span
    /// `side − 1` grid units ([`Projective::from_unit_cube`]).
    pub fn face_map(&self, face: usize, side: u32) -> Result<Projective, ImpostorError> {
        check_side(side)?;
        let depth = f64::from(side - 1);
        Projective::from_unit_cube(self.face_unit(face), side, side, depth)
            .map_err(ImpostorError::Map)
    }

    /// The part of `[t_min, t_max]` where `world` is inside the cube, if any (`f64`).
    pub fn clip<R: Real>(&self, world: &Query<R>) -> Option<(f64, f64)> {
        let (o, d) = (world.origin().map(R::to_f64), world.dir().map(R::to_f64));
        let lo = self.center.map(|c| c - self.half);
        let hi = self.center.map(|c| c + self.half);
        let (t0, t1) = crate::ray::slabs(o, d, lo, hi);
        let t0 = t0.max(world.t_min().to_f64());
        let t1 = t1.min(world.t_max().to_f64());
        (t0 <= t1).then_some((t0, t1))
    }
}

/// Rejects sides a field cannot have.
fn check_side(side: u32) -> Result<(), ImpostorError> {
    if !(2..=crate::field::MAX_SIDE).contains(&side) {
        return Err(ImpostorError::BadSide);
    }
    Ok(())
}

/// Fills `heights` (`side²`, row-major) with the grid height of `mesh`'s highest point
/// on each sample's projector line under `map` ([`EMPTY`] where there is none), and
/// `triangles`, when given, with that point's triangle ([`NO_TRIANGLE`] where none).
/// Triangles with a vertex behind the centre of projection (`w ≤ 0`) or seen edge-on
/// are skipped (an edge-on triangle covers no sample its neighbours do not).
pub fn rasterize(
    mesh: &Mesh,
    map: &Projective,
    side: u32,
    heights: &mut [f32],
    mut triangles: Option<&mut [u32]>,
) -> Result<(), ImpostorError> {
    check_side(side)?;
    let n = side as usize * side as usize;
    if heights.len() < n || triangles.as_ref().is_some_and(|t| t.len() < n) {
        return Err(ImpostorError::BufferTooSmall);
    }
    heights[..n].fill(EMPTY);
    if let Some(t) = triangles.as_deref_mut() {
        t[..n].fill(NO_TRIANGLE);
    }
    let last = f64::from(side - 1);
    for k in 0..mesh.len() {
        let h = mesh.triangle(k).map(|p| map.to_grid_h(p));
        if h.iter().any(|g| g[3].is_nan() || g[3] <= 0.0) {
            continue;
        }
        let [a, b, c] = h.map(|g| [g[0] / g[3], g[1] / g[3], g[2] / g[3]]);
        let area = edge(a, b, c);
        if area == 0.0 || !area.is_finite() {
            continue;
        }
        let x0 = libm::ceil(a[0].min(b[0]).min(c[0])).max(0.0);
        let x1 = libm::floor(a[0].max(b[0]).max(c[0])).min(last);
        let y0 = libm::ceil(a[1].min(b[1]).min(c[1])).max(0.0);
        let y1 = libm::floor(a[1].max(b[1]).max(c[1])).min(last);
        if x0 > x1 || y0 > y1 {
            continue;
        }
        for j in y0 as usize..=y1 as usize {
            for i in x0 as usize..=x1 as usize {
                let p = [i as f64, j as f64, 0.0];
                let (wa, wb, wc) = (edge(b, c, p), edge(c, a, p), edge(a, b, p));
                let inside = if area > 0.0 {
                    wa >= 0.0 && wb >= 0.0 && wc >= 0.0
                } else {
                    wa <= 0.0 && wb <= 0.0 && wc <= 0.0
                };
                let z = ((wa * a[2] + wb * b[2] + wc * c[2]) / area) as f32;
                let at = j * side as usize + i;
                if inside && z > heights[at] {
                    heights[at] = z;
                    if let Some(t) = triangles.as_deref_mut() {
                        t[at] = k as u32;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Raises every [`EMPTY`] sample next to a captured one (of its eight neighbours) to the
/// highest such neighbour, so that a cell across the object's silhouette is flat at the
/// object's height instead of a ramp down to [`EMPTY`] that cuts into the object. The
/// intersection of the six solids keeps every field's cut, while a field's overshoot
/// past its silhouette is cut away by the fields that see that side.
#[cfg(feature = "alloc")]
pub fn pad_silhouettes(heights: &mut [f32], side: u32) -> Result<(), ImpostorError> {
    check_side(side)?;
    let n = side as usize;
    if heights.len() < n * n {
        return Err(ImpostorError::BufferTooSmall);
    }
    let captured = heights[..n * n].to_vec();
    for j in 0..n {
        for i in 0..n {
            if captured[j * n + i] != EMPTY {
                continue;
            }
            let mut top = EMPTY;
            for jj in j.saturating_sub(1)..(j + 2).min(n) {
                for ii in i.saturating_sub(1)..(i + 2).min(n) {
                    let v = captured[jj * n + ii];
                    if v != EMPTY {
                        top = top.max(v);
                    }
                }
            }
            heights[j * n + i] = top;
        }
    }
    Ok(())
}

/// An object as six projective fields on its bounding cube (see the module).
#[derive(Clone, Copy, Debug)]
pub struct Impostor<'a> {
    layout: Layout,
    fields: [HeightField<'a>; 6],
    maps: [Projective; 6],
}

/// [`Impostor::trace`]'s answer: the world hit (its `point` and `normal` in world
/// space, its `cell` in the face's field), the face whose field set it, and the
/// passes it took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpostorTrace<R: Real = f32> {
    /// The first hit and the fetches of every field's traces together.
    pub trace: Trace<R>,
    /// The face whose field the hit is on; `None` for a miss.
    pub face: Option<usize>,
    /// Field traces made.
    pub traces: u32,
}

impl<'a> Impostor<'a> {
    /// The impostor of the six fields on `layout`'s faces (in [`FACES`] order), each
    /// square with the same side.
    pub fn new(
        layout: Layout,
        fields: [HeightField<'a>; 6],
    ) -> Result<Impostor<'a>, ImpostorError> {
        let side = fields[0].width();
        if fields
            .iter()
            .any(|f| f.width() != side || f.height() != side)
        {
            return Err(ImpostorError::FieldsDiffer);
        }
        let mut maps = [layout.face_map(0, side)?; 6];
        for (face, m) in maps.iter_mut().enumerate().skip(1) {
            *m = layout.face_map(face, side)?;
        }
        Ok(Impostor {
            layout,
            fields,
            maps,
        })
    }

    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Face `face`'s field.
    pub fn field(&self, face: usize) -> &HeightField<'a> {
        &self.fields[face]
    }

    /// Face `face`'s map to its field's grid.
    pub fn map(&self, face: usize) -> &Projective {
        &self.maps[face]
    }

    /// Where the world point `p` falls on face `face`'s textures: grid x and y divided
    /// by `side − 1`, so `[0, 1]²` over the footprint at any texture side.
    pub fn texcoord(&self, face: usize, p: [f64; 3]) -> [f64; 2] {
        let g = self.maps[face].to_grid_h(p);
        let last = f64::from(self.fields[face].width() - 1);
        [g[0] / g[3] / last, g[1] / g[3] / last]
    }

    /// The face whose textures show the world point `p` of the object best, `n` its
    /// unit normal: of the faces whose field's surface passes within a grid unit of
    /// `p` (the faces that see it), the one whose projector line at `p` runs most
    /// nearly along `n`; `hit_face` (the face of the hit) when no other face sees it.
    /// Colour and normal textures read from it do not smear where the hit's own field
    /// sees the surface edge-on.
    pub fn texture_face(&self, p: [f64; 3], n: [f64; 3], hit_face: usize) -> usize {
        let mut best = (f64::NEG_INFINITY, hit_face);
        for (face, (hf, map)) in self.fields.iter().zip(&self.maps).enumerate() {
            let g = map.to_grid_h(p);
            let [x, y, z] = [g[0] / g[3], g[1] / g[3], g[2] / g[3]];
            let last = f64::from(hf.width() - 1);
            if !(g[3] > 0.0 && (0.0..=last).contains(&x) && (0.0..=last).contains(&y)) {
                continue;
            }
            let surface = crate::Surface::Triangles.height_at(hf, x, y);
            if (z - surface).abs() > 1.0 && face != hit_face {
                continue;
            }
            let (a, b) = (map.to_world([x, y, z]), map.to_world([x, y, z + 1.0]));
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let len = libm::sqrt(dot3(d, d));
            let along = if len > 0.0 {
                dot3(d, n).abs() / len
            } else {
                0.0
            };
            if along > best.0 {
                best = (along, face);
            }
        }
        best.1
    }

    /// Field `face`'s trace of the world ray `q` (its first point in the field's
    /// solid), the solid bounded below at grid height [`FLOOR`]: the grid ray's range
    /// is cut to where it is at or above the floor, so a ray that comes up through the
    /// floor under the surface hits there.
    fn field_trace<R: Real>(
        &self,
        face: usize,
        q: &Query<R>,
        march: &mut impl FnMut(&HeightField, &Query<R>) -> Trace<R>,
    ) -> Result<Trace<R>, RayError> {
        let (hf, map) = (&self.fields[face], &self.maps[face]);
        let Some(mapped) = map.map(hf, q)? else {
            return Ok(Trace::MISS);
        };
        let g = &mapped.grid;
        let (oz, dz) = (g.origin()[2].to_f64(), g.dir()[2].to_f64());
        let (mut s0, mut s1) = (g.t_min().to_f64(), g.t_max().to_f64());
        let at_floor = (f64::from(FLOOR) - oz) / dz;
        if dz > 0.0 {
            s0 = s0.max(at_floor);
        } else if dz < 0.0 {
            s1 = s1.min(at_floor);
        } else if oz < f64::from(FLOOR) {
            return Ok(Trace::MISS);
        }
        if s0 > s1 || s0.is_nan() {
            return Ok(Trace::MISS);
        }
        let grid = Query::from_arrays(g.origin(), g.dir(), R::from_f64(s0), R::from_f64(s1))?;
        Ok(map.trace_to_world(&mapped, march(hf, &grid)))
    }

    /// The first point of `world` in the object inside the cube as `combine` makes it
    /// of the six fields, each traced by `march` on its grid query (see the module).
    pub fn trace<R: Real>(
        &self,
        combine: Combine,
        world: &Query<R>,
        mut march: impl FnMut(&HeightField, &Query<R>) -> Trace<R>,
    ) -> Result<ImpostorTrace<R>, RayError> {
        let mut out = ImpostorTrace {
            trace: Trace::MISS,
            face: None,
            traces: 0,
        };
        let Some((t_in, t_out)) = self.layout.clip(world) else {
            return Ok(out);
        };
        let (t_end, mut t) = (R::from_f64(t_out), R::from_f64(t_in));
        if combine == Combine::FacingField {
            let k = facing_face(world.dir().map(R::to_f64));
            let q = Query::from_arrays(world.origin(), world.dir(), t, t_end)?;
            out.trace = self.field_trace(k, &q, &mut march)?;
            out.traces = 1;
            out.face = out.trace.hit.map(|_| k);
            return Ok(out);
        }
        // held[k]: the t at which field k last held the ray's point.
        let mut held: [Option<R>; 6] = [None; 6];
        let mut best: Option<(usize, Hit<R>)> = None;
        let mut fetches = 0u32;
        while let Some(k) = (0..6).find(|&k| held[k] != Some(t)) {
            if out.traces >= 6 * MAX_ROUNDS {
                out.trace.flags = Flags::BUDGET_EXHAUSTED;
                break;
            }
            out.traces += 1;
            let q = Query::from_arrays(world.origin(), world.dir(), t, t_end)?;
            let tr = self.field_trace(k, &q, &mut march)?;
            fetches = fetches.saturating_add(tr.fetches);
            let Some(h) = tr.hit else {
                out.trace.fetches = fetches;
                return Ok(out);
            };
            if h.t > t || best.is_none() {
                t = t.max(h.t);
                best = Some((k, h));
            }
            held[k] = Some(t);
        }
        if let Some((k, mut h)) = best {
            h.t = t;
            out.trace = Trace {
                hit: Some(h),
                fetches,
                clearance: R::ZERO,
                flags: out.trace.flags,
            };
            out.face = Some(k);
        }
        Ok(out)
    }
}

/// Twice the signed area of the grid-space triangle `a b p` (x and y only).
fn edge(a: [f64; 3], b: [f64; 3], p: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// `a · b`.
pub(crate) fn mat_mul(a: &Mat4, b: &Mat4) -> Mat4 {
    core::array::from_fn(|r| core::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

/// A procedural test object (`segments` ≥ 3 around): a tower of revolution (a
/// cylinder with flat bottom, a wider eave and a cone roof) with a ring around its
/// middle, tilted off the axes so that no face of it is axis-aligned. Vertical
/// walls, a concave gap between ring and body, a hole: the cases six fields find hard.
/// Returns positions and triangles (closed surfaces; about `12·segments` triangles).
#[cfg(feature = "alloc")]
pub fn procedural_tower(segments: u32) -> (alloc::vec::Vec<[f32; 3]>, alloc::vec::Vec<[u32; 3]>) {
    use alloc::vec::Vec;
    let n = segments.max(3);
    let (mut pos, mut tri) = (Vec::new(), Vec::new());
    // Revolves the (radius, height) profile, closed at both ends when the radius is 0.
    let mut revolve = |profile: &[(f64, f64)], around: [f64; 2]| {
        let base = pos.len() as u32;
        for &(r, z) in profile {
            for s in 0..n {
                let a = core::f64::consts::TAU * f64::from(s) / f64::from(n);
                pos.push([
                    around[0] + r * libm::cos(a),
                    around[1] + r * libm::sin(a),
                    z,
                ]);
            }
        }
        for ring in 0..profile.len() as u32 - 1 {
            for s in 0..n {
                let (a, b) = (base + ring * n + s, base + ring * n + (s + 1) % n);
                let (c, d) = (a + n, b + n);
                tri.push([a, b, d]);
                tri.push([a, d, c]);
            }
        }
    };
    let body = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 2.0),
        (1.4, 2.0),
        (1.4, 2.15),
        (0.0, 3.4),
    ];
    revolve(&body, [0.0, 0.0]);
    // The ring: a circle of radius 0.22 around (1.75, 1.0), revolved as a closed loop.
    let loop_: Vec<(f64, f64)> = (0..=12)
        .map(|k| {
            let a = core::f64::consts::TAU * f64::from(k) / 12.0;
            (1.75 + 0.22 * libm::cos(a), 1.0 + 0.22 * libm::sin(a))
        })
        .collect();
    revolve(&loop_, [0.0, 0.0]);
    // Tilt: 20° about x, then 30° about z.
    let (sx, cx) = (libm::sin(0.349), libm::cos(0.349));
    let (sz, cz) = (libm::sin(0.524), libm::cos(0.524));
    let positions = pos
        .iter()
        .map(|p: &[f64; 3]| {
            let (y, z) = (cx * p[1] - sx * p[2], sx * p[1] + cx * p[2]);
            let (x, y) = (cz * p[0] - sz * y, sz * p[0] + cz * y);
            [x as f32, y as f32, z as f32]
        })
        .collect();
    (positions, tri)
}
