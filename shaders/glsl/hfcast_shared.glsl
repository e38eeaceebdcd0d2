// hfcast_shared.glsl: the constants and texture layouts the GLSL ports share with
// the Rust core and the C API. Generated from Rust by glsl_shared() in
// shaders/src/shared.rs: do not edit; regenerate with
// HFCAST_BLESS=1 cargo test -p hfcast-shaders (a test fails when this file drifts).

// Surfaces (hfcast::Surface, hf_surface).
const uint HF_SURFACE_TRIANGLES = 0u;
const uint HF_SURFACE_BILINEAR = 1u;
const uint HF_SURFACE_HEIGHT_PLANES = 2u;
const uint HF_SURFACE_CORNER_PLANES = 3u;
const uint HF_SURFACE_VIEW_LINEAR = 4u;
const uint HF_SURFACE_QU_TRIANGLES = 5u;

// Hit and trace flags (hfcast::Flags, HF_FLAG_*).
const uint HF_FLAG_ORIGIN_INSIDE = 1u;
const uint HF_FLAG_SIDE = 2u;
const uint HF_FLAG_WALL = 4u;
const uint HF_FLAG_BUDGET_EXHAUSTED = 8u;

// Ray classes (hfcast::RayClass).
const uint HF_RAY_CLASS_X_POS = 0u;
const uint HF_RAY_CLASS_X_NEG = 1u;
const uint HF_RAY_CLASS_Y_POS = 2u;
const uint HF_RAY_CLASS_Y_NEG = 3u;

// Ray-class sets (hfcast::scene::RayClasses, the C API's HF_RAYS_*): bit 1 << class;
// the classes a safety-distance or cylinder-cone map holds (hf_safety_classes,
// hf_cc_classes): n of them, texel (i, j) of a class at row n j + its slot.
const uint HF_RAYS_X_POS = 1u;
const uint HF_RAYS_X_NEG = 2u;
const uint HF_RAYS_Y_POS = 4u;
const uint HF_RAYS_Y_NEG = 8u;
const uint HF_RAYS_ALL = 15u;

// Methods (hf_method).
const uint HF_METHOD_EXACT = 0u;
const uint HF_METHOD_LINEAR_BINARY = 1u;
const uint HF_METHOD_LINEAR_SECANT = 2u;
const uint HF_METHOD_MAXMIP = 3u;
const uint HF_METHOD_SAFETY = 4u;
const uint HF_METHOD_CONE = 5u;
const uint HF_METHOD_RELAXED = 6u;
const uint HF_METHOD_QDM = 7u;
const uint HF_METHOD_CC = 8u;
const uint HF_METHOD_RADIUS = 9u;
const uint HF_METHOD_MULTIRES = 10u;

// Safety-distance map layouts (hf_safety_variant, hfcast::safety::Variant).
const uint HF_SAFETY_DIRECTIONAL = 0u;
const uint HF_SAFETY_ISOTROPIC = 1u;
// Texel segment widening of the bake (hfcast::safety::SEG_PAD).
const float HF_SAFETY_SEG_PAD = 0.0625;
// Cylinder-cone slope code meaning "no cone" (hfcast::safety::cc::NO_CONE).
const uint HF_CC_NO_CONE = 255u;

// How a traced span begins (hfcast::dda::Entry): Span.entry.
const uint HF_ENTRY_START = 0u;
const uint HF_ENTRY_SIDE = 1u;
const uint HF_ENTRY_TOP = 2u;

// Sizes and texture layouts.
// Largest width or height of a field (hfcast::field::MAX_SIDE).
const uint HF_MAX_SIDE = 16777216u;
// Most levels of a maximum-mipmap pyramid (hfcast::maxmip::MAX_LEVELS).
const int HF_MAX_LEVELS = 25;
// Width of the R32F texture holding the pyramid buffer: texel k at
// (k % HF_PYRAMID_TEX_WIDTH, k / HF_PYRAMID_TEX_WIDTH).
const int HF_PYRAMID_TEX_WIDTH = 4096;
