//! A scene description: what one renderer or query workload uses, so that shaders,
//! bakes and builds can leave out everything else.
//!
//! A [`Scene`] names one surface and one method and says which rays occur. Shader
//! generation (crate `hfcast-shaders`) emits only the code it needs; the bakes skip
//! the data it never reads (see [`Scene::bake_plan`]).

use crate::ktx2::MapKind;
use crate::ray::RayClass;
use crate::Surface;

named_enum! {
    /// Every marching method of hfcast, baked or not, by the number the C API
    /// (`hf_method`) and the shaders (`HF_METHOD_*`) give it, and by the short name the
    /// CLI, the report and `hf_method_name` spell it with; each with its row of the
    /// registry ([`MethodKind::info`]).
    pub enum MethodKind: u32 {
        /// Exact grid traversal (Amanatides–Woo DDA, exact per-cell test). Needs no bake.
        Exact = 0 => "exact" (&MethodInfo {
            shader: &["method_exact"],
            ..MethodInfo::base(MethodKind::Exact, ALWAYS)
        }),
        /// Linear search then bisection (Policarpo et al. 2005); approximate, no bake.
        LinearBinary = 1 => "linear-binary" (&MethodInfo {
            accuracy: Accuracy::Approximate,
            steps: SEARCH_STEPS,
            shader: &["search", "method_linear_binary"],
            ..MethodInfo::base(MethodKind::LinearBinary, SEARCH)
        }),
        /// Linear search then one secant step (parallax occlusion mapping); approximate.
        LinearSecant = 2 => "linear-secant" (&MethodInfo {
            accuracy: Accuracy::Approximate,
            steps: SEARCH_STEPS.split_at(1).0,
            shader: &["search", "method_linear_secant"],
            ..MethodInfo::base(MethodKind::LinearSecant, SEARCH)
        }),
        /// Maximum mipmaps (Tevs et al. 2008); exact, needs the baked pyramid.
        MaxMip = 3 => "maxmip" (&MethodInfo {
            map: Some(MapKind::MaxMip),
            shader: &["maxmip", "method_maxmip"],
            ..MethodInfo::base(MethodKind::MaxMip, (Some("maxmip"), cfg!(feature = "maxmip")))
        }),
        /// Safety distances (Baboud et al. 2011); exact on the triangle surface, needs the
        /// baked safety-distance map.
        Safety = 4 => "safety" (&MethodInfo::safety_shape(
            MethodKind::Safety,
            MapKind::Safety,
            &["safety", "method_safety"],
        )),
        /// Conservative cone step mapping (Dummer 2006, made exact for the triangle
        /// surface); exact within its iteration budget, needs the baked cone map.
        Cone = 5 => "cone" (&MethodInfo::cone_family(
            MethodKind::Cone,
            MapKind::Cone,
            (Some("cone"), cfg!(feature = "cone")),
            &["cone", "method_cone"],
        )),
        /// Relaxed cone stepping (Policarpo & Oliveira 2007); approximate, needs the baked
        /// relaxed cone map.
        Relaxed = 6 => "relaxed" (&MethodInfo {
            accuracy: Accuracy::Approximate,
            steps: &[
                StepParam { name: "cone step count", default: 64 },
                StepParam { name: "binary step count", default: 8 },
            ],
            ..MethodInfo::cone_family(
                MethodKind::Relaxed,
                MapKind::Relaxed,
                (Some("relaxed"), cfg!(feature = "relaxed")),
                &["relaxed", "method_relaxed"],
            )
        }),
        /// Quadratic displacement maps (after Kiglics et al.); exact within its iteration
        /// budget, needs the baked QDM.
        Qdm = 7 => "qdm" (&MethodInfo::cone_family(
            MethodKind::Qdm,
            MapKind::Qdm,
            (Some("qdm"), cfg!(feature = "qdm")),
            &["cone", "qdm", "method_qdm"],
        )),
        /// Cylinder–cone safety shapes (Baboud et al. 2011, §6.3); exact on the triangle
        /// surface, needs the baked cylinder–cone map.
        Cc = 8 => "cc" (&MethodInfo::safety_shape(
            MethodKind::Cc,
            MapKind::Cc,
            &["safety", "cc", "method_cc"],
        )),
        /// Safety radius (Baboud & Décoret 2006); exact on the triangle surface with zero
        /// radii walked (`HF_RADIUS_WALK`), needs the baked radius map.
        Radius = 9 => "radius" (&MethodInfo::safety_shape(
            MethodKind::Radius,
            MapKind::Radius,
            &["safety", "radius", "method_radius"],
        )),
        /// Multiresolution traversal (Qu et al. 2003, after Cohen-Or et al. 1996): the
        /// exact walk on coarser grids (every 2^ℓ-th sample) where a pixel's footprint is
        /// wider than their cells; approximate, no bake.
        Multires = 10 => "multires" (&MethodInfo {
            accuracy: Accuracy::Approximate,
            steps: &[StepParam { name: "one-texel distance", default: 512 }],
            shader: &["multires", "method_multires"],
            ..MethodInfo::base(MethodKind::Multires, ALWAYS)
        }),
    }
    /// The method's row of the registry: everything the C API, the shaders, the
    /// report and the tools derive from a method's identity.
    pub fn info(self) -> &'static MethodInfo;
}

