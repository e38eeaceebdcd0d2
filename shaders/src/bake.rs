//! The host side of the GPU bakes (`shaders/{wgsl,glsl}/bake_*`, issue 27): the passes
//! a caller dispatches, in order, each with the uniform it binds and its workgroup
//! count. Each pass must finish before the next starts (a barrier between dispatches,
//! as separate compute passes give in wgpu, `glMemoryBarrier` in OpenGL).
//!
//! - `bake_maxmip` (feature `maxmip`): `hf_heights`
//!   ([`wgsl_layout::HEIGHTS`](crate::wgsl_layout::HEIGHTS), R32Float W × H),
//!   `hf_pyramid_out` ([`wgsl_layout::PYRAMID_OUT`](crate::wgsl_layout::PYRAMID_OUT), a
//!   read-write storage buffer of `maxmip::pyramid_len` floats) and `hf_maxmip_pass`
//!   ([`wgsl_layout::MAXMIP_PASS`](crate::wgsl_layout::MAXMIP_PASS),
//!   [`MaxMipPass::uniform`]).
//! - `bake_safety` (feature `safety`; the device needs 64-bit floats): `hf_heights`,
//!   `hf_safety_scratch` ([`wgsl_layout::SAFETY_SCRATCH`](crate::wgsl_layout::SAFETY_SCRATCH),
//!   `safety::scratch_len` floats), `hf_safety_out`
//!   ([`wgsl_layout::SAFETY_OUT`](crate::wgsl_layout::SAFETY_OUT), the map's bytes
//!   rounded up to whole words) and `hf_safety_pass`
//!   ([`wgsl_layout::SAFETY_PASS`](crate::wgsl_layout::SAFETY_PASS)), all bound whole,
//!   passes from [`safety_bake_passes`].
//! - `bake_nbuffer` (feature `safety`): `hf_heights`, `hf_nbuffer`
//!   ([`wgsl_layout::NBUFFER`](crate::wgsl_layout::NBUFFER), a read-write
//!   storage buffer of `cc::nbuffer_len` floats, each pass binding the range
//!   [`BakePass::bind_offset`], [`BakePass::bind_size`] of it) and `hf_nbuffer_pass`
//!   ([`wgsl_layout::NBUFFER_PASS`](crate::wgsl_layout::NBUFFER_PASS),
//!   [`BakePass::uniform`] of [`nbuffer_bake_passes`]).

#[cfg(feature = "maxmip")]
use hfcast::maxmip::{pyramid_len, Layout};

/// The side of every GPU bake's square workgroups (`@workgroup_size(8, 8)`).
pub const WORKGROUP: u32 = 8;

/// The side of `maxmip_bake_pass`'s square workgroups.
pub const MAXMIP_WORKGROUP: u32 = WORKGROUP;

/// Byte alignment of a pass's bound range: the largest storage-buffer offset
/// alignment WebGPU and OpenGL allow a device to require.
pub const BIND_ALIGN: u64 = 256;

/// One dispatch of `nbuffer_bake_pass`: one step of `cc::nbuffer_steps`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BakePass {
    /// Its `NbufferPass` uniform as 32-bit words (32 bytes, little-endian on upload):
    /// kind, axis, rows, row length, first element written and first element read
    /// (both counted from the bound range's start), half, columns.
    pub uniform: [u32; 8],
    /// Workgroups along x (along a row) and y (across rows).
    pub workgroups: [u32; 2],
    /// The part of the output buffer the pass binds: from this byte (a multiple of
    /// [`BIND_ALIGN`]) …
    pub bind_offset: u64,
    /// … this many bytes: what it reads and writes, at most two levels of one axis, so
    /// that a field whose whole N-buffers exceed a device's binding limit still bakes.
    pub bind_size: u64,
}

impl BakePass {
    /// The uniform's bytes.
    pub fn uniform_bytes(&self) -> Vec<u8> {
        self.uniform.iter().flat_map(|w| w.to_le_bytes()).collect()
    }
}

