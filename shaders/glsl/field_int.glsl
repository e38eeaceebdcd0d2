// Heights of 16 or 8 bits (hf_scene.height_format HF_HEIGHTS_U16, HF_HEIGHTS_U8), for
// generated shaders only (the general ones read field.glsl's R32F texture): `hf_heights`
// is an R16UI or R8UI texture of the samples, and a height is sample x `hf_height_step`,
// with hf_height_step = depth / 65535 (or depth / 255) in float, the core's
// `HeightField::from_u16` (`from_u8`) product, so the GPU heights equal the CPU's.
//#if heights_u16|heights_u8
uniform usampler2D hf_heights;
uniform float hf_height_step;

// `HeightField::at`.
float field_at(uint i, uint j) { return float(texelFetch(hf_heights, ivec2(i, j), 0).r) * hf_height_step; }
//#endif