/// How close a method's answer is to the exact traversal's (docs/DESIGN.md, "Accuracy
/// and cost").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Accuracy {
    /// Always the exact traversal's hit (zero wrong rays).
    Exact,
    /// The exact hit while its step budget lasts (`BUDGET_EXHAUSTED` when it runs out).
    ExactWithinBudget,
    /// Approximate: its error is measured, not bounded.
    Approximate,
}

/// A march parameter of a method with a step budget, and its default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StepParam {
    /// What it counts (`linear step count`, `binary step count`, `iteration cap`,
    /// `cone step count`), as the CLI's messages about `method:N:M` name it.
    pub name: &'static str,
    /// Its default.
    pub default: u32,
}

/// One row of the method registry ([`MethodKind::info`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodInfo {
    /// The method.
    pub kind: MethodKind,
    /// The cargo feature (of this crate and the C API) that builds it; `None`: always.
    pub feature: Option<&'static str>,
    /// Whether this build has it.
    pub built: bool,
    /// How exact its answer is.
    pub accuracy: Accuracy,
    /// The surfaces its march traces.
    pub surfaces: &'static [Surface],
    /// The map its march reads (`None`: it needs no bake).
    pub map: Option<MapKind>,
    /// Its step parameters in order (the first is the C API's `steps`, the second its
    /// `binary_steps`), with their defaults.
    pub steps: &'static [StepParam],
    /// Its shader files (stems in `shaders/wgsl` and `shaders/glsl`) after the ones every
    /// march shares, in dependency order, the last defining `hf_trace`
    /// (`hfcast_shaders::parts`).
    pub shader: &'static [&'static str],
}

/// The surfaces every traversal-based method traces.
const EVERY_SURFACE: &[Surface] = &Surface::ALL;
/// The surfaces the safety-shape maps bound (`safety::MarchSurface`).
const SAFETY_SURFACES: &[Surface] = &[Surface::Triangles, Surface::ViewLinear];
/// The triangle surface alone (the cone family's bakes).
const TRIANGLES: &[Surface] = &[Surface::Triangles];
/// A linear search's budget: equal steps through the box, then bisections.
const SEARCH_STEPS: &[StepParam] = &[
    StepParam {
        name: "linear step count",
        default: 64,
    },
    StepParam {
        name: "binary step count",
        default: 8,
    },
];
/// An iteration budget.
const ITERATIONS: &[StepParam] = &[StepParam {
    name: "iteration cap",
    default: 64,
}];

/// The cargo feature of a method and whether this build has it on: none (always built).
const ALWAYS: (Option<&str>, bool) = (None, true);
/// The search baselines' feature.
const SEARCH: (Option<&str>, bool) = (Some("search"), cfg!(feature = "search"));
/// The safety-shape methods' feature.
const SAFETY: (Option<&str>, bool) = (Some("safety"), cfg!(feature = "safety"));

