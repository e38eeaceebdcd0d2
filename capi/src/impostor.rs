//! Six-field impostors (`hfcast::impostor`; Baboud & Décoret 2006, §4): a triangle
//! mesh's bounding cube and its faces' frusta (`hf_impostor_layout`), the capture of
//! each face's height field, and the trace of the object the six fields make.

use crate::detail::{fail, fail_at};
use crate::hf_result::{self, *};
use crate::ptr::{self, Named};
use crate::trace::{hf_hit, hf_ray, ray_error};
use crate::{guard, surface_of, HF_MAX_SIDE};
use hfcore::impostor::{rasterize, Combine, Frustum, Impostor, ImpostorError, Layout, Mesh};
use hfcore::projective::Mat4;
use hfcore::{dda, FieldError, HeightField, Query};

/// The height `hf_impostor_capture` stores where a sample's projector line misses the
/// mesh: one grid unit under the opposite face, so that nothing there is solid.
pub const HF_IMPOSTOR_EMPTY: f32 = -1.0;

/// The grid height under which no field's solid reaches (half a grid unit under the
/// object's far end along the face's normal): each field's region is its footprint
/// times heights from this to `side − 1`, the frustum to draw for it unclipped.
pub const HF_IMPOSTOR_FLOOR: f32 = -0.5;

/// The triangle `hf_impostor_capture` stores where a sample's projector line misses
/// the mesh, and the face `hf_impostor_trace_batch` reports for a miss.
pub const HF_IMPOSTOR_NONE: u32 = u32::MAX;

/// How each face's field projects the object (`hf_impostor_layout::frustum`). Passed
/// as `uint32_t`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum hf_impostor_frustum {
    /// Projector lines along the face's normal.
    HF_IMPOSTOR_ORTHOGRAPHIC = 0,
    /// Reverse perspective (Baboud & Décoret §4): projector lines from a centre `apex`
    /// half sides behind the cube's centre, on the side away from the face, fanning out
    /// towards the face, so that a field holds the object's sides as well as its top.
    HF_IMPOSTOR_REVERSE_PERSPECTIVE = 1,
}

/// The bounding cube of an impostor and its six faces' maps, filled by
/// `hf_impostor_layout_around` (or by the caller, for a cube of its own). Faces are
/// numbered 0 to 5 with outward normals +x, −x, +y, −y, +z, −z; each face's grid x and
/// y run along +y and +z (face 0), +z and +y (1), +z and +x (2), +x and +z (3), +x and
/// +y (4), +y and +x (5); its heights rise towards the face.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct hf_impostor_layout {
    /// The cube's centre (world units).
    pub center: [f64; 3],
    /// The cube's half side (world units), finite and > 0.
    pub half: f64,
    /// The frustum of every face, an `hf_impostor_frustum`.
    pub frustum: u32,
    /// For `HF_IMPOSTOR_REVERSE_PERSPECTIVE`, the distance of the centre of projection
    /// from the cube's centre in half sides: finite and > 1, or 0 for the default (2).
    /// Ignored for `HF_IMPOSTOR_ORTHOGRAPHIC`.
    pub apex: f64,
    /// Each face's map from world points `[x, y, z, 1]` to its unit cube (homogeneous;
    /// row-major 4×4): grid x and y in [0, 1] across the face's footprint, z rising to
    /// 1 towards the face. Each must be finite and invertible.
    pub units: [[f64; 16]; 6],
}

impl From<ImpostorError> for hf_result {
    fn from(e: ImpostorError) -> Self {
        use ImpostorError as E;
        let code = match e {
            E::NoTriangles | E::BadSide | E::FieldsDiffer => HF_ERR_INVALID_SIZE,
            E::NotFinite => HF_ERR_NOT_FINITE,
            E::IndexOutOfRange | E::NoExtent | E::BadApex | E::Map(_) => HF_ERR_INVALID_ARGUMENT,
            E::BufferTooSmall => HF_ERR_BUFFER_TOO_SMALL,
        };
        fail(code, e)
    }
}

/// The core's frustum of `frustum` (an `hf_impostor_frustum`) and `apex` (0: the
/// default reverse perspective's).
fn frustum_of(frustum: u32, apex: f64) -> Result<Frustum, hf_result> {
    match frustum {
        0 => Ok(Frustum::Orthographic),
        1 if apex == 0.0 => Ok(Frustum::DEFAULT_REVERSE),
        1 => Ok(Frustum::ReversePerspective { apex }),
        _ => Err(fail(
            HF_ERR_INVALID_ENUM,
            format_args!("frustum: {frustum} is not an hf_impostor_frustum"),
        )),
    }
}

