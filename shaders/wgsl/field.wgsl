// Mirror of core/src/field.rs: the height field, read from textures.
//
// `hf_heights`: an R32Float texture of W x H texels, texel (i, j) = sample (i, j) in
// grid units, read with textureLoad only (never filtered). `hf_field.size` = (W, H);
// `hf_field.height_range` = (min_height, max_height) as the CPU's HeightField holds
// them (hf_field_get_info), since the clip to the bounding box uses them;
// `hf_field.height_step` is read by field_int.wgsl only (16- and 8-bit heights).

struct FieldParams {
    size: vec2<u32>,
    height_range: vec2<f32>,
    height_step: f32,
}

//#if heights_f32
@group(0) @binding(0) var hf_heights: texture_2d<f32>;
//#endif
@group(0) @binding(1) var<uniform> hf_field: FieldParams;

fn field_width() -> u32 { return hf_field.size.x; }
fn field_height() -> u32 { return hf_field.size.y; }
//#if one_field
fn field_min_height() -> f32 { return hf_field.height_range.x; }
fn field_max_height() -> f32 { return hf_field.height_range.y; }
//#else
// An impostor's shader (impostor.wgsl; every other shader sets the flag one_field)
// reads six fields of W x H stacked in `hf_heights` (W x 6H texels: field k's sample
// (i, j) at texel (i, j + kH)), the one of slot `hf_field_slot`, whose heights range
// over `hf_field_ranges[slot].xy` (binding 20: array<vec4<f32>, 6>, xy = min, max).
var<private> hf_field_slot: u32 = 0u;
@group(0) @binding(20) var<uniform> hf_field_ranges: array<vec4<f32>, 6>;

fn field_min_height() -> f32 { return hf_field_ranges[hf_field_slot].x; }
fn field_max_height() -> f32 { return hf_field_ranges[hf_field_slot].y; }
//#endif

//#if heights_f32
//#if one_field
// `HeightField::at`.
fn field_at(i: u32, j: u32) -> f32 { return textureLoad(hf_heights, vec2<u32>(i, j), 0).r; }
//#else
// `HeightField::at` of the field of slot `hf_field_slot`.
fn field_at(i: u32, j: u32) -> f32 { return textureLoad(hf_heights, vec2<u32>(i, j + hf_field_slot * hf_field.size.y), 0).r; }
//#endif
//#endif

// `HeightField::cell_corners`: `[h00, h10, h01, h11]`.
fn field_cell_corners(i: u32, j: u32) -> vec4<f32> {
    return vec4<f32>(field_at(i, j), field_at(i + 1u, j), field_at(i, j + 1u), field_at(i + 1u, j + 1u));
}