impl MethodInfo {
    /// The row of `kind` built by `feature` (its name, and whether it is on): exact,
    /// on every surface, without a map, step parameters or shader files (the rows
    /// override what differs).
    const fn base(kind: MethodKind, feature: (Option<&'static str>, bool)) -> MethodInfo {
        MethodInfo {
            kind,
            feature: feature.0,
            built: feature.1,
            accuracy: Accuracy::Exact,
            surfaces: EVERY_SURFACE,
            map: None,
            steps: &[],
            shader: &[],
        }
    }

    /// A safety-shape method (feature `safety`, exact on the surfaces its maps bound)
    /// over `map`, with its `shader` files.
    const fn safety_shape(
        kind: MethodKind,
        map: MapKind,
        shader: &'static [&'static str],
    ) -> MethodInfo {
        MethodInfo {
            surfaces: SAFETY_SURFACES,
            map: Some(map),
            shader,
            ..MethodInfo::base(kind, SAFETY)
        }
    }

    /// A method of the cone family (triangles only, exact within an iteration budget)
    /// over `map`, built by `feature`, with its `shader` files.
    const fn cone_family(
        kind: MethodKind,
        map: MapKind,
        feature: (Option<&'static str>, bool),
        shader: &'static [&'static str],
    ) -> MethodInfo {
        MethodInfo {
            accuracy: Accuracy::ExactWithinBudget,
            surfaces: TRIANGLES,
            map: Some(map),
            steps: ITERATIONS,
            shader,
            ..MethodInfo::base(kind, feature)
        }
    }
}

/// A cargo feature that leaves methods out ([`FEATURES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Feature {
    /// Its name, in this crate's and the C API's `Cargo.toml`.
    pub name: &'static str,
    /// The features it turns on.
    pub needs: &'static [&'static str],
    /// Whether this build has it on.
    pub built: bool,
    /// The C header's macro for it (cbindgen's define of the feature, which
    /// `capi/tests/header.rs` generates from this list).
    pub have_macro: &'static str,
}

/// The cargo features that leave methods out, in `Cargo.toml` order: the one list.
/// `core/Cargo.toml` and `capi/Cargo.toml` are checked against it, and the C API's
/// feature switches (`capi/src/features.rs`) and the header's `HF_HAVE_*` defines are
/// generated from it (`capi/tests/header.rs`). `all-methods` turns them all on.
pub const FEATURES: [Feature; 6] = {
    const fn f(
        name: &'static str,
        needs: &'static [&'static str],
        built: bool,
        have_macro: &'static str,
    ) -> Feature {
        Feature {
            name,
            needs,
            built,
            have_macro,
        }
    }
    [
        f("maxmip", &[], cfg!(feature = "maxmip"), "HF_HAVE_MAXMIP"),
        f("safety", &[], cfg!(feature = "safety"), "HF_HAVE_SAFETY"),
        f("cone", &["maxmip"], cfg!(feature = "cone"), "HF_HAVE_CONE"),
        f("qdm", &["cone"], cfg!(feature = "qdm"), "HF_HAVE_QDM"),
        f(
            "relaxed",
            &["cone"],
            cfg!(feature = "relaxed"),
            "HF_HAVE_RELAXED",
        ),
        f("search", &[], cfg!(feature = "search"), "HF_HAVE_SEARCH"),
    ]
};

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

/// Which shadow rays a scene traces: none, or towards a directional light from each
/// lit point, started at one end or the other of the same segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Shadows {
    /// No shadow rays.
    None = 0,
    /// From the lit point up towards the light ([`Hit::shadow_query`](crate::Hit::shadow_query)):
    /// they start inside the field's box and rise, so no narrower ray set holds them.
    FromSurface = 1,
    /// From the light's side down to the lit point
    /// ([`Hit::shadow_query_from_light`](crate::Hit::shadow_query_from_light)): they
    /// start outside the box and descend along the light's direction, so they are
    /// exterior rays, within the scene's view angle when the light is.
    FromLight = 2,
}

impl Shadows {
    /// Every value, in order.
    pub const ALL: [Shadows; 3] = [Shadows::None, Shadows::FromSurface, Shadows::FromLight];

    /// Whether shadow rays are traced.
    pub fn traced(self) -> bool {
        self != Shadows::None
    }

