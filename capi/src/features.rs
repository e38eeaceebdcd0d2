//! Which of the registry's cargo features (`hfcast::scene::FEATURES`) this build of
//! the C API has on. Its own list, since the C API may leave out the exports of a
//! feature the core turns on for another (a cone build bakes through the core's
//! maxmip module but exports no maxmip function). Shared with `examples/header.rs`.
//!
//! Generated from the core's registry by `capi/tests/header.rs`: edit the registry
//! and run `HFCAST_BLESS=1 cargo test -p hfcast-capi --test header`; the test fails
//! when this file is out of date.

/// Whether the C API's feature `name` is on; `None` for a name that is not a
/// method feature.
pub fn feature_on(name: &str) -> Option<bool> {
    Some(match name {
        "maxmip" => cfg!(feature = "maxmip"),
        "safety" => cfg!(feature = "safety"),
        "cone" => cfg!(feature = "cone"),
        "qdm" => cfg!(feature = "qdm"),
        "relaxed" => cfg!(feature = "relaxed"),
        "search" => cfg!(feature = "search"),
        _ => return None,
    })
}
