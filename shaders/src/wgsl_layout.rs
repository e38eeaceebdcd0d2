//! The resource layout of the WGSL ports: the fixed `@group(0)` binding numbers of
//! the resources the files of `shaders/wgsl` declare, a contract with every caller
//! that binds them (the table at the top of `hfcast_shared.wgsl` is rendered from
//! these). Any set of files composes without clashes; the bindings of group 0 up to
//! [`RESERVED_UP_TO`] are hfcast's, and a caller's own resources go in `@group(1)` or
//! later.

/// `hf_heights`: `texture_2d<f32>`, R32Float, W × H (field.wgsl); in a shader
/// generated for 16- or 8-bit heights a `texture_2d<u32>`, R16Uint or R8Uint
/// (field_int.wgsl).
pub const HEIGHTS: u32 = 0;
/// `hf_field`: uniform `FieldParams` (field.wgsl).
pub const FIELD: u32 = 1;
/// `hf_params`: uniform, the method's step counts (method_*.wgsl).
pub const PARAMS: u32 = 2;
/// `hf_pyramid`: `texture_2d<f32>`, R32Float, the pyramid buffer in rows of
/// [`PYRAMID_TEX_WIDTH`](crate::PYRAMID_TEX_WIDTH) texels (maxmip.wgsl).
pub const PYRAMID: u32 = 3;
/// `hf_maxmip`: uniform `MaxMipParams` (maxmip.wgsl).
pub const MAXMIP: u32 = 4;
/// `hf_safety_map`: `texture_2d<u32>`, R8Uint: W × nH for the `n` ray classes of the
/// override `hf_safety_classes` (directional, texel `(i, nj + slot)`; a whole map W ×
/// 4H, texel `(i, 4j + class)`) or W × H (isotropic) (safety.wgsl).
pub const SAFETY_MAP: u32 = 5;
/// `hf_cone_map`: `texture_2d<f32>`, RG32Float, (W − 1) × (H − 1) (cone.wgsl).
pub const CONE_MAP: u32 = 6;
/// `hf_qdm_map`: `texture_2d<f32>`, RGBA32Float, (W − 1) × (H − 1) (qdm.wgsl).
pub const QDM_MAP: u32 = 7;
/// `hf_relaxed_map`: `texture_2d<f32>`, R32Float, W × H (relaxed.wgsl).
pub const RELAXED_MAP: u32 = 8;
/// `hf_cc_map`: `texture_2d<u32>`, Rg8Uint, W × nH for the `n` ray classes of the
/// override `hf_cc_classes` (texel `(i, nj + slot)`; a whole map W × 4H) (cc.wgsl).
pub const CC_MAP: u32 = 9;
/// `hf_cc`: uniform `CcParams` (cc.wgsl).
pub const CC: u32 = 10;
/// `hf_radius_map`: `texture_2d<u32>`, R8Uint, W × H (radius.wgsl).
pub const RADIUS_MAP: u32 = 11;
/// `hf_world`: uniform `WorldParams`, the field's grid-to-world transform, read by
/// `hf_trace_world` only (world.wgsl).
pub const WORLD: u32 = 12;
/// `hf_pyramid_out`: `array<f32>`, a read-write storage buffer, the pyramid the GPU
/// bake writes in the core's `maxmip::Layout` (bake_maxmip.wgsl).
pub const PYRAMID_OUT: u32 = 13;
/// `hf_maxmip_pass`: uniform `MaxMipPass`, one level's pass of the GPU bake
/// (bake_maxmip.wgsl).
pub const MAXMIP_PASS: u32 = 14;
/// `hf_nbuffer`: `array<f32>`, a storage buffer, the N-buffers in the core's layout
/// (`cc::nbuffer_len` floats): written by the GPU N-buffer bake (read-write,
/// bake_nbuffer.wgsl), read by the cylinder–cone bake (read-only, bake_safety.wgsl).
pub const NBUFFER: u32 = 15;
/// `hf_nbuffer_pass`: uniform `NbufferPass`, one step of the GPU N-buffer bake
/// (bake_nbuffer.wgsl).
pub const NBUFFER_PASS: u32 = 16;
/// `hf_safety_scratch`: `array<f32>`, a read-write storage buffer, the strip bounds of
/// the GPU safety-distance bake (`safety::scratch_len` floats) (bake_safety.wgsl).
pub const SAFETY_SCRATCH: u32 = 17;
/// `hf_safety_out`: `array<u32>`, a read-write storage buffer, the safety-distance map
/// the GPU bake writes, four bytes to a word (bake_safety.wgsl).
pub const SAFETY_OUT: u32 = 18;
/// `hf_safety_pass`: uniform `SafetyBakePass`, one pass of the GPU safety-distance
/// bake (bake_safety.wgsl).
pub const SAFETY_PASS: u32 = 19;
/// `hf_field_ranges`: uniform `array<vec4<f32>, 6>`, the height range (xy: min, max)
/// of each of an impostor's six fields (field.wgsl, impostor shaders only: not in the
/// table of `hfcast_shared.wgsl`, which every other shader holds).
pub const FIELD_RANGES: u32 = 20;
/// `hf_impostor`: uniform `ImpostorParams`, an impostor's six face maps, their inverses
/// and its cube (impostor.wgsl).
pub const IMPOSTOR: u32 = 21;
/// `hf_view_proj`: uniform `Mat4Rows`, the world-to-clip matrix of an impostor
/// shader's depth output (impostor.wgsl, scenes with `depth_output`).
pub const VIEW_PROJ: u32 = 22;
/// `hf_occluders`: `texture_2d<f32>`, RGBA32Float, 3·n × 1 for the override
/// `hf_occluder_count` = n: occluder `k`'s corners (x, y, z) at texels `3k` to
/// `3k + 2` (safety.wgsl, shaders of scenes with occluders).
pub const OCCLUDERS: u32 = 23;
/// The last binding of group 0 kept for hfcast's own resources.
pub const RESERVED_UP_TO: u32 = 31;
