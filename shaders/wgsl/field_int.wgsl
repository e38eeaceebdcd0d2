// Heights of 16 or 8 bits (hf_scene.height_format HF_HEIGHTS_U16, HF_HEIGHTS_U8), for
// generated shaders only (the general ones read field.wgsl's R32Float texture):
// `hf_heights` is an R16Uint or R8Uint texture of the samples, and a height is sample x
// `hf_field.height_step` (GLSL: `hf_height_step`; in WGSL a member of field.wgsl's
// FieldParams), with height_step = depth / 65535 (or depth / 255) in f32, the core's
// `HeightField::from_u16` (`from_u8`) product, so the GPU heights equal the CPU's.
//#if heights_u16|heights_u8
@group(0) @binding(0) var hf_heights: texture_2d<u32>;

// `HeightField::at`.
fn field_at(i: u32, j: u32) -> f32 { return f32(textureLoad(hf_heights, vec2<u32>(i, j), 0).r) * hf_field.height_step; }
//#endif