/// The source of the GPU cylinder–cone bake (N-buffer slopes) in `lang`: `bake_safety`
/// (WGSL: its entry point `cc_bake_pass`; GLSL: with `HF_CC_BAKE` defined after the
/// `#version` line, which selects that entry as `main`).
#[cfg(feature = "safety")]
pub fn cc_bake_source(lang: crate::Lang) -> Option<String> {
    let text = crate::file(lang, "bake_safety")?;
    Some(match lang {
        crate::Lang::Wgsl => text.to_string(),
        crate::Lang::Glsl => {
            let version = "#version 430 core\n";
            text.replacen(version, &format!("{version}#define HF_CC_BAKE 1\n"), 1)
        }
    })
}

/// The two passes of the GPU cylinder–cone bake of a `width × height` field for every
/// ray with N-buffer slopes and the cone reach `cap` (`cc::bake` with
/// `Slope::NBuffer`): the strip bounds into `hf_safety_scratch`, then the map (`[r,
/// s]` per texel and class, two entries to a word) into `hf_safety_out`, reading the
/// N-buffers of [`nbuffer_bake_passes`] for the same `cap` from `hf_nbuffer`. `None`
/// as [`safety_bake_passes`], or N-buffers of 2³² floats or more.
#[cfg(feature = "safety")]
pub fn cc_bake_passes(width: u32, height: u32, cap: u8) -> Option<Vec<BakePass>> {
    nbuffer_bake_passes(width, height, cap)?;
    let mut passes = safety_bake_passes(width, height, false, u8::MAX, false)?;
    let bytes = u32::try_from(hfcast::safety::cc::map_len(width, height)).ok()?;
    let words = bytes / 4;
    passes[1] = grid_pass(
        2,
        words,
        4 * u64::from(words),
        [width, height, 0, u32::from(cap), 0],
    );
    Some(passes)
}

/// A pass of the safety shader over `items` items in a grid of 8 × 8 workgroups (at
/// most 65535 along x), its uniform `[kind, head…, items, grid width]`, binding
/// `written` bytes.
#[cfg(feature = "safety")]
fn grid_pass(kind: u32, items: u32, written: u64, head: [u32; 5]) -> BakePass {
    let across = items.div_ceil(WORKGROUP).clamp(1, 65535);
    let grid_width = across * WORKGROUP;
    let rows = items.div_ceil(grid_width).div_ceil(WORKGROUP).max(1);
    let [w, h, iso, cap, least] = head;
    BakePass {
        uniform: [kind, w, h, iso, cap, least, items, grid_width],
        workgroups: [across, rows],
        bind_offset: 0,
        bind_size: written,
    }
}

/// The two passes of the GPU safety-distance bake of a `width × height` field for every
/// ray (`safety::bake` with `AllRays`): the strip bounds into `hf_safety_scratch`, then
/// the map (directional, or `isotropic`; distances at most `cap`, at least 1 when
/// `positive`) into `hf_safety_out`, four bytes to a word. Each pass's `bind_offset`
/// and `bind_size` are the whole buffer it writes. `None` for a size no field has, or a
/// map or scratch of 2³² bytes or floats or more (the shader's indices are 32-bit).
#[cfg(feature = "safety")]
pub fn safety_bake_passes(
    width: u32,
    height: u32,
    isotropic: bool,
    cap: u8,
    positive: bool,
) -> Option<Vec<BakePass>> {
    use hfcast::safety::{self, Variant};
    let side = |n: u32| (2..=hfcast::field::MAX_SIDE).contains(&n);
    if !side(width) || !side(height) {
        return None;
    }
    let variant = if isotropic {
        Variant::Isotropic
    } else {
        Variant::Directional
    };
    let bytes = u32::try_from(safety::map_len(width, height, variant)).ok()?;
    let scratch = safety::scratch_len(width, height);
    u32::try_from(scratch).ok()?;
    let strip_slots = (scratch / 3) as u32;
    let words = bytes.div_ceil(4);
    let pass = |kind: u32, items: u32, written: u64| {
        // A grid of 8 × 8 workgroups, at most 65535 along x.
        let across = items.div_ceil(WORKGROUP).clamp(1, 65535);
        let grid_width = across * WORKGROUP;
        let rows = items.div_ceil(grid_width).div_ceil(WORKGROUP).max(1);
        let head = [kind, width, height, u32::from(isotropic), u32::from(cap)];
        BakePass {
            uniform: [
                head[0],
                head[1],
                head[2],
                head[3],
                head[4],
                u32::from(positive),
                items,
                grid_width,
            ],
            workgroups: [across, rows],
            bind_offset: 0,
            bind_size: written,
        }
    };
    Some(vec![
        pass(0, strip_slots, 4 * scratch as u64),
        pass(1, words, 4 * u64::from(words)),
    ])
}