    /// The value numbered `v` (its discriminant, as the C API passes it).
    pub fn from_u32(v: u32) -> Option<Shadows> {
        Shadows::ALL.into_iter().find(|&s| s as u32 == v)
    }
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
    /// Which shadow rays are traced, if any.
    pub shadows: Shadows,
    /// Whether level-of-detail marching is used (maximum mipmaps only; approximate).
    pub lod: bool,
    /// Whether the shader writes the hit depth.
    pub depth_output: bool,
    /// The height texture's format.
    pub heights: HeightFormat,
    /// Whether the safety-shape maps are baked over static occluders
    /// ([`Rays::occluders`](crate::rayset::Rays::occluders); the list goes to the
    /// bake and the traces beside the plan's ray set): the shader keeps their guard.
    pub occluders: bool,
}

/// Why a [`Scene`] is invalid ([`Scene::validate`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneError {
    /// The ray-class set is empty or has bits above the four classes.
    RayClasses,
    /// `max_view_angle_deg` is outside (0, 180].
    ViewAngle,
}

impl core::fmt::Display for SceneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            SceneError::RayClasses => "the ray-class set is empty or unknown",
            SceneError::ViewAngle => "max_view_angle_deg is outside (0, 180]",
        })
    }
}

impl Scene {
    /// Checks the fields every user of a scene relies on (the C API's `hf_scene_check`,
    /// shader generation): a ray-class set of one to four classes, a view angle in
    /// (0, 180].
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.ray_classes.0 == 0 || self.ray_classes.0 > RayClasses::ALL.0 {
            return Err(SceneError::RayClasses);
        }
        let angle = self.max_view_angle_deg;
        if !(angle > 0.0 && angle <= 180.0) {
            return Err(SceneError::ViewAngle);
        }
        Ok(())
    }

    /// The general scene of `method` on `surface`: every ray class, viewpoints
    /// anywhere, any direction, shadows from the surface, no LOD, depth output, `F32`
    /// heights, occluders.
    pub fn general(method: MethodKind, surface: Surface) -> Scene {
        Scene {
            surface,
            method,
            ray_classes: RayClasses::ALL,
            outside_only: false,
            max_view_angle_deg: 180.0,
            shadows: Shadows::FromSurface,
            lod: false,
            depth_output: true,
            heights: HeightFormat::F32,
            occluders: true,
        }
    }
}

impl MethodKind {
    /// Whether this build of the core has the method (its cargo feature is on; the
    /// exact traversal always is).
    pub fn built(self) -> bool {
        self.info().built
    }
}

impl RayClasses {
    /// No class.
    pub const NONE: RayClasses = RayClasses(0);

    /// How many of the four classes the set holds (bits above the four are ignored).
    #[inline]
    pub fn count(self) -> u32 {
        u32::from(BITS[usize::from(self.0 & RayClasses::ALL.0)])
    }

    /// Where `class` sits among the classes of the set, in class order (its row in a
    /// texel's rows of a class-per-row map holding this set); `None` when not held.
    #[inline]
    pub fn slot(self, class: RayClass) -> Option<u32> {
        let bit = 1u8 << class as u8;
        (self.0 & bit != 0).then(|| u32::from(BITS[usize::from(self.0 & (bit - 1))]))
    }
}

/// The number of bits set in each four-bit value: a load where `count_ones` without a
/// popcount instruction (the baseline x86-64 target) is a dozen, once per march.
const BITS: [u8; 16] = {
    let mut b = [0; 16];
    let mut v = 0;
    while v < 16 {
        b[v] = (v as u32).count_ones() as u8;
        v += 1;
    }
    b
};

