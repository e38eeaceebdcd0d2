// Mirror of core/src/field.rs: the height field, read from textures.
//
// `hf_heights`: an R32F texture of W x H texels, texel (i, j) = sample (i, j) in grid
// units, read with texelFetch only (never filtered). `hf_size` = (W, H);
// `hf_height_range` = (min_height, max_height) as the CPU's HeightField holds them
// (hf_field_get_info), since the clip to the bounding box uses them.

//#if heights_f32
uniform sampler2D hf_heights;
//#endif
uniform ivec2 hf_size;
uniform vec2 hf_height_range;

uint field_width() { return uint(hf_size.x); }
uint field_height() { return uint(hf_size.y); }
//#if one_field
float field_min_height() { return hf_height_range.x; }
float field_max_height() { return hf_height_range.y; }
//#else
// An impostor's shader (impostor.glsl; every other shader sets the flag one_field)
// reads six fields of W x H stacked in `hf_heights` (W x 6H texels: field k's sample
// (i, j) at texel (i, j + kH)), the one of slot `hf_field_slot`, whose heights range
// over `hf_field_ranges[slot]` (min, max).
uint hf_field_slot = 0u;
uniform vec2 hf_field_ranges[6];

float field_min_height() { return hf_field_ranges[hf_field_slot].x; }
float field_max_height() { return hf_field_ranges[hf_field_slot].y; }
//#endif

//#if heights_f32
//#if one_field
// `HeightField::at`.
float field_at(uint i, uint j) { return texelFetch(hf_heights, ivec2(i, j), 0).r; }
//#else
// `HeightField::at` of the field of slot `hf_field_slot`.
float field_at(uint i, uint j) { return texelFetch(hf_heights, ivec2(i, j + hf_field_slot * uint(hf_size.y)), 0).r; }
//#endif
//#endif

// `HeightField::cell_corners`: `[h00, h10, h01, h11]`.
vec4 field_cell_corners(uint i, uint j) {
    return vec4(field_at(i, j), field_at(i + 1u, j), field_at(i, j + 1u), field_at(i + 1u, j + 1u));
}
