// Mirror of core/src/radius.rs (the march; the bake stays on the CPU): the safety
// radius (Baboud & Decoret 2006) on the triangle surface, or the view-linear one from
// the same map, stepping with the safety march of safety.wgsl.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", safety radius): `hf_radius_map`.

@group(0) @binding(11) var hf_radius_map: texture_2d<u32>;

// `RadiusMap::radius`: radius of texel (i, j).
fn radius_at(i: u32, j: u32) -> u32 {
    return textureLoad(hf_radius_map, vec2<u32>(i, j), 0).r;
}