/// The core's layout of `l`, checked (`Layout::from_parts`).
fn layout_of(l: &hf_impostor_layout) -> Result<Layout, hf_result> {
    let units = l
        .units
        .map(|u| -> Mat4 { core::array::from_fn(|r| core::array::from_fn(|c| u[4 * r + c])) });
    Ok(Layout::from_parts(
        l.center,
        l.half,
        frustum_of(l.frustum, l.apex)?,
        units,
    )?)
}

/// `m`'s entries, row after row.
fn rows(m: &Mat4) -> [f64; 16] {
    core::array::from_fn(|k| m[k / 4][k % 4])
}

/// The C form of a core layout.
fn c_layout(l: &Layout) -> hf_impostor_layout {
    let (frustum, apex) = match l.frustum() {
        Frustum::Orthographic => (hf_impostor_frustum::HF_IMPOSTOR_ORTHOGRAPHIC, 0.0),
        Frustum::ReversePerspective { apex } => {
            (hf_impostor_frustum::HF_IMPOSTOR_REVERSE_PERSPECTIVE, apex)
        }
    };
    hf_impostor_layout {
        center: l.center(),
        half: l.half(),
        frustum: frustum as u32,
        apex,
        units: core::array::from_fn(|k| rows(&l.face_unit(k))),
    }
}

/// Checks a face number (0 to 5).
fn face_of(face: u32) -> Result<usize, hf_result> {
    if face >= 6 {
        return Err(fail(
            HF_ERR_INVALID_ARGUMENT,
            format_args!("face: {face} is not 0 to 5"),
        ));
    }
    Ok(face as usize)
}

/// The samples of one face's field, `side²`, for a side of 2 to `HF_MAX_SIDE`.
fn field_len(side: u32) -> Result<usize, hf_result> {
    let n = usize::try_from(u64::from(side) * u64::from(side));
    match n {
        Ok(n) if (2..=HF_MAX_SIDE).contains(&side) => Ok(n),
        _ => Err(fail(
            HF_ERR_INVALID_SIZE,
            format_args!("side {side}: must be 2 to {HF_MAX_SIDE}"),
        )),
    }
}

/// The mesh of `vertex_count` positions (three floats each) and `triangle_count`
/// triangles (three vertex indices each), checked.
///
/// # Safety
/// Each pointer NULL (an error) or valid for reading its count of triples, not written
/// while the mesh lives.
unsafe fn mesh<'a>(
    positions: *const f32,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
) -> Result<Mesh<'a>, hf_result> {
    // SAFETY: the caller's promises; a triple of floats (indices) has their alignment.
    let (p, t) = unsafe {
        (
            ptr::slice(positions.cast::<[f32; 3]>(), vertex_count).named("positions")?,
            ptr::slice(triangles.cast::<[u32; 3]>(), triangle_count).named("triangles")?,
        )
    };
    Ok(Mesh::new(p, t)?)
}

/// Writes the number of samples of one face's field of `side × side` to `*out_len`:
/// `side²`, the length of `hf_impostor_capture`'s buffers (`hf_impostor_trace_batch`
/// reads six). `HF_ERR_INVALID_SIZE` for a side under 2 or over `HF_MAX_SIDE`. Thread
/// safe.
///
/// # Safety
/// `out_len` is NULL (an error) or valid for writing one `size_t`.
#[no_mangle]
pub unsafe extern "C" fn hf_impostor_field_len(side: u32, out_len: *mut usize) -> hf_result {
    // SAFETY: the caller's promise, passed on.
    unsafe { ptr::answer(|| field_len(side), out_len, Ok) }
}

