// Generated from shaders/wgsl/radius.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/radius.rs (the march; the bake stays on the CPU): the safety
// radius (Baboud & Decoret 2006) on the triangle surface, or the view-linear one from
// the same map, stepping with the safety march of safety.wgsl.
//
// Texture layout (docs/DESIGN.md, "Texture layouts", safety radius): `hf_radius_map`.

uniform usampler2D hf_radius_map;

// `RadiusMap::radius`: radius of texel (i, j).
uint radius_at(uint i, uint j) {
    return texelFetch(hf_radius_map, ivec2(i, j), 0).r;
}