/// The passes that fill the N-buffers of a `width × height` field for the cone reach
/// `cap` (`cc::prepare_nbuffer`), in order (steps without rows left out); `None` for a
/// size no field has or N-buffers of 2³² floats or more (the shader's offsets are
/// 32-bit).
#[cfg(feature = "safety")]
pub fn nbuffer_bake_passes(width: u32, height: u32, cap: u8) -> Option<Vec<BakePass>> {
    use hfcast::safety::cc;
    let side = |n: u32| (2..=hfcast::field::MAX_SIDE).contains(&n);
    if !side(width) || !side(height) {
        return None;
    }
    u32::try_from(cc::nbuffer_len(width, height, cap)).ok()?;
    Some(
        cc::nbuffer_steps(width, height, cap)
            .filter(|s| s.rows > 0)
            .map(|s| {
                // Elements, from the first read (or written) to the last written.
                let float = 4u64;
                let first = (s.src.min(s.dst) as u64 * float) / BIND_ALIGN * BIND_ALIGN;
                let end = (s.dst + s.rows as usize * s.row_len as usize) as u64 * float;
                let skip = (first / float) as usize;
                BakePass {
                    uniform: [
                        s.kind as u32,
                        s.axis,
                        s.rows,
                        s.row_len,
                        (s.dst - skip) as u32,
                        (s.src - skip) as u32,
                        s.half,
                        s.columns,
                    ],
                    workgroups: [s.row_len.div_ceil(WORKGROUP), s.rows.div_ceil(WORKGROUP)],
                    bind_offset: first,
                    bind_size: end - first,
                }
            })
            .collect(),
    )
}

/// One dispatch of `maxmip_bake_pass`.
#[cfg(feature = "maxmip")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaxMipPass {
    /// The level it writes.
    pub level: u32,
    /// Its `MaxMipPass` uniform as 32-bit words (48 bytes, little-endian on upload).
    pub uniform: [u32; 12],
    /// Workgroups along x and y.
    pub workgroups: [u32; 2],
}

#[cfg(feature = "maxmip")]
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

#[cfg(feature = "maxmip")]
/// The layout of a `width × height` field whose pyramid has 32-bit texel offsets (what
/// the shader indexes with); `None` else.
fn layout32(width: u32, height: u32) -> Option<Layout> {
    let layout = Layout::new(width, height)?;
    u32::try_from(pyramid_len(width, height)).ok()?;
    Some(layout)
}

#[cfg(feature = "maxmip")]
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