/// Writes the layout of the mesh (`vertex_count` positions of three floats,
/// `triangle_count` triangles of three vertex indices) to `*out_layout`: the cube around
/// its vertices (half side 1 % over half the largest extent) and each face's footprint
/// and height range fitted to the mesh as that face projects it, with `frustum` (an
/// `hf_impostor_frustum`; `apex` as `hf_impostor_layout::apex`, 0 for the default).
/// `HF_ERR_NOT_FINITE` for a NaN or infinite position, `HF_ERR_INVALID_SIZE` for no
/// triangles, `HF_ERR_INVALID_ARGUMENT` for a vertex index past `vertex_count`, a mesh
/// whose vertices are all one point, or a reverse perspective's apex NaN, infinite or
/// at most 1 (but not 0), `HF_ERR_INVALID_ENUM` for an unknown frustum. Thread safe.
///
/// # Safety
/// `positions` (3 × `vertex_count` floats) and `triangles` (3 × `triangle_count`
/// indices) are NULL (an error) or valid for reading; `out_layout` NULL (an error) or
/// valid for writing one `hf_impostor_layout`.
#[no_mangle]
pub unsafe extern "C" fn hf_impostor_layout_around(
    positions: *const f32,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    frustum: u32,
    apex: f64,
    out_layout: *mut hf_impostor_layout,
) -> hf_result {
    guard(|| {
        let out = ptr::out(out_layout).named("out_layout")?;
        let frustum = frustum_of(frustum, apex)?;
        // SAFETY: the caller's promises, passed on; the mesh is not used after this.
        let layout = Layout::around(
            &unsafe { mesh(positions, vertex_count, triangles, triangle_count) }?,
            frustum,
        )?;
        // SAFETY: the caller promises `out_layout` is writable.
        unsafe { out.set(c_layout(&layout)) };
        Ok(())
    })
}

/// Writes face `face`'s map to the grid of a `side × side` field (16 doubles,
/// row-major) to `out_matrix`: world points `[x, y, z, 1]` to homogeneous grid points
/// whose heights span `side − 1` grid units, as `hf_projective_trace_batch` and the
/// shaders' `hf_trace_projective` take it. `HF_ERR_INVALID_ARGUMENT` for a face over 5
/// or a layout `hf_impostor_layout_around` would not give (a singular map, an apex not >
/// 1, a half side not > 0), `HF_ERR_NOT_FINITE` for a NaN or infinite centre or half
/// side, `HF_ERR_INVALID_ENUM` for an unknown frustum, `HF_ERR_INVALID_SIZE` for a side
/// under 2 or over `HF_MAX_SIDE`. Thread safe.
///
/// # Safety
/// `layout` is NULL (an error) or valid for reading; `out_matrix` NULL (an error) or
/// valid for writing 16 doubles.
#[no_mangle]
pub unsafe extern "C" fn hf_impostor_face_map(
    layout: *const hf_impostor_layout,
    face: u32,
    side: u32,
    out_matrix: *mut f64,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `layout` is readable (read before any output).
        let layout = layout_of(unsafe { ptr::get(layout) }.named("layout")?)?;
        let map = layout.face_map(face_of(face)?, side)?;
        // SAFETY: the caller promises 16 writable doubles.
        let out = unsafe { ptr::slice_mut(out_matrix, 16) }.named("out_matrix")?;
        out.copy_from_slice(&rows(map.matrix()));
        Ok(())
    })
}

/// Captures face `face`'s field of the mesh (as `hf_impostor_layout_around` takes it)
/// on `layout` at `side × side` into `heights` (`side²` floats, row-major): each
/// sample holds the grid height of the mesh's point nearest the face on its projector
/// line (exact rasterization in double), `HF_IMPOSTOR_EMPTY` where the line misses the
/// mesh; and, when `triangle_ids` is not NULL, that point's triangle
/// (`HF_IMPOSTOR_NONE` where none) into it, for colour and normal textures. With
/// `pad_silhouettes` 1 the empty samples next to the object are then raised to its
/// height (the highest of their eight neighbours), so that no cell across a
/// silhouette ramps down into it: what `hf_impostor_trace_batch` wants. Buffers
/// shorter than `side²` are `HF_ERR_BUFFER_TOO_SMALL` (`hf_impostor_field_len`), an
/// output sharing a byte with another buffer `HF_ERR_INVALID_ARGUMENT`, as are a face
/// over 5 and `pad_silhouettes` not 0 or 1; mesh and layout errors as
/// `hf_impostor_layout_around` and `hf_impostor_face_map`. Thread safe (for distinct
/// output buffers).
///
/// # Safety
/// As `hf_impostor_layout_around` for the mesh; `layout` NULL (an error) or valid for
/// reading; `heights` NULL (an error) or valid for writing `heights_len` floats;
/// `triangle_ids` NULL or valid for writing `triangle_ids_len` indices.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_impostor_capture(
    positions: *const f32,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    layout: *const hf_impostor_layout,
    face: u32,
    side: u32,
    pad_silhouettes: u32,
    heights: *mut f32,
    heights_len: usize,
    triangle_ids: *mut u32,
    triangle_ids_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `layout` is readable (read before any output).
        let layout = layout_of(unsafe { ptr::get(layout) }.named("layout")?)?;
        let map = layout.face_map(face_of(face)?, side)?;
        let pad = match pad_silhouettes {
            0 | 1 => pad_silhouettes == 1,
            _ => {
                let why = "pad_silhouettes: must be 0 or 1";
                return Err(fail(HF_ERR_INVALID_ARGUMENT, why));
            }
        };
        let ins = [
            ptr::span(positions.cast::<[f32; 3]>(), vertex_count, "positions")?,
            ptr::span(triangles.cast::<[u32; 3]>(), triangle_count, "triangles")?,
        ];
        let out = ptr::span(heights, heights_len, "heights")?;
        let ids = (!triangle_ids.is_null())
            .then(|| ptr::span(triangle_ids, triangle_ids_len, "triangle_ids"))
            .transpose()?;
        ptr::apart(&[&ins[0], &ins[1]], &[Some(&out), ids.as_ref()])?;
        // SAFETY: the caller's promises, passed on; the outputs are apart from the mesh.
        let mesh = unsafe { mesh(positions, vertex_count, triangles, triangle_count) }?;
        // SAFETY: checked apart from the mesh and each other; writable by the caller's
        // promise.
        let (heights, ids) = unsafe {
            let ids = match ids {
                Some(_) => Some(ptr::slice_mut(triangle_ids, triangle_ids_len)?),
                None => None,
            };
            (ptr::slice_mut(heights, heights_len)?, ids)
        };
        // Checks the buffers' lengths before writing anything.
        rasterize(&mesh, &map, side, heights, ids)?;
        if pad {
            hfcore::impostor::pad_silhouettes(heights, side)?;
        }
        Ok(())
    })
}

