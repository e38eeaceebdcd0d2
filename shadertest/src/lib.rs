//! Tests of the WGSL ports of the hfcast marches (`shaders/wgsl`); this library is
//! empty. The sources come from `hfcast-shaders`: a method's general shader
//! (`hfcast_shaders::general`, every scene choice an `override`) and the shaders it
//! generates for scene descriptions (`hfcast_shaders::generate_with`, 16-bit heights
//! included), bound in the layout of `hfcast_shaders::wgsl_layout`. The tests validate
//! every source with naga (`tests/wgsl_validate.rs`) and run every march through wgpu
//! (on lavapipe in CI) against the Rust core ray by ray (`tests/wgsl_parity.rs`); their
//! harness (the test entry point, the Vulkan device, the scenes, the rays) is
//! `tests/common/mod.rs`.
