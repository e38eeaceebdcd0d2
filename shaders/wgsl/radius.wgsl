// Mirror of core/src/radius.rs (the march; the bake stays on the CPU): the safety
// radius (Baboud & Decoret 2006) on the triangle surface, or the view-linear one from
// the same map, stepping with the safety march of safety.wgsl.
//
// Texture layout: the map of hf_radius_bake as `hf_radius_map`, an R8Uint texture of
// W x H texels: the radius of texel (i, j).

@group(0) @binding(11) var hf_radius_map: texture_2d<u32>;

// `RadiusMap::radius`: radius of texel (i, j).
fn radius_at(i: u32, j: u32) -> u32 {
    return textureLoad(hf_radius_map, vec2<u32>(i, j), 0).r;
}