/// Traces `rays_len` world rays into the impostor of the six fields `heights` (six
/// `side × side` fields, face 0 to face 5, each as `hf_impostor_capture` fills it) on
/// `layout`: `out_hits[k]` answers `rays[k]` with the first point of the object in the
/// cube, each field traced by the exact DDA on `surface` (an `hf_surface`) in `float`,
/// and `out_faces[k]` (when `out_faces` is not NULL) is the face whose field the hit is
/// on (`HF_IMPOSTOR_NONE` for a miss). `combine` (an `hf_impostor_combine`) makes the
/// object: `HF_IMPOSTOR_INTERSECTION` the first point inside all six solids (each field
/// carves what it sees; its hit's normal and face are those of the field that set `t`
/// last; after 64 passes unsettled it stops there, flagged
/// `HF_FLAG_BUDGET_EXHAUSTED`), `HF_IMPOSTOR_FACING_FIELD` the hit of the one field the
/// ray faces most directly (the face whose outward normal is most against `dir`; the
/// first axis of largest `|dir|`). The hit's `t`, `point` and `normal` are the world
/// ray's; `cell` is in the face's field; `fetches` counts every field's traces;
/// `clearance` is not meaningful. On the calling thread. Errors as `hf_trace_batch`
/// (every ray checked before any is traced; an error writes nothing), plus
/// `HF_ERR_BUFFER_TOO_SMALL` for `heights_len` under `6 · side²`, `HF_ERR_NOT_FINITE`
/// for a NaN or infinite height (`hf_last_error_index` gives it), layout errors as
/// `hf_impostor_face_map`, `HF_ERR_INVALID_ENUM` for an unknown surface or combine.
/// Thread safe.
///
/// # Safety
/// `layout` is NULL (an error) or valid for reading; `heights` NULL (an error) or
/// valid for reading `heights_len` floats; `rays` NULL (an error) or valid for
/// reading `rays_len` rays; `out_hits` NULL (an error) or valid for writing
/// `out_hits_len` hits; `out_faces` NULL or valid for writing `out_faces_len` faces.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn hf_impostor_trace_batch(
    layout: *const hf_impostor_layout,
    heights: *const f32,
    heights_len: usize,
    side: u32,
    surface: u32,
    combine: u32,
    rays: *const hf_ray,
    rays_len: usize,
    out_hits: *mut hf_hit,
    out_hits_len: usize,
    out_faces: *mut u32,
    out_faces_len: usize,
) -> hf_result {
    guard(|| {
        // SAFETY: the caller promises `layout` is readable (read before any output).
        let layout = layout_of(unsafe { ptr::get(layout) }.named("layout")?)?;
        let surface = surface_of(surface)?;
        let combine = Combine::from_u32(combine).ok_or_else(|| {
            let why = format_args!("combine: {combine} is not an hf_impostor_combine");
            fail(HF_ERR_INVALID_ENUM, why)
        })?;
        let n = field_len(side)?;
        let ins = [
            ptr::span(heights, heights_len, "heights")?,
            ptr::span(rays, rays_len, "rays")?,
        ];
        let hits_span = ptr::span(out_hits, out_hits_len, "out_hits")?;
        let faces_span = (!out_faces.is_null())
            .then(|| ptr::span(out_faces, out_faces_len, "out_faces"))
            .transpose()?;
        ptr::apart(
            &[&ins[0], &ins[1]],
            &[Some(&hits_span), faces_span.as_ref()],
        )?;
        let short = |name: &str, len: usize, needed: usize| {
            let why = format_args!("{name}: {len} elements, {needed} needed");
            Err(fail(HF_ERR_BUFFER_TOO_SMALL, why))
        };
        match n.checked_mul(6) {
            Some(total) if total <= heights_len => {}
            total => return short("heights", heights_len, total.unwrap_or(usize::MAX)),
        }
        if out_hits_len < rays_len {
            return short("out_hits", out_hits_len, rays_len);
        }
        if faces_span.is_some() && out_faces_len < rays_len {
            return short("out_faces", out_faces_len, rays_len);
        }
        // SAFETY: the caller promises both readable, not written during the call.
        let (heights, rays) = unsafe { (ptr::slice(heights, 6 * n)?, ptr::slice(rays, rays_len)?) };
        let field = |k: usize| {
            let samples = &heights[k * n..(k + 1) * n];
            HeightField::new(samples, side, side, side as usize).map_err(|e| match e {
                FieldError::NotFinite { index } => fail_at(
                    HF_ERR_NOT_FINITE,
                    Some(k * n + index),
                    format_args!("heights[{}] is NaN or infinite", k * n + index),
                ),
                e => hf_result::from(e),
            })
        };
        let mut fields = [field(0)?; 6];
        for (k, f) in fields.iter_mut().enumerate().skip(1) {
            *f = field(k)?;
        }
        let impostor = Impostor::new(layout, fields)?;
        let queries = rays
            .iter()
            .enumerate()
            .map(|(k, r)| {
                Query::<f32>::from_arrays(r.origin, r.dir, r.t_min, r.t_max)
                    .map_err(|e| ray_error(e, Some(k)))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let answers = queries
            .iter()
            .enumerate()
            .map(|(k, q)| {
                let r = impostor
                    .trace(combine, q, |hf, g| dda::trace(hf, surface, g))
                    .map_err(|e| ray_error(e, Some(k)))?;
                Ok((
                    hf_hit::from(r.trace),
                    r.face.map_or(HF_IMPOSTOR_NONE, |f| f as u32),
                ))
            })
            .collect::<Result<Vec<_>, hf_result>>()?;
        // SAFETY: checked apart from the inputs and each other, long enough; writable
        // by the caller's promise.
        let hits = unsafe { ptr::slice_mut(out_hits, rays_len) }?;
        for (h, a) in hits.iter_mut().zip(&answers) {
            *h = a.0;
        }
        if faces_span.is_some() {
            // SAFETY: as `hits`.
            let faces = unsafe { ptr::slice_mut(out_faces, rays_len) }?;
            for (f, a) in faces.iter_mut().zip(&answers) {
                *f = a.1;
            }
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hfcore::impostor::{EMPTY, FACES, FLOOR, NO_TRIANGLE};

    #[test]
    fn constants_and_faces_match_the_core() {
        assert_eq!(HF_IMPOSTOR_EMPTY, EMPTY);
        assert_eq!(HF_IMPOSTOR_FLOOR, FLOOR);
        assert_eq!(HF_IMPOSTOR_NONE, NO_TRIANGLE);
        // The faces' normals and grid axes as hf_impostor_layout's comment lists them.
        let axes = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 2, 0],
            [1, 0, 2],
            [2, 0, 1],
            [2, 1, 0],
        ];
        for (k, [n, x, y]) in FACES.iter().enumerate() {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            assert_eq!(n[axes[k][0]], sign, "face {k}");
            assert_eq!((x[axes[k][1]], y[axes[k][2]]), (1.0, 1.0), "face {k}");
        }
    }

    #[test]
    fn layouts_go_through_c_unchanged() {
        let p = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.5]];
        let mesh = Mesh::new(&p, &[[0, 1, 2]]).unwrap();
        for f in [Frustum::Orthographic, Frustum::DEFAULT_REVERSE] {
            let l = Layout::around(&mesh, f).unwrap();
            assert_eq!(layout_of(&c_layout(&l)), Ok(l));
        }
    }
}