#[cfg(feature = "maxmip")]
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
        for stem in ["bake_maxmip", "bake_nbuffer"] {
            let wgsl = crate::file(crate::Lang::Wgsl, stem).expect("a bake");
            let size = format!("@workgroup_size({WORKGROUP}, {WORKGROUP})");
            assert!(wgsl.contains(&size), "{stem}.wgsl lacks {size}");
            let glsl = crate::file(crate::Lang::Glsl, stem).expect("a bake");
            let size =
                format!("layout(local_size_x = {WORKGROUP}, local_size_y = {WORKGROUP}) in;");
            assert!(glsl.contains(&size), "{stem}.glsl lacks {size}");
        }
    }

    #[cfg(feature = "safety")]
    #[test]
    fn safety_passes_cover_the_slots_and_words() {
        use hfcast::safety;
        let p = safety_bake_passes(13, 6, false, 255, false).unwrap();
        assert_eq!(p.len(), 2);
        let slots = safety::scratch_len(13, 6) as u32 / 3;
        assert_eq!(
            p[0].uniform,
            [0, 13, 6, 0, 255, 0, slots, 8 * slots.div_ceil(8)]
        );
        assert_eq!(p[1].uniform[6], 13 * 6);
        for q in &p {
            let invocations = 64 * q.workgroups[0] * q.workgroups[1];
            assert!(invocations >= q.uniform[6] && q.uniform[7] == 8 * q.workgroups[0]);
        }
        let iso = safety_bake_passes(13, 6, true, 9, true).unwrap();
        assert_eq!(iso[1].uniform[3..7], [1, 9, 1, (13 * 6u32).div_ceil(4)]);
        // 2²⁴ × 2²⁴ is a field, but its map is over 2³² bytes.
        assert_eq!(safety_bake_passes(1 << 24, 1 << 24, true, 9, true), None);
        assert_eq!(safety_bake_passes(1, 6, true, 9, true), None);
        // Wide grids: at most 65535 workgroups along x.
        let big = safety_bake_passes(4096, 4096, false, 255, false).unwrap();
        assert!(big[1].workgroups[0] <= 65535 && big[1].workgroups[1] > 1);
    }

    #[cfg(feature = "safety")]
    #[test]
    fn cc_passes_are_the_strips_then_two_entries_a_word() {
        use hfcast::safety;
        let p = cc_bake_passes(13, 6, 64).unwrap();
        assert_eq!(
            p[0],
            safety_bake_passes(13, 6, false, 255, false).unwrap()[0]
        );
        assert_eq!(p[1].uniform[..7], [2, 13, 6, 0, 64, 0, 2 * 13 * 6]);
        assert_eq!(p[1].bind_size as usize, safety::cc::map_len(13, 6));
        let glsl = cc_bake_source(crate::Lang::Glsl).unwrap();
        assert!(
            glsl.starts_with("//") && glsl.contains("#version 430 core\n#define HF_CC_BAKE 1\n")
        );
        assert!(cc_bake_source(crate::Lang::Wgsl)
            .unwrap()
            .contains("fn cc_bake_pass("));
        assert_eq!(cc_bake_passes(20000, 20000, 255), None);
    }

    #[cfg(feature = "safety")]
    #[test]
    fn nbuffer_passes_are_the_steps_with_rows() {
        use hfcast::safety::cc;
        // 9 samples across: one block of 8 cell columns per axis.
        let passes = nbuffer_bake_passes(9, 3, 1).unwrap();
        let steps: Vec<_> = cc::nbuffer_steps(9, 3, 1).collect();
        assert_eq!(passes.len(), steps.len());
        assert_eq!(passes[0].uniform, [0, 0, 9, 3, 0, 0, 0, 9]);
        assert_eq!(passes[0].workgroups, [1, 2]);
        assert_eq!([passes[0].bind_offset, passes[0].bind_size], [0, 4 * 27]);
        // Each pass binds from an aligned byte at or below what it reads, to the end
        // of what it writes.
        for (p, s) in passes.iter().zip(&steps) {
            assert_eq!(p.bind_offset % BIND_ALIGN, 0);
            let skip = (p.bind_offset / 4) as usize;
            assert_eq!(
                [p.uniform[4], p.uniform[5]].map(|v| v as usize + skip),
                [s.dst, s.src]
            );
            let end = (s.dst + (s.rows * s.row_len) as usize) as u64 * 4;
            assert_eq!(p.bind_offset + p.bind_size, end);
        }
        let written: u32 = passes.iter().map(|p| p.uniform[2] * p.uniform[3]).sum();
        assert_eq!(written as usize, cc::nbuffer_len(9, 3, 1));
        assert_eq!(nbuffer_bake_passes(1, 3, 1), None);
        // Over 2³² floats.
        assert_eq!(nbuffer_bake_passes(20000, 20000, 255), None);
    }

    #[cfg(feature = "maxmip")]
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