named_enum! {
    /// Something a bake can produce: a map the march reads, or an intermediate another
    /// bake reads.
    pub enum Product: u32 {
        /// The maximum-mipmap pyramid (`maxmip::bake`): the maxmip march reads it, and the
        /// cone, relaxed-cone and QDM bakes search it (`cone::prepare`).
        Pyramid = 0 => "pyramid" (Some(MapKind::MaxMip)),
        /// The strip bounds of the safety-shape bakes (`safety::prepare`).
        SafetyScratch = 1 => "safety scratch" (None),
        /// The safety-distance map (`safety::bake_rows_classes`).
        SafetyMap = 2 => "safety map" (Some(MapKind::Safety)),
        /// The packed cylinder–cone map (`safety::cc::bake_rows_classes`).
        CcMap = 3 => "cc map" (Some(MapKind::Cc)),
        /// The N-buffers the cylinder–cone slopes read (`safety::cc::prepare_nbuffer`),
        /// with either slope: the exact slope culls columns with them too.
        NBuffer = 4 => "n-buffer" (None),
        /// The conservative cone map (`cone::bake_rows::<cone::Cone>`).
        ConeMap = 5 => "cone map" (Some(MapKind::Cone)),
        /// The relaxed cone map (`cone::bake_rows::<relaxed::Relaxed>`).
        RelaxedMap = 6 => "relaxed map" (Some(MapKind::Relaxed)),
        /// The quadratic displacement map (`cone::bake_rows::<qdm::Qdm>`).
        QdmMap = 7 => "qdm map" (Some(MapKind::Qdm)),
        /// The safety-radius map (`radius::bake_rows`).
        RadiusMap = 8 => "radius map" (Some(MapKind::Radius)),
    }
    /// The map it is (a method reads it, [`MethodInfo::map`]); `None` for the
    /// intermediates only bakes read.
    pub fn map(self) -> Option<MapKind>;
}

/// Whether and how a scene needs a [`Product`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Need {
    /// Not baked; the reason says why.
    Skip(&'static str),
    /// Baked as the input of another bake only: free it once that bake is done.
    Scratch,
    /// Baked and read by the march: keep it (upload it).
    Keep,
}

/// Skip reason: the method marches the heights alone.
const NO_BAKE: &str = "the method reads no baked data";
/// Skip reason: another method's data.
const NOT_READ: &str = "the scene's method never reads it";
/// Skip reason: the cylinder–cone map packs its own safety distances.
const CC_OWN: &str = "the cylinder-cone map packs its own safety distances";
/// Skip reason: the QDM stores its own cone.
const QDM_OWN: &str = "the QDM stores its own cone";
/// Skip reason of a ray class's channel.
const CLASS_UNUSED: &str = "the scene casts no such ray: its rows are neither baked nor stored";
/// The ray classes in channel order, with the name of their channel.
const CLASS_CHANNELS: [(RayClass, &str); 4] = [
    (RayClass::XPos, "x+ channel"),
    (RayClass::XNeg, "x- channel"),
    (RayClass::YPos, "y+ channel"),
    (RayClass::YNeg, "y- channel"),
];
/// Skip reason of the directional layout.
const ONE_CLASS: &str = "one ray class: the isotropic byte holds its distances exactly";

/// What to bake for a [`Scene`], from [`Scene::bake_plan`]: per [`Product`] whether it
/// is needed and how, the ray classes the safety-shape bakes compute, and the safety
/// map's layout. [`BakePlan::skipped`] lists what is left out and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BakePlan {
    /// The method the plan serves.
    pub method: MethodKind,
    /// Per product, in [`Product::ALL`] order.
    pub needs: [Need; 9],
    /// The ray classes the safety-distance and cylinder–cone bakes compute (pass it to
    /// `safety::bake_rows_classes`, `safety::cc::bake_rows_classes`, and read the maps
    /// with the same set): the maps hold these classes' rows only. [`RayClasses::NONE`]
    /// when neither map is baked.
    pub classes: RayClasses,
    /// The safety-distance map's layout: isotropic (one byte per texel) when exactly
    /// one ray class occurs — then it holds that class's distances exactly —,
    /// directional (four) otherwise. `false` when no safety map is baked.
    pub isotropic: bool,
    /// The rays the safety-distance and cylinder–cone maps are baked for
    /// ([`Rays`](crate::rayset::Rays); [`Rays::ALL`](crate::rayset::Rays::ALL) for
    /// the other methods): exterior when the scene's origins stay outside the box,
    /// its view angle when below 180°, but every ray once it traces
    /// [`Shadows::FromSurface`] (they start inside the box and rise). Shadow rays
    /// traced [`Shadows::FromLight`] keep the scene's set: they are exterior, and
    /// within its view angle when the light is. A ray outside the set still gets its
    /// exact answer (the march's guard), only without the map's steps.
    pub rays: crate::rayset::Rays,
}

