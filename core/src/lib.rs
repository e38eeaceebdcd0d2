//! # hfcast — exact and fast ray casting of height fields
//!
//! A `no_std` core: height fields over caller-owned samples, the five surface
//! reconstructions of `docs/DESIGN.md`, the exact grid traversal (in `f64` the test oracle,
//! in `f32` the fast path), and the bake-free search baselines.
//!
//! Cargo features leave whole methods out (docs/DESIGN.md, "Leave out what a scene does
//! not need"): `maxmip`, `safety` (safety distances and cylinder–cone shapes),
//! `cone` (needs `maxmip`), `qdm` and `relaxed` (need `cone`), `search`; the default
//! `all-methods` enables them all. The exact traversal ([`dda`]), the scene
//! description ([`scene`]) and, with `alloc`, the brute-force oracle (`brute`) are
//! always built.
//!
//! Grid space: sample (i, j) sits at (x = i, y = j); the surface covers
//! [0, W−1] × [0, H−1]; heights are in grid units. Everything below the surface is
//! solid, so a ray starting under it hits at `t_min`.
//!
//! ```
//! use hfcast::{HeightField, Query, Surface, Method};
//! let heights = [0.0f32, 1.0, 1.0, 2.0];
//! let hf = HeightField::new(&heights, 2, 2, 2).unwrap();
//! let q = Query::<f32>::from_arrays([0.5, 0.5, 5.0], [0.0, 0.0, -1.0], 0.0, f32::INFINITY).unwrap();
//! let hit = Method::Exact.trace(&hf, Surface::Triangles, &q).hit.unwrap();
//! assert!((hit.point.z - 1.0).abs() < 1e-6);
//! ```
#![no_std]
#![deny(unsafe_code)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

/// Declares a field-less enum whose variants carry explicit values and short names,
/// with what every enumeration of the registry needs: `ALL` (every variant in
/// declaration order), `from_u32` (by value), `name`, `from_name` and `doc` (the
/// variant's doc comment, which the C header's generated enums repeat). Written once so
/// that a new variant is one line.
///
/// A variant may carry a constant in parentheses after its name, which the getter
/// declared after the enum (`pub fn getter(self) -> Type;`) returns: the per-variant
/// data of a table, written in the variant's row instead of a `match` elsewhere.
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        pub enum $name:ident: $repr:ident {
            $( $(#[doc = $doc:literal])+ $variant:ident = $value:literal => $label:literal ($data:expr), )+
        }
        $(#[$gmeta:meta])*
        pub fn $getter:ident(self) -> $ty:ty;
    ) => {
        named_enum! {
            $(#[$meta])*
            pub enum $name: $repr {
                $( $(#[doc = $doc])+ $variant = $value => $label, )+
            }
        }

        impl $name {
            $(#[$gmeta])*
            pub fn $getter(self) -> $ty {
                match self {
                    $($name::$variant => {
                        const DATA: $ty = $data;
                        DATA
                    })+
                }
            }
        }
    };
    (
        $(#[$meta:meta])*
        pub enum $name:ident: $repr:ident {
            $( $(#[doc = $doc:literal])+ $variant:ident = $value:literal => $label:literal, )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr($repr)]
        pub enum $name {
            $( $(#[doc = $doc])+ $variant = $value, )+
        }

        impl $name {
            /// Every value, in declaration order.
            pub const ALL: [$name; [$($value),+].len()] = [$($name::$variant),+];

            /// The value numbered `v`, if any.
            pub fn from_u32(v: u32) -> Option<$name> {
                match v {
                    $($value => Some($name::$variant),)+
                    _ => None,
                }
            }

            /// Its short name (lower case; a format's Vulkan name).
            pub fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $label,)+
                }
            }

            /// The variant's doc comment, its lines joined by `\n`.
            pub fn doc(self) -> &'static str {
                match self {
                    $($name::$variant => concat!($($doc, "\n"),+).trim_ascii_end(),)+
                }
            }

            /// The value [`name`](Self::name) calls `name`, if any.
            pub fn from_name(name: &str) -> Option<$name> {
                $name::ALL.into_iter().find(|x| x.name() == name)
            }
        }
    };
}

pub mod bake;
#[cfg(feature = "alloc")]
pub mod brute;
pub mod buffer;
pub mod camera;
pub mod condition;
#[cfg(feature = "cone")]
pub mod cone;
pub mod dda;
pub mod field;
#[cfg(feature = "alloc")]
pub mod horizon;
pub mod hybrid;
pub mod impostor;
pub mod judge;
pub mod ktx2;
pub mod mapdesc;
pub mod march;
pub mod math;
#[cfg(feature = "maxmip")]
pub mod maxmip;
pub mod multires;
pub mod projective;
#[cfg(feature = "qdm")]
pub mod qdm;
#[cfg(feature = "safety")]
pub mod radius;
pub mod ray;
pub mod rayset;
#[cfg(feature = "relaxed")]
pub mod relaxed;
pub mod rng;
#[cfg(feature = "safety")]
pub mod safety;
pub mod scene;
#[cfg(feature = "search")]
pub mod search;
pub mod simd;
pub mod surface;
pub mod world;

pub use field::{FieldError, HeightField};
pub use march::Marcher;
pub use math::Real;
pub use ray::{Flags, Hit, Query, RayClass, RayError, Trace};
#[cfg(feature = "search")]
pub use search::SearchSteps;
pub use surface::Surface;
pub use world::{TransformError, WorldTransform};

/// The marching methods that need no baked data, as one value a caller can pass around
/// (the searches only with the `search` feature).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Exact grid traversal ([`dda::trace`]).
    Exact,
    /// Linear then binary search ([`search::linear`], [`search::Refine::Binary`]);
    /// approximate.
    #[cfg(feature = "search")]
    LinearBinary(SearchSteps),
    /// Linear search then a secant step, parallax-occlusion style
    /// ([`search::linear`], [`search::Refine::Secant`]); approximate.
    #[cfg(feature = "search")]
    LinearSecant(u32),
    /// The multiresolution walk ([`multires::trace`]) with its one-texel distance;
    /// approximate.
    Multires(u32),
}

impl Method {
    /// `true` for methods that never return a wrong ray.
    pub fn is_exact(self) -> bool {
        matches!(self, Method::Exact)
    }

    /// Traces one query.
    pub fn trace<R: Real>(self, hf: &HeightField, surface: Surface, q: &Query<R>) -> Trace<R> {
        match self {
            Method::Exact => dda::trace(hf, surface, q),
            #[cfg(feature = "search")]
            Method::LinearBinary(steps) => search::linear(
                hf,
                surface,
                q,
                steps.linear,
                search::Refine::Binary(steps.binary),
            ),
            #[cfg(feature = "search")]
            Method::LinearSecant(n) => search::linear(hf, surface, q, n, search::Refine::Secant),
            Method::Multires(range) => multires::trace(hf, surface, q, range),
        }
    }
}
