//! The host side of the GPU bakes (`shaders/wgsl/bake_*.wgsl`, issue 27): the passes a
//! caller dispatches, in order, each with the uniform it binds and its workgroup
//! count. Bindings: `hf_heights` ([`wgsl_layout::HEIGHTS`](crate::wgsl_layout::HEIGHTS),
//! R32Float W × H), `hf_pyramid_out`
//! ([`wgsl_layout::PYRAMID_OUT`](crate::wgsl_layout::PYRAMID_OUT), a read-write storage
//! buffer of `maxmip::pyramid_len` floats) and `hf_maxmip_pass`
//! ([`wgsl_layout::MAXMIP_PASS`](crate::wgsl_layout::MAXMIP_PASS), [`MaxMipPass::uniform`]).
//! Each pass must finish before the next starts (a barrier between dispatches, as
//! separate compute passes give).

use hfcast::maxmip::{pyramid_len, Layout};

/// The side of `maxmip_bake_pass`'s square workgroups (`@workgroup_size(8, 8)`).
pub const MAXMIP_WORKGROUP: u32 = 8;

/// One dispatch of `maxmip_bake_pass`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaxMipPass {
    /// The level it writes.
    pub level: u32,
    /// Its `MaxMipPass` uniform as 32-bit words (48 bytes, little-endian on upload).
    pub uniform: [u32; 12],
    /// Workgroups along x and y.
    pub workgroups: [u32; 2],
}

impl MaxMipPass {
    fn new(layout: &Layout, level: u32, lo: [u32; 2], hi: [u32; 2]) -> MaxMipPass {
        let [w, _] = layout.dims(level);
        let finer = level.checked_sub(1);
        let finer_offset = finer.map_or(0, |f| layout.offset(f) as u32);
        let [fw, fh] = finer.map_or([0, 0], |f| layout.dims(f));
        MaxMipPass {
            level,
            uniform: [
                level,
                layout.offset(level) as u32,
                w,
                finer_offset,
                fw,
                fh,
                lo[0],
                lo[1],
                hi[0],
                hi[1],
                0,
                0,
            ],
            workgroups: [0, 1].map(|k| (hi[k] - lo[k]).div_ceil(MAXMIP_WORKGROUP)),
        }
    }

    /// The uniform's bytes.
    pub fn uniform_bytes(&self) -> Vec<u8> {
        self.uniform.iter().flat_map(|w| w.to_le_bytes()).collect()
    }
}

/// The layout of a `width × height` field whose pyramid has 32-bit texel offsets (what
/// the shader indexes with); `None` else.
fn layout32(width: u32, height: u32) -> Option<Layout> {
    let layout = Layout::new(width, height)?;
    u32::try_from(pyramid_len(width, height)).ok()?;
    Some(layout)
}

/// The passes that bake the whole pyramid of a `width × height` field, finest level
/// first (`maxmip::bake`); `None` for a size no field has or a pyramid of 2³² texels
/// or more (the shader's offsets are 32-bit).
pub fn maxmip_bake_passes(width: u32, height: u32) -> Option<Vec<MaxMipPass>> {
    let layout = layout32(width, height)?;
    Some(
        (0..layout.levels())
            .map(|l| MaxMipPass::new(&layout, l, [0, 0], layout.dims(l)))
            .collect(),
    )
}

/// The passes that refresh the pyramid after the samples `[x0, x1) × [y0, y1)`
/// changed (`maxmip::update_rect`), finest level first, each over the texels that
/// depend on them only: none for an empty rectangle, `None` for a size
/// [`maxmip_bake_passes`] refuses or a rectangle outside the field.
pub fn maxmip_update_passes(
    width: u32,
    height: u32,
    [x0, y0, x1, y1]: [u32; 4],
) -> Option<Vec<MaxMipPass>> {
    let layout = layout32(width, height)?;
    if x0 > x1 || y0 > y1 || x1 > width || y1 > height {
        return None;
    }
    if x0 == x1 || y0 == y1 {
        return Some(Vec::new());
    }
    Some(
        layout
            .update_ranges(x0, y0, x1, y1)
            .map(|(l, lo, hi)| MaxMipPass::new(&layout, l, lo, hi))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_workgroup_is_the_shaders() {
        let src = crate::file(crate::Lang::Wgsl, "bake_maxmip").expect("bake_maxmip.wgsl");
        let size = format!("@workgroup_size({MAXMIP_WORKGROUP}, {MAXMIP_WORKGROUP})");
        assert!(src.contains(&size), "bake_maxmip.wgsl lacks {size}");
    }

    #[test]
    fn passes_cover_each_level_and_an_update_only_its_texels() {
        let bake = maxmip_bake_passes(13, 6).unwrap();
        let layout = Layout::new(13, 6).unwrap();
        assert_eq!(bake.len() as u32, layout.levels());
        assert_eq!(bake[0].uniform[..3], [0, 0, 12]);
        assert_eq!(bake[1].uniform[..6], [1, 60, 6, 0, 12, 5]);
        assert_eq!(bake[0].workgroups, [2, 1]);
        let up = maxmip_update_passes(13, 6, [4, 2, 5, 3]).unwrap();
        // Sample (4, 2) is a corner of cells 3..5 × 1..3.
        assert_eq!(up[0].uniform[6..10], [3, 1, 5, 3]);
        assert_eq!(up.last().unwrap().uniform[6..10], [0, 0, 1, 1]);
        assert_eq!(maxmip_update_passes(13, 6, [4, 2, 4, 3]), Some(Vec::new()));
        assert_eq!(maxmip_update_passes(13, 6, [4, 2, 14, 3]), None);
        assert_eq!(maxmip_bake_passes(1, 6), None);
        // Over 2³² texels: 65536² samples.
        assert_eq!(maxmip_bake_passes(65536, 65536), None);
    }
}
