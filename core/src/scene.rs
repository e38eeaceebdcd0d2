//! A scene description: what one renderer or query workload uses, so that shaders,
//! bakes and builds can leave out everything else.
//!
//! A [`Scene`] names one surface and one method and says which rays occur. Shader
//! generation (crate `hfcast-shaders`) emits only the code it needs; the bakes skip
//! the data it never reads (see [`Scene::bake_plan`]).

use crate::ray::RayClass;
use crate::Surface;

/// Every marching method of hfcast, baked or not, by the number the C API
/// (`hf_method`) and the shaders (`HF_METHOD_*`) give it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum MethodKind {
    /// Exact grid traversal ([`crate::dda::trace`]); no bake.
    Exact = 0,
    /// Linear then binary search; approximate; no bake.
    LinearBinary = 1,
    /// Linear search then a secant step (parallax occlusion mapping); approximate.
    LinearSecant = 2,
    /// Maximum mipmaps; exact; needs the pyramid.
    MaxMip = 3,
    /// Safety distances; exact on triangles; needs the safety-distance map.
    Safety = 4,
    /// Conservative cone step mapping; exact within its budget; needs the cone map.
    Cone = 5,
    /// Relaxed cone stepping; approximate; needs the relaxed cone map.
    Relaxed = 6,
    /// Quadratic displacement maps; exact within its budget; needs the QDM.
    Qdm = 7,
    /// Cylinder–cone safety shapes; exact on triangles; needs the CC map.
    Cc = 8,
}

impl MethodKind {
    /// Every method, in value order.
    pub const ALL: [MethodKind; 9] = [
        MethodKind::Exact,
        MethodKind::LinearBinary,
        MethodKind::LinearSecant,
        MethodKind::MaxMip,
        MethodKind::Safety,
        MethodKind::Cone,
        MethodKind::Relaxed,
        MethodKind::Qdm,
        MethodKind::Cc,
    ];

    /// Short lower-case name (`exact`, `linear-binary`, …, `cc`), as the CLI spells it.
    pub fn name(self) -> &'static str {
        match self {
            MethodKind::Exact => "exact",
            MethodKind::LinearBinary => "linear-binary",
            MethodKind::LinearSecant => "linear-secant",
            MethodKind::MaxMip => "maxmip",
            MethodKind::Safety => "safety",
            MethodKind::Cone => "cone",
            MethodKind::Relaxed => "relaxed",
            MethodKind::Qdm => "qdm",
            MethodKind::Cc => "cc",
        }
    }

    /// The method with this number, if any.
    pub fn from_u32(v: u32) -> Option<MethodKind> {
        MethodKind::ALL.get(v as usize).copied()
    }
}

/// A set of [`RayClass`]es: bit `1 << class`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RayClasses(pub u8);

impl RayClasses {
    /// All four classes.
    pub const ALL: RayClasses = RayClasses(0b1111);

    /// Whether `class` is in the set.
    pub fn contains(self, class: RayClass) -> bool {
        self.0 & (1 << class as u8) != 0
    }

    /// The set with `class` added.
    pub fn with(self, class: RayClass) -> RayClasses {
        RayClasses(self.0 | (1 << class as u8))
    }
}

/// How the height texture stores samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum HeightFormat {
    /// 32-bit float heights in grid units (`R32F`).
    F32 = 0,
    /// 16-bit unsigned normalised samples times a depth scale (`R16`).
    U16 = 1,
    /// 8-bit unsigned normalised samples times a depth scale (`R8`).
    U8 = 2,
}

/// What a scene uses. Everything it does not name may be left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scene {
    /// The one surface reconstruction.
    pub surface: Surface,
    /// The one marching method.
    pub method: MethodKind,
    /// The horizontal ray classes that occur (primary and shadow rays together).
    pub ray_classes: RayClasses,
    /// Whether every ray origin stays outside the field's bounding box.
    pub outside_only: bool,
    /// The largest angle between a primary ray and the downward vertical, in degrees:
    /// 90 = horizontal rays at most, 180 = any direction.
    pub max_view_angle_deg: f32,
    /// Whether shadow rays (upward, towards a light) are traced.
    pub shadows: bool,
    /// Whether level-of-detail marching is used (maximum mipmaps only; approximate).
    pub lod: bool,
    /// Whether the shader writes the hit depth.
    pub depth_output: bool,
    /// The height texture's format.
    pub heights: HeightFormat,
}

impl Scene {
    /// The general scene of `method` on `surface`: every ray class, viewpoints
    /// anywhere, any direction, shadows, no LOD, depth output, `F32` heights.
    pub fn general(method: MethodKind, surface: Surface) -> Scene {
        Scene {
            surface,
            method,
            ray_classes: RayClasses::ALL,
            outside_only: false,
            max_view_angle_deg: 180.0,
            shadows: true,
            lod: false,
            depth_output: true,
            heights: HeightFormat::F32,
        }
    }
}
