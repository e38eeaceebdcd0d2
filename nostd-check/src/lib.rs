//! Builds the hfcast core into a `#![no_std]` static library with its own panic
//! handler. If anything in the core's dependency graph linked `std`, this crate would
//! fail to build with "duplicate lang item `panic_impl`": that failure is the check.
#![no_std]

use hfcast::{dda, HeightField, Query, Surface};

/// Traces one downward ray through a 2 × 2 field; exported so the code is kept.
#[no_mangle]
pub extern "C" fn hfcast_nostd_probe(z: f32) -> f32 {
    let h = [0.0f32, 1.0, 1.0, 2.0];
    let Ok(hf) = HeightField::new(&h, 2, 2, 2) else {
        return -1.0;
    };
    let Ok(q) = Query::<f32>::from_arrays([0.5, 0.5, z], [0.0, 0.0, -1.0], 0.0, f32::INFINITY)
    else {
        return -1.0;
    };
    dda::trace(&hf, Surface::Triangles, &q).hit.map_or(-1.0, |h| h.t)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
