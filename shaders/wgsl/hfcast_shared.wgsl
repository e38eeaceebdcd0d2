// hfcast_shared.wgsl: the constants and texture layouts the WGSL ports share with
// the Rust core and the C API. Generated from Rust by wgsl_shared() in
// shaders/src/shared.rs: do not edit; regenerate with
// HFCAST_BLESS=1 cargo test -p hfcast-shaders (a test fails when this file drifts).
//
// Resource bindings, all in @group(0), fixed so that any set of files composes:
//   binding  name            type                                  declared in
//   0        hf_heights      texture_2d<f32>, R32Float, W x H       field.wgsl
//   1        hf_field        uniform FieldParams                    field.wgsl
//   2        hf_params       uniform, the method's step counts      method_*.wgsl
//   3        hf_pyramid      texture_2d<f32>, R32Float              maxmip.wgsl
//   4        hf_maxmip       uniform MaxMipParams                   maxmip.wgsl
//   5        hf_safety_map   texture_2d<u32>, R8Uint                safety.wgsl
//   6        hf_cone_map     texture_2d<f32>, RG32Float             cone.wgsl
//   7        hf_qdm_map      texture_2d<f32>, RGBA32Float           qdm.wgsl
//   8        hf_relaxed_map  texture_2d<f32>, R32Float              relaxed.wgsl
//   9        hf_cc_map       texture_2d<u32>, Rg8Uint               cc.wgsl
//   10       hf_cc           uniform CcParams                       cc.wgsl
//   11       hf_radius_map   texture_2d<u32>, R8Uint                radius.wgsl
//   12       hf_world        uniform WorldParams                    world.wgsl
//   13       hf_pyramid_out  storage array<f32>, read_write         bake_maxmip.wgsl
//   14       hf_maxmip_pass  uniform MaxMipPass                     bake_maxmip.wgsl
//   15       hf_nbuffer      storage array<f32>                     bake_nbuffer.wgsl, bake_safety.wgsl
//   16       hf_nbuffer_pass uniform NbufferPass                    bake_nbuffer.wgsl
//   17       hf_safety_scratch storage array<f32>, read_write         bake_safety.wgsl
//   18       hf_safety_out   storage array<u32>, read_write         bake_safety.wgsl
//   19       hf_safety_pass  uniform SafetyBakePass                 bake_safety.wgsl
//   23       hf_occluders    texture_2d<f32>, RGBA32Float, 3n x 1   safety.wgsl
// Bindings 20 to 22 (the impostor shaders') and the others up
// to 31 of group 0 are reserved; a caller's own resources go in group 1
// or later. Textures are read with textureLoad only (never sampled). Scene-level
// choices are override constants: hf_surface, hf_safety_variant,
// hf_safety_classes, hf_cc_classes, hf_rays_exterior, hf_rays_max_view_angle,
// hf_occluder_count.

// Surfaces (hfcast::Surface, hf_surface).
const HF_SURFACE_TRIANGLES: u32 = 0u;
const HF_SURFACE_BILINEAR: u32 = 1u;
const HF_SURFACE_HEIGHT_PLANES: u32 = 2u;
const HF_SURFACE_CORNER_PLANES: u32 = 3u;
const HF_SURFACE_VIEW_LINEAR: u32 = 4u;
const HF_SURFACE_QU_TRIANGLES: u32 = 5u;

// Hit and trace flags (hfcast::Flags, HF_FLAG_*).
const HF_FLAG_ORIGIN_INSIDE: u32 = 1u;
const HF_FLAG_SIDE: u32 = 2u;
const HF_FLAG_WALL: u32 = 4u;
const HF_FLAG_BUDGET_EXHAUSTED: u32 = 8u;

// Ray classes (hfcast::RayClass).
const HF_RAY_CLASS_X_POS: u32 = 0u;
const HF_RAY_CLASS_X_NEG: u32 = 1u;
const HF_RAY_CLASS_Y_POS: u32 = 2u;
const HF_RAY_CLASS_Y_NEG: u32 = 3u;

// Ray-class sets (hfcast::scene::RayClasses, the C API's HF_RAYS_*): bit 1 << class;
// the classes a safety-distance or cylinder-cone map holds (hf_safety_classes,
// hf_cc_classes): n of them, texel (i, j) of a class at row n j + its slot.
const HF_RAYS_X_POS: u32 = 1u;
const HF_RAYS_X_NEG: u32 = 2u;
const HF_RAYS_Y_POS: u32 = 4u;
const HF_RAYS_Y_NEG: u32 = 8u;
const HF_RAYS_ALL: u32 = 15u;

// Methods (hf_method).
const HF_METHOD_EXACT: u32 = 0u;
const HF_METHOD_LINEAR_BINARY: u32 = 1u;
const HF_METHOD_LINEAR_SECANT: u32 = 2u;
const HF_METHOD_MAXMIP: u32 = 3u;
const HF_METHOD_SAFETY: u32 = 4u;
const HF_METHOD_CONE: u32 = 5u;
const HF_METHOD_RELAXED: u32 = 6u;
const HF_METHOD_QDM: u32 = 7u;
const HF_METHOD_CC: u32 = 8u;
const HF_METHOD_RADIUS: u32 = 9u;
const HF_METHOD_MULTIRES: u32 = 10u;

// Safety-distance map layouts (hf_safety_variant, hfcast::safety::Variant).
const HF_SAFETY_DIRECTIONAL: u32 = 0u;
const HF_SAFETY_ISOTROPIC: u32 = 1u;
// Texel segment widening of the bake (hfcast::safety::SEG_PAD).
const HF_SAFETY_SEG_PAD: f32 = 0.0625;
// Cylinder-cone slope code meaning "no cone" (hfcast::safety::cc::NO_CONE).
const HF_CC_NO_CONE: u32 = 255u;

// How a traced span begins (hfcast::dda::Entry): Span.entry.
const HF_ENTRY_START: u32 = 0u;
const HF_ENTRY_SIDE: u32 = 1u;
const HF_ENTRY_TOP: u32 = 2u;

// Sizes and texture layouts.
// Largest width or height of a field (hfcast::field::MAX_SIDE).
const HF_MAX_SIDE: u32 = 16777216u;
// Most levels of a maximum-mipmap pyramid (hfcast::maxmip::MAX_LEVELS).
const HF_MAX_LEVELS: i32 = 25;
// Width of the R32F texture holding the pyramid buffer: texel k at
// (k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH).
const HF_PYRAMID_TEX_WIDTH: i32 = 4096;