impl BakePlan {
    /// The bake of the map the plan's method marches over for a `width × height` field
    /// (its layout and ray classes as planned, the bake's default cap and choices);
    /// `None` for a method without a map.
    pub fn map_spec(&self, width: u32, height: u32) -> Option<crate::bake::Spec> {
        let map = match self.method.info().map? {
            MapKind::Safety if self.isotropic => MapKind::SafetyIsotropic,
            m => m,
        };
        let mut desc = crate::ktx2::Desc::new(map, width, height);
        if matches!(
            map,
            MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Cc
        ) {
            desc.classes = self.classes;
            desc.rays = self.rays;
        }
        Some(crate::bake::Spec::new(desc))
    }

    /// How the scene needs `p`.
    pub fn need(&self, p: Product) -> Need {
        self.needs[p as usize]
    }

    /// Whether `p` is baked (as scratch or kept).
    pub fn bakes(&self, p: Product) -> bool {
        !matches!(self.need(p), Need::Skip(_))
    }

    /// Whether nothing at all is baked (the exact and search methods).
    pub fn bakes_nothing(&self) -> bool {
        !Product::ALL.into_iter().any(|p| self.bakes(p))
    }

    /// What the plan leaves out, as `(item, reason)`: every skipped product, then,
    /// when a safety-shape map is baked, each ray class it does not compute and the
    /// directional layout when the isotropic one suffices.
    pub fn skipped(&self) -> impl Iterator<Item = (&'static str, &'static str)> {
        let products = Product::ALL
            .into_iter()
            .zip(self.needs)
            .filter_map(|(p, n)| match n {
                Need::Skip(why) => Some((p.name(), why)),
                _ => None,
            });
        let shapes = self.bakes(Product::SafetyMap) || self.bakes(Product::CcMap);
        let classes = self.classes;
        let class_items = CLASS_CHANNELS
            .into_iter()
            .filter(move |&(c, _)| shapes && !classes.contains(c))
            .map(|(_, name)| (name, CLASS_UNUSED));
        let layout = (self.isotropic && self.bakes(Product::SafetyMap))
            .then_some(("directional channels", ONE_CLASS));
        products.chain(class_items).chain(layout)
    }
}

impl Scene {
    /// What to bake for this scene, and what not: only the data its method reads,
    /// safety-shape channels only for the ray classes that occur, and the safety
    /// shapes for the scene's ray set (`outside_only`, `max_view_angle_deg`; every
    /// ray when the scene traces shadows from the surface, which start inside the box
    /// and rise).
    pub fn bake_plan(&self) -> BakePlan {
        use Need::{Keep, Scratch, Skip};
        use Product as P;
        let mut needs = [Skip(NOT_READ); 9];
        let mut set = |p: P, n: Need| needs[p as usize] = n;
        let mut classes = RayClasses::NONE;
        let mut isotropic = false;
        let mut rays = crate::rayset::Rays::ALL;
        let scene_rays = crate::rayset::Rays {
            exterior: self.outside_only,
            max_view_angle_deg: self.max_view_angle_deg,
            occluders: 0,
        };
        let scene_rays = match scene_rays.validate() {
            Ok(r) if self.shadows != Shadows::FromSurface => r,
            _ => crate::rayset::Rays::ALL,
        };
        // The method's own map is kept; the bakes' inputs are scratch.
        let map = self.method.info().map;
        for p in P::ALL {
            if map.is_none() {
                set(p, Skip(NO_BAKE));
            } else if p.map() == map {
                set(p, Keep);
            }
        }
        match self.method {
            MethodKind::Cone | MethodKind::Relaxed => set(P::Pyramid, Scratch),
            MethodKind::Qdm => {
                set(P::Pyramid, Scratch);
                set(P::ConeMap, Skip(QDM_OWN));
            }
            MethodKind::Safety => {
                set(P::SafetyScratch, Scratch);
                classes = self.ray_classes;
                isotropic = classes.count() == 1;
                rays = scene_rays;
            }
            MethodKind::Cc => {
                rays = scene_rays;
                set(P::SafetyScratch, Scratch);
                set(P::SafetyMap, Skip(CC_OWN));
                set(P::NBuffer, Scratch);
                classes = self.ray_classes;
            }
            MethodKind::Radius => set(P::SafetyScratch, Scratch),
            _ => {}
        }
        BakePlan {
            method: self.method,
            needs,
            classes: RayClasses(classes.0 & RayClasses::ALL.0),
            isotropic,
            rays,
        }
    }
}
