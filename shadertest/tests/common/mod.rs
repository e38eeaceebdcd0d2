//! The harness both WGSL tests share: the test-side compute entry point, the Vulkan
//! device (lavapipe in CI), scenes with every bake, their textures and uniforms in
//! the binding layout of `shaders/wgsl`, the table of cases, the rays, and one call
//! that runs a case's march over a batch of rays and reads the answers back.
#![allow(dead_code)] // each test binary uses a different part

use hfcast::cone::{self, ConeMap};
use hfcast::maxmip::{self, Layout, MaxMip};
use hfcast::projective::Projective;
use hfcast::qdm::{self, QdmMap};
use hfcast::radius::{self, RadiusMap, Zero};
use hfcast::rayset::{Occluder, Rays};
use hfcast::relaxed;
use hfcast::safety::cc::{self, CcMap, CcOptions, Slope};
use hfcast::safety::{self, MarchSurface, SafetyMap, Variant};
use hfcast::scene::{HeightFormat, MethodKind, RayClasses};
use hfcast::world::WorldTransform;
use hfcast::{HeightField, Marcher, Query, SearchSteps, Surface, Trace};
use hfcast_shaders::{wgsl_layout as binding, Lang, SafetyVariant, PYRAMID_TEX_WIDTH};
use hfcast_tools::Rng;
use wgpu::util::DeviceExt;

/// The test-side entry point appended to a method's source: one invocation per ray,
/// read from a storage buffer, traced with `hf_trace`, the `Trace` written out as
/// plain numbers (a `bool` is not host-shareable). Its resources are in `@group(1)`.
pub const WRAPPER: &str = r#"
// ---- test entry point (shadertest/tests/common/mod.rs)
struct TestRay {
    origin: vec4<f32>, // xyz, t_min
    dir: vec4<f32>,    // xyz, t_max
}

struct TestOut {
    head: vec4<u32>,    // has_hit, flags (trace | hit), fetches, 0
    point: vec4<f32>,   // hit.point, hit.t
    normal: vec4<f32>,  // hit.normal, clearance
    cell: vec4<u32>,    // hit.cell, 0, 0
}

@group(1) @binding(0) var<storage, read> test_rays: array<TestRay>;
@group(1) @binding(1) var<storage, read_write> test_out: array<TestOut>;

@compute @workgroup_size(64)
fn test_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= arrayLength(&test_rays)) {
        return;
    }
    let r = test_rays[k];
    let tr = hf_trace(Query(r.origin.xyz, r.dir.xyz, r.origin.w, r.dir.w));
    var flags = tr.flags;
    if (tr.has_hit) {
        flags |= tr.hit.flags;
    }
    test_out[k] = TestOut(vec4<u32>(u32(tr.has_hit), flags, tr.fetches, 0u),
                          vec4<f32>(tr.hit.point, tr.hit.t),
                          vec4<f32>(tr.hit.normal, tr.clearance),
                          vec4<u32>(tr.hit.cell, 0u, 0u));
}
"#;

/// The general WGSL source of `method` (`hfcast_shaders::general`): every scene
/// choice an `override`, heights an R32Float texture.
pub fn general_source(method: MethodKind) -> String {
    hfcast_shaders::general(method, Lang::Wgsl).unwrap_or_else(|e| panic!("{}: {e}", method.name()))
}

/// The general scene of `method` on `surface` (every ray class, upward rays), with
/// heights as 16-bit samples when `int_heights`.
pub fn scene_of(method: MethodKind, surface: Surface, int_heights: bool) -> hfcast::scene::Scene {
    let mut scene = hfcast::scene::Scene::general(method, surface);
    if int_heights {
        scene.heights = HeightFormat::U16;
    }
    scene
}

/// The ray-class subsets (`HF_RAYS_*` bits) whose compact safety-distance and
/// cylinder–cone maps (`bake_rows_classes`: only those classes' rows) the parity test
/// also runs, on rays of every class: {x+, y−} and {x−}.
pub const SUBSETS: [u8; 2] = [0b1001, 0b0010];

/// The ray set whose safety-distance and cylinder–cone maps (every class) the parity
/// test also runs: exterior rays within 60° of the downward vertical. The cameras'
/// rays start outside the box (the 45° ones mostly within the angle, the 5° ones
/// not); the random rays start anywhere: a ray outside the set walks cell by cell.
pub const RAY_SET: Rays = Rays {
    max_view_angle_deg: 60.0,
    ..Rays::EXTERIOR
};

/// The maps the scenes bake beside the whole ones: each class subset for every ray,
/// and every class for [`RAY_SET`], alone and over the scene's walls
/// ([`Scene::walls`]: `true`).
pub const MAP_SETS: [(u8, Rays, bool); 4] = [
    (SUBSETS[0], Rays::ALL, false),
    (SUBSETS[1], Rays::ALL, false),
    (15, RAY_SET, false),
    (15, RAY_SET, true),
];

/// Occluders around every scene (`hf_occluder_count` of the cases over walls): four
/// walls, each top two triangles.
pub const WALLS: usize = 8;

/// A short name of the ray-class set `classes`: `x+,y-`.
pub fn classes_name(classes: u8) -> String {
    let names: Vec<&str> = ["x+", "x-", "y+", "y-"]
        .into_iter()
        .enumerate()
        .filter(|(k, _)| classes & (1 << k) != 0)
        .map(|(_, n)| n)
        .collect();
    names.join(",")
}

/// The WGSL shader `hfcast_shaders::generate_with` makes for `scene` with the safety
/// layout `variant`.
pub fn generated_source(scene: &hfcast::scene::Scene, variant: Variant) -> String {
    let opts = hfcast_shaders::Options {
        safety_variant: layout(variant),
    };
    hfcast_shaders::generate_with(scene, Lang::Wgsl, &opts)
        .unwrap_or_else(|e| panic!("{} {}: {e}", scene.method.name(), scene.surface.name()))
}

/// hfcast-shaders' name of the safety-map layout `variant`.
pub fn layout(variant: Variant) -> SafetyVariant {
    match variant {
        Variant::Directional => SafetyVariant::Directional,
        Variant::Isotropic => SafetyVariant::Isotropic,
    }
}

/// The source of `method` for 16-bit heights (`field_int.wgsl`): the shader generated
/// for its general scene on the triangle surface, which every method traces.
pub fn int_heights_source(method: MethodKind) -> String {
    generated_source(
        &scene_of(method, Surface::Triangles, true),
        Variant::Directional,
    )
}

/// The `override` constants of the general sources (scene-level choices).
const OVERRIDES: [&str; 7] = [
    "hf_surface",
    "hf_safety_variant",
    "hf_safety_classes",
    "hf_cc_classes",
    "hf_rays_exterior",
    "hf_rays_max_view_angle",
    "hf_occluder_count",
];

/// The cylinder–cone cap of the bake and the march (as the C tests).
pub const CC_CAP: u8 = 64;

/// One march to compare: a method, the scene-level choices and the step counts
/// (`params` is written as the method's `hf_params` uniform).
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// The method.
    pub method: MethodKind,
    /// `hf_surface` (exact, search and maxmip methods; triangles or view-linear for the
    /// safety-shape methods safety, cc and radius).
    pub surface: Surface,
    /// `hf_safety_variant` (safety).
    pub variant: Variant,
    /// The method's `hf_params` as `u32`s, in declaration order.
    pub params: [u32; 4],
    /// `false` for the approximate methods (reported, held to the same criterion).
    pub exact: bool,
    /// Heights as a texture of 16-bit samples (`field_int.wgsl`) instead of R32Float.
    pub int_heights: bool,
    /// Runs the shader generated for the case's scene instead of the general source.
    pub generated: bool,
    /// The ray classes (`HF_RAYS_*` bits) the safety-distance or cylinder–cone map
    /// holds (`hf_safety_classes`, `hf_cc_classes`; the generated shader's scene's
    /// `ray_classes`): 15 for the whole maps, else one of [`SUBSETS`]' compact maps.
    pub classes: u8,
    /// The ray set those maps are baked for (`hf_rays_exterior`,
    /// `hf_rays_max_view_angle`; the generated shader's scene's `outside_only` and
    /// `max_view_angle_deg`): [`Rays::ALL`], or [`RAY_SET`] on the whole maps.
    pub rays: Rays,
    /// The maps of [`RAY_SET`] are baked over the scene's [`Scene::walls`]
    /// (`hf_occluder_count` [`WALLS`], the texture `hf_occluders`; the generated
    /// shader's scene's `occluders`).
    pub occluders: bool,
    /// Traces world rays with `hf_trace_world` under this transform (the `hf_world`
    /// uniform; the CPU side `WorldTransform::trace`) instead of grid rays with
    /// `hf_trace`.
    pub world: Option<WorldTransform>,
    /// Traces world rays with `hf_trace_projective` through this projective map (the
    /// shader gets it and its inverse as constants by rows; the CPU side
    /// `Projective::trace`) instead of grid rays with `hf_trace`.
    pub projective: Option<Projective>,
}

impl Case {
    /// A case of the general source on the whole maps, grid rays.
    pub const fn new(method: MethodKind, surface: Surface, params: [u32; 4], exact: bool) -> Case {
        Case {
            method,
            surface,
            variant: Variant::Directional,
            params,
            exact,
            int_heights: false,
            generated: false,
            classes: 15,
            rays: Rays::ALL,
            occluders: false,
            world: None,
            projective: None,
        }
    }

    /// This case on the compact maps holding the ray classes `classes` only (one of
    /// [`SUBSETS`]).
    const fn holding(self, classes: u8) -> Case {
        Case { classes, ..self }
    }

    /// This case on the maps baked for [`RAY_SET`].
    const fn exterior(self) -> Case {
        Case {
            rays: RAY_SET,
            ..self
        }
    }

    /// This case on the maps baked for [`RAY_SET`] over the scene's walls.
    const fn over_walls(self) -> Case {
        Case {
            rays: RAY_SET,
            occluders: true,
            ..self
        }
    }

    /// The ray set of this case's maps on `scene` (with the fingerprint of its walls
    /// for a case over walls), and the occluders the marches take.
    pub fn set_on<'a>(&self, scene: &'a Scene) -> (Rays, &'a [Occluder]) {
        if self.occluders {
            let set = self.rays.passing_over(&scene.walls).expect("walls");
            (set, &scene.walls)
        } else {
            (self.rays, &[])
        }
    }

    /// This case with the heights as 16-bit samples: hfcast-shaders makes shaders for
    /// 16-bit heights for scenes only, so the case runs its scene's generated shader.
    const fn u16(self) -> Case {
        Case {
            int_heights: true,
            generated: true,
            ..self
        }
    }

    /// Every case of the parity test: exact on all five surfaces, the search methods,
    /// maxmip on triangles and bilinear, safety (both layouts), cc, cone, qdm, relaxed
    /// (step counts of the C tests), radius (zero radii walked and clamped), safety
    /// (directional), cc and radius (walked) again on the view-linear surface, a few with
    /// 16-bit heights; then all of them again as the shaders generated for their scenes.
    pub fn all() -> Vec<Case> {
        let tri = Surface::Triangles;
        let mut cases: Vec<Case> = Surface::ALL
            .iter()
            .map(|&s| Case::new(MethodKind::Exact, s, [0; 4], true))
            .collect();
        cases.extend([
            Case::new(MethodKind::LinearBinary, tri, [64, 8, 0, 0], false),
            Case::new(
                MethodKind::LinearBinary,
                Surface::Bilinear,
                [64, 8, 0, 0],
                false,
            ),
            Case::new(MethodKind::LinearSecant, tri, [64, 0, 0, 0], false),
            // hf_params.range: a one-texel distance of 64 grid units, so that the
            // scenes' rays reach coarse levels.
            Case::new(MethodKind::Multires, tri, [64, 0, 0, 0], false),
            Case::new(
                MethodKind::Multires,
                Surface::Bilinear,
                [64, 0, 0, 0],
                false,
            ),
            Case::new(MethodKind::MaxMip, tri, [0; 4], true),
            Case::new(MethodKind::MaxMip, Surface::Bilinear, [0; 4], true),
            Case::new(MethodKind::Safety, tri, [0; 4], true),
            Case {
                variant: Variant::Isotropic,
                ..Case::new(MethodKind::Safety, tri, [0; 4], true)
            },
            Case::new(MethodKind::Cc, tri, [0; 4], true),
            Case::new(MethodKind::Cone, tri, [512, 0, 0, 0], true),
            Case::new(MethodKind::Qdm, tri, [512, 0, 0, 0], true),
            Case::new(MethodKind::Relaxed, tri, [64, 8, 0, 0], false),
            // hf_params.clamp: 0 walks zero radii (exact), 1 clamps them to 1.
            Case::new(MethodKind::Radius, tri, [0; 4], true),
            Case::new(MethodKind::Radius, tri, [1, 0, 0, 0], false),
            // The safety-shape marches finishing on the view-linear surface (§7) from the
            // same triangle-baked maps.
            Case::new(MethodKind::Safety, Surface::ViewLinear, [0; 4], true),
            Case::new(MethodKind::Cc, Surface::ViewLinear, [0; 4], true),
            Case::new(MethodKind::Radius, Surface::ViewLinear, [0; 4], true),
            // 16-bit heights (field_int.wgsl) where the scene has samples.
            Case::new(MethodKind::Exact, tri, [0; 4], true).u16(),
            Case::new(MethodKind::Exact, Surface::HeightPlanes, [0; 4], true).u16(),
            Case::new(MethodKind::MaxMip, Surface::Bilinear, [0; 4], true).u16(),
            Case::new(MethodKind::Cc, tri, [0; 4], true).u16(),
            Case::new(MethodKind::Cone, tri, [512, 0, 0, 0], true).u16(),
        ]);
        // Compact maps of a ray-class subset (only those classes' rows) read with the
        // class set, on rays of every class: those of the other classes read zero jumps
        // without a fetch.
        for classes in SUBSETS {
            cases.extend([
                Case::new(MethodKind::Safety, tri, [0; 4], true).holding(classes),
                Case {
                    variant: Variant::Isotropic,
                    ..Case::new(MethodKind::Safety, tri, [0; 4], true)
                }
                .holding(classes),
                Case::new(MethodKind::Cc, tri, [0; 4], true).holding(classes),
            ]);
        }
        cases.extend([
            Case::new(MethodKind::Safety, Surface::ViewLinear, [0; 4], true).holding(SUBSETS[1]),
            Case::new(MethodKind::Cc, Surface::ViewLinear, [0; 4], true).holding(SUBSETS[0]),
        ]);
        // Maps of a ray set, read with the set: a ray outside it reads zero jumps.
        cases.extend([
            Case::new(MethodKind::Safety, tri, [0; 4], true).exterior(),
            Case {
                variant: Variant::Isotropic,
                ..Case::new(MethodKind::Safety, tri, [0; 4], true)
            }
            .exterior(),
            Case::new(MethodKind::Cc, tri, [0; 4], true).exterior(),
            Case::new(MethodKind::Cc, Surface::ViewLinear, [0; 4], true).exterior(),
        ]);
        // The same set over the scene's walls: a ray whose line dips under one reads
        // zero jumps.
        cases.extend([
            Case::new(MethodKind::Safety, tri, [0; 4], true).over_walls(),
            Case {
                variant: Variant::Isotropic,
                ..Case::new(MethodKind::Safety, tri, [0; 4], true)
            }
            .over_walls(),
            Case::new(MethodKind::Cc, tri, [0; 4], true).over_walls(),
            Case::new(MethodKind::Cc, Surface::ViewLinear, [0; 4], true).over_walls(),
        ]);
        // And every general one generated for its scene (overrides made constants,
        // unused branches and functions left out).
        let generated: Vec<Case> = cases
            .iter()
            .filter(|c| !c.generated)
            .map(|c| Case {
                generated: true,
                ..*c
            })
            .collect();
        cases.extend(generated);
        cases
    }

    /// A short name: method, and the surface or layout where the method has one.
    pub fn label(&self) -> String {
        let m = self.method.name();
        let heights = if self.int_heights { " u16" } else { "" };
        let generated = if self.generated && !self.int_heights {
            " generated"
        } else {
            ""
        };
        let name = match self.method {
            MethodKind::Exact
            | MethodKind::LinearBinary
            | MethodKind::LinearSecant
            | MethodKind::Multires
            | MethodKind::MaxMip => {
                format!("{m} {}", self.surface.name())
            }
            MethodKind::Safety => format!("{m} {:?}", self.variant).to_lowercase(),
            MethodKind::Radius => format!("{m} {:?}", self.zero()).to_lowercase(),
            _ => m.to_string(),
        };
        // The safety-shape methods on a surface other than their default triangles.
        let surface = match self.method {
            MethodKind::Safety | MethodKind::Cc | MethodKind::Radius
                if self.surface != Surface::Triangles =>
            {
                format!(" {}", self.surface.name())
            }
            _ => String::new(),
        };
        let classes = if self.classes == 15 {
            String::new()
        } else {
            format!(" holding {}", classes_name(self.classes))
        };
        let rays = if self.rays.is_all() {
            String::new()
        } else {
            format!(" for {}", self.rays)
        };
        let walls = if self.occluders { " over walls" } else { "" };
        name + &surface + &classes + &rays + walls + heights + generated
    }

    /// The source the case runs, with the test entry point (calling `hf_trace_world`
    /// for a world case): the method's general source, or the shader generated for the
    /// case's scene (its surface, heights and safety layout) when `generated`.
    pub fn source(&self) -> String {
        let mut scene = hfcast::scene::Scene {
            ray_classes: RayClasses(self.classes),
            ..scene_of(self.method, self.surface, self.int_heights)
        };
        if !self.rays.is_all() {
            // The scene whose bake plan bakes the maps for the case's set: its rays,
            // no shadow rays (they start on the surface).
            scene.outside_only = self.rays.exterior;
            scene.max_view_angle_deg = self.rays.max_view_angle_deg;
            scene.shadows = hfcast::scene::Shadows::None;
        }
        scene.occluders = self.occluders;
        let src = if self.generated {
            generated_source(&scene, self.variant)
        } else {
            general_source(self.method)
        };
        match (self.world, self.projective) {
            (Some(_), _) => src + &WRAPPER.replace("hf_trace(Query", "hf_trace_world(Query"),
            (None, Some(p)) => {
                let rows = |m: &hfcast::projective::Mat4| {
                    let row = |r: &[f64; 4]| {
                        let v: Vec<String> = r.iter().map(|x| format!("{:?}", *x as f32)).collect();
                        format!("vec4<f32>({})", v.join(", "))
                    };
                    format!(
                        "Mat4Rows({})",
                        m.iter().map(row).collect::<Vec<_>>().join(", ")
                    )
                };
                let consts = format!(
                    "\nconst TEST_M: Mat4Rows = {};\nconst TEST_M_INV: Mat4Rows = {};\n",
                    rows(p.matrix()),
                    rows(p.inverse())
                );
                src + &consts
                    + &WRAPPER.replace(
                        "hf_trace(Query",
                        "hf_trace_projective(TEST_M, TEST_M_INV, Query",
                    )
            }
            (None, None) => src + WRAPPER,
        }
    }

    /// The values of the `override` constants `src` declares (none in a generated
    /// shader: its scene choices are constants).
    pub fn constants(&self, src: &str) -> Vec<(&'static str, f64)> {
        let value = |name: &str| match name {
            "hf_surface" => f64::from(self.surface as u32),
            "hf_safety_classes" | "hf_cc_classes" => f64::from(self.classes),
            "hf_rays_exterior" => f64::from(u8::from(self.rays.exterior)),
            "hf_rays_max_view_angle" => f64::from(self.rays.max_view_angle_deg),
            "hf_occluder_count" => f64::from(if self.occluders { WALLS as u32 } else { 0 }),
            _ => f64::from(layout(self.variant) as u32),
        };
        OVERRIDES
            .into_iter()
            .filter(|n| src.contains(&format!("override {n}:")))
            .map(|n| (n, value(n)))
            .collect()
    }

    /// What the radius march does at a zero radius (`params[0]`, `hf_params.clamp`).
    pub fn zero(&self) -> Zero {
        if self.params[0] == 1 {
            Zero::Clamp
        } else {
            Zero::Walk
        }
    }

    /// The Rust core's f32 march of this case over `rays` (the dispatch of
    /// `capi/src/trace.rs`).
    pub fn cpu(&self, scene: &Scene, rays: &[Ray]) -> Vec<Trace<f32>> {
        let hf = scene.hf();
        let p = self.params;
        let mip = MaxMip::new(&hf, &scene.pyramid).expect("pyramid");
        let maps = scene.maps(self.classes, self.rays, self.occluders);
        let (set, walls) = self.set_on(scene);
        let safety_data = match self.variant {
            Variant::Directional => maps.safety_dir,
            Variant::Isotropic => maps.safety_iso,
        };
        let classes = RayClasses(self.classes);
        let safety_map = SafetyMap::with_classes(&hf, safety_data, self.variant, classes)
            .expect("safety map")
            .with_rays(set)
            .with_occluders(&hf, walls)
            .expect("the walls");
        let cc_map = CcMap::with_classes(&hf, maps.cc, CC_CAP, classes)
            .expect("cc map")
            .with_rays(set)
            .with_occluders(&hf, walls)
            .expect("the walls");
        let cone_map = ConeMap::new(&hf, &scene.cone).expect("cone map");
        let qdm_map = QdmMap::new(&hf, &scene.qdm).expect("qdm map");
        let radius_map = RadiusMap::new(&hf, &scene.radius).expect("radius map");
        // The surface the safety-shape marches finish on.
        let march_surface = || {
            MarchSurface::of(self.surface)
                .unwrap_or_else(|| panic!("no safety-shape march on {}", self.surface.name()))
        };
        let radius_opts = radius::Options {
            zero: self.zero(),
            surface: match self.method {
                MethodKind::Radius => march_surface(),
                _ => MarchSurface::Triangles,
            },
        };
        let marcher = match self.method {
            MethodKind::Exact => Marcher::Exact(self.surface),
            MethodKind::LinearBinary => Marcher::LinearBinary(
                self.surface,
                SearchSteps {
                    linear: p[0],
                    binary: p[1],
                },
            ),
            MethodKind::LinearSecant => Marcher::LinearSecant(self.surface, p[0]),
            MethodKind::Multires => Marcher::Multires(self.surface, p[0]),
            MethodKind::MaxMip => Marcher::MaxMip(mip, self.surface, maxmip::Options::default()),
            MethodKind::Safety => Marcher::Safety(safety_map, march_surface()),
            MethodKind::Cc => Marcher::Cc(cc_map, march_surface()),
            MethodKind::Radius => Marcher::Radius(radius_map, radius_opts),
            MethodKind::Cone => Marcher::Cone(cone_map, p[0]),
            MethodKind::Qdm => Marcher::Qdm(qdm_map, p[0]),
            MethodKind::Relaxed => {
                let map = scene.relaxed.as_ref().expect("relaxed bake");
                let steps = relaxed::Steps {
                    cone: p[0],
                    binary: p[1],
                };
                Marcher::Relaxed(map, steps)
            }
        };
        let trace = |q: &Query<f32>| marcher.trace(&hf, q);
        match (self.world, self.projective) {
            (Some(world), _) => rays
                .iter()
                .map(|r| world.trace(r, trace).expect("a world ray in grid space"))
                .collect(),
            (None, Some(p)) => rays
                .iter()
                .map(|r| {
                    p.trace(&hf, r, trace)
                        .expect("a world ray on the projective field")
                })
                .collect(),
            (None, None) => rays.iter().map(trace).collect(),
        }
    }

    /// The `@group(0)` bindings the case's entry point uses: the method's, and
    /// `hf_world` for a world case.
    pub fn bindings(&self) -> Vec<u32> {
        let mut b = self.method_bindings().to_vec();
        if self.world.is_some() {
            b.push(binding::WORLD);
        }
        b
    }

    /// The `@group(0)` bindings the method's `hf_trace` uses.
    fn method_bindings(&self) -> &'static [u32] {
        use binding::*;
        match self.method {
            MethodKind::Exact => &[HEIGHTS, FIELD],
            MethodKind::LinearBinary | MethodKind::LinearSecant | MethodKind::Multires => {
                &[HEIGHTS, FIELD, PARAMS]
            }
            MethodKind::MaxMip => &[HEIGHTS, FIELD, PYRAMID, MAXMIP],
            MethodKind::Safety => &[HEIGHTS, FIELD, SAFETY_MAP, OCCLUDERS],
            MethodKind::Cone => &[HEIGHTS, FIELD, PARAMS, CONE_MAP],
            MethodKind::Qdm => &[HEIGHTS, FIELD, PARAMS, QDM_MAP],
            MethodKind::Relaxed => &[HEIGHTS, FIELD, PARAMS, RELAXED_MAP],
            MethodKind::Cc => &[HEIGHTS, FIELD, CC_MAP, CC, OCCLUDERS],
            MethodKind::Radius => &[HEIGHTS, FIELD, PARAMS, RADIUS_MAP],
        }
    }
}

// ---------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------

/// A height field and every bake the cases read (relaxed only on small fields: its
/// bake is Θ(N⁴)).
pub struct Scene {
    /// Name for the report.
    pub name: String,
    /// Samples along x.
    pub w: u32,
    /// Samples along y.
    pub h: u32,
    /// `w × h` heights, row-major.
    pub heights: Vec<f32>,
    /// The maximum-mipmap pyramid.
    pub pyramid: Vec<f32>,
    /// Directional safety distances (4 bytes per texel, one row per class: W × 4H).
    pub safety_dir: Vec<u8>,
    /// Isotropic safety distances (1 byte per texel).
    pub safety_iso: Vec<u8>,
    /// Cone map, `[top, ratio]` per cell.
    pub cone: Vec<f32>,
    /// QDM map, `[a, b, c, h]` per cell.
    pub qdm: Vec<f32>,
    /// Relaxed cone ratios per sample, when baked.
    pub relaxed: Option<Vec<f32>>,
    /// Packed cylinder–cone map (8 bytes per texel: `[r, s]` per class).
    pub cc: Vec<u8>,
    /// Safety radii, tolerance 0 (1 byte per texel).
    pub radius: Vec<u8>,
    /// The 16-bit samples the heights came from and the height of one sample step
    /// (`depth / 65535` in f32), for maps read from PNG.
    pub samples: Option<(Vec<u16>, f32)>,
    /// The maps of each of [`MAP_SETS`], in its order.
    pub subsets: Vec<ClassMaps>,
    /// The occluders around the field (`hfcast_tools::maps::walls_around`, [`WALLS`]
    /// of them).
    pub walls: Vec<Occluder>,
}

/// The safety-distance (both layouts) and cylinder–cone maps of a ray-class set, as
/// `bake_rows_classes` writes them: `n` rows per texel row for the set's `n` classes
/// (directional, cylinder–cone), one byte per texel (isotropic, the minimum over the
/// set's classes).
pub struct ClassMaps {
    /// The classes held (`HF_RAYS_*` bits).
    pub classes: u8,
    /// The rays the maps are baked for.
    pub rays: Rays,
    /// Whether they are baked over the scene's walls too.
    pub occluded: bool,
    /// Directional safety distances, W × nH bytes.
    pub safety_dir: Vec<u8>,
    /// Isotropic safety distances over the set, W × H bytes.
    pub safety_iso: Vec<u8>,
    /// Packed cylinder–cone map, W × nH × 2 bytes.
    pub cc: Vec<u8>,
}

/// Borrowed maps of one class set (the whole maps for 15).
pub struct MapsRef<'a> {
    /// Directional safety distances.
    pub safety_dir: &'a [u8],
    /// Isotropic safety distances.
    pub safety_iso: &'a [u8],
    /// Packed cylinder–cone map.
    pub cc: &'a [u8],
}

impl Scene {
    /// Bakes everything for `heights` (`w × h`, row-major); relaxed when `relaxed`.
    pub fn new(name: &str, w: u32, h: u32, heights: Vec<f32>, relaxed: bool) -> Scene {
        let hf = HeightField::new(&heights, w, h, w as usize).expect("valid field");
        let mut pyramid = vec![0f32; maxmip::pyramid_len(w, h)];
        maxmip::bake(&hf, &mut pyramid).expect("maxmip bake");
        let mut scratch = vec![0f32; safety::scratch_len(w, h)];
        let safety_bake = |variant: Variant, scratch: &mut [f32]| {
            let opts = safety::Options {
                variant,
                positive: false,
                cap: u8::MAX,
            };
            let mut out = vec![0u8; safety::map_len(w, h, variant)];
            safety::bake(&hf, scratch, opts, &mut out).expect("safety bake");
            out
        };
        let safety_dir = safety_bake(Variant::Directional, &mut scratch);
        let safety_iso = safety_bake(Variant::Isotropic, &mut scratch);
        // The slow bakes (cc, cone, qdm) by row ranges on every core; `scratch` holds
        // what safety::prepare filled (safety::bake prepares it).
        let mut nb = vec![0f32; cc::nbuffer_len(w, h, CC_CAP)];
        cc::prepare_nbuffer(&hf, CC_CAP, &mut nb).expect("n-buffer");
        let opts = CcOptions {
            slope: Slope::Exact,
            cap: CC_CAP,
        };
        let mut cc_map = vec![0u8; cc::map_len(w, h)];
        in_row_ranges(h, cc::map_len(w, 1), &mut cc_map, |rows, out| {
            cc::bake_rows(&hf, &scratch, &nb, rows, opts, out).expect("cc bake");
        });
        let mut radius_map = vec![0u8; radius::map_len(w, h)];
        in_row_ranges(h, w as usize, &mut radius_map, |rows, out| {
            radius::bake_rows(&hf, &scratch, rows, radius::BakeOptions::default(), out)
                .expect("radius bake");
        });
        let mut cone_scratch = vec![0f32; cone::scratch_len(w, h)];
        cone::prepare(&hf, &mut cone_scratch).expect("cone pyramid");
        let mut cone_map = vec![0f32; cone::map_len(w, h)];
        in_row_ranges(h - 1, 2 * (w - 1) as usize, &mut cone_map, |rows, out| {
            cone::bake_rows::<cone::Cone>(&hf, &cone_scratch, rows, out).expect("cone bake");
        });
        let mut qdm_scratch = vec![0f32; qdm::scratch_len(w, h)];
        qdm::prepare(&hf, &mut qdm_scratch).expect("qdm pyramid");
        let mut qdm_map = vec![0f32; qdm::map_len(w, h)];
        in_row_ranges(h - 1, 4 * (w - 1) as usize, &mut qdm_map, |rows, out| {
            cone::bake_rows::<qdm::Qdm>(&hf, &qdm_scratch, rows, out).expect("qdm bake");
        });
        // The maps of the class subsets and the ray set; `scratch` holds what
        // safety::prepare filled.
        let walls = hfcast_tools::maps::walls_around(&hf);
        let subsets = MAP_SETS
            .iter()
            .map(|&(bits, rays, occluded)| {
                let classes = RayClasses(bits);
                let over: &[Occluder] = if occluded { &walls } else { &[] };
                let set = rays.passing_over(over).expect("walls");
                let sd = |variant: Variant| {
                    let opts = safety::Options {
                        variant,
                        positive: false,
                        cap: u8::MAX,
                    };
                    let mut out = vec![0u8; safety::map_len_classes(w, h, variant, classes)];
                    let row_len = safety::map_len_classes(w, 1, variant, classes);
                    in_row_ranges(h, row_len, &mut out, |rows, out| {
                        safety::bake_rows_classes(
                            &hf,
                            &scratch,
                            &set.on_over(&hf, over).expect("walls"),
                            classes,
                            rows,
                            opts,
                            out,
                        )
                        .expect("safety bake of a class subset");
                    });
                    out
                };
                let mut cc_sub = vec![0u8; cc::map_len_classes(w, h, classes)];
                let row_len = cc::map_len_classes(w, 1, classes);
                in_row_ranges(h, row_len, &mut cc_sub, |rows, out| {
                    let on = set.on_over(&hf, over).expect("walls");
                    cc::bake_rows_with(&hf, &scratch, &nb, &on, classes, rows, opts, out)
                        .expect("cc bake of a class subset");
                });
                ClassMaps {
                    classes: bits,
                    rays,
                    occluded,
                    safety_dir: sd(Variant::Directional),
                    safety_iso: sd(Variant::Isotropic),
                    cc: cc_sub,
                }
            })
            .collect();
        let relaxed_map = relaxed.then(|| {
            let mut s = vec![0f32; relaxed::scratch_len(w, h)];
            let mut out = vec![0f32; relaxed::map_len(w, h)];
            cone::bake::<relaxed::Relaxed>(&hf, &mut s, &mut out).expect("relaxed bake");
            out
        });
        Scene {
            name: name.to_string(),
            w,
            h,
            pyramid,
            safety_dir,
            safety_iso,
            cone: cone_map,
            qdm: qdm_map,
            relaxed: relaxed_map,
            cc: cc_map,
            radius: radius_map,
            heights,
            samples: None,
            subsets,
            walls,
        }
    }

    /// The maps holding the ray classes `classes` for the rays `rays` (over the
    /// walls when `occluded`): the whole maps for 15 and every ray, else those of one
    /// of [`MAP_SETS`].
    pub fn maps(&self, classes: u8, rays: Rays, occluded: bool) -> MapsRef<'_> {
        if classes == 15 && rays.is_all() {
            return MapsRef {
                safety_dir: &self.safety_dir,
                safety_iso: &self.safety_iso,
                cc: &self.cc,
            };
        }
        let m = self
            .subsets
            .iter()
            .find(|m| m.classes == classes && m.rays == rays && m.occluded == occluded)
            .unwrap_or_else(|| panic!("no maps of the classes {classes:#06b} for {rays}"));
        MapsRef {
            safety_dir: &m.safety_dir,
            safety_iso: &m.safety_iso,
            cc: &m.cc,
        }
    }

    /// The scene with the 16-bit `samples` its heights were converted from with
    /// `HeightField::from_u16` and relief `depth`.
    pub fn with_samples(mut self, samples: Vec<u16>, depth: f32) -> Scene {
        assert_eq!(samples.len(), self.heights.len());
        self.samples = Some((samples, depth / 65535.0));
        self
    }

    /// The synthetic `w × h` field of [`spiky_fractal`] (relief 6) for `seed`, named by
    /// its size; relaxed baked when `relaxed`.
    pub fn spiky(seed: u64, w: u32, h: u32, relaxed: bool) -> Scene {
        let name = format!("spiky fractal {w}x{h}");
        Scene::new(&name, w, h, spiky_fractal(seed, w, h, 6.0), relaxed)
    }

    /// The height field over [`Scene::heights`].
    pub fn hf(&self) -> HeightField<'_> {
        HeightField::new(&self.heights, self.w, self.h, self.w as usize).expect("valid field")
    }

    /// The `cw × ch` corner (origin at sample (0, 0)) of the row-major `w`-wide `values`.
    pub fn crop<T: Copy>(values: &[T], w: u32, cw: u32, ch: u32) -> Vec<T> {
        (0..ch)
            .flat_map(|j| {
                let row = (j * w) as usize;
                values[row..row + cw as usize].iter().copied()
            })
            .collect()
    }
}

/// Runs `bake(rows, out)` over `rows` rows of `row_len` values of `out`, split into
/// one contiguous range per core.
fn in_row_ranges<T: Send>(
    rows: u32,
    row_len: usize,
    out: &mut [T],
    bake: impl Fn(std::ops::Range<u32>, &mut [T]) + Sync,
) {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let per = rows.div_ceil(threads.max(1)).max(1);
    std::thread::scope(|s| {
        for (k, chunk) in out[..rows as usize * row_len]
            .chunks_mut(per as usize * row_len)
            .enumerate()
        {
            let start = k as u32 * per;
            let range = start..(start + per).min(rows);
            let bake = &bake;
            s.spawn(move || bake(range, chunk));
        }
    });
}

/// The bundled map `data/dem_jacksboro_fault_403x344.png` loaded by the tools
/// (`hfcast_tools::maps`: heights `png / 65535 × depth`, depth 0.1 × max(W, H)), with
/// the 16-bit samples its heights were made of. Returns `(w, h, samples, depth,
/// heights)`.
pub fn load_bundled_map() -> (u32, u32, Vec<u16>, f32, Vec<f32>) {
    let path = hfcast_tools::maps::bundled_map();
    let map = hfcast_tools::maps::load_map(&path, None)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (w, h, depth) = (map.width, map.height, map.depth);
    // Each height is the f32 product sample × (depth / 65535), so dividing by the step
    // and rounding gives the sample back; checked by converting again.
    let step = depth / 65535.0;
    let samples: Vec<u16> = map
        .heights
        .iter()
        .map(|&z| (z / step).round() as u16)
        .collect();
    let mut again = vec![0f32; map.heights.len()];
    HeightField::from_u16(&samples, w, h, w as usize, depth, &mut again).expect("heights");
    assert!(again == map.heights, "the map's samples are not recovered");
    (w, h, samples, depth, map.heights)
}

/// The tools' seeded SplitMix64 generator with `seed` mixed with the golden-ratio
/// increment (so the fields and rays are those the tests were calibrated with).
fn rng(seed: u64) -> Rng {
    Rng::new(seed ^ 0x9E37_79B9_7F4A_7C15)
}

/// A synthetic `w × h` field: a fractal-ish sum of sines with a little noise, plus
/// single-sample needles three times the relief high and 1-texel walls (a column, a
/// row and a diagonal) at twice the relief, as the core's tests build them.
pub fn spiky_fractal(seed: u64, w: u32, h: u32, amp: f64) -> Vec<f32> {
    let mut rng = rng(seed);
    let waves: Vec<[f64; 4]> = (0..8)
        .map(|k| {
            let f = 0.05 * 1.9f64.powi(k);
            let a = rng.range(0.0, std::f64::consts::TAU);
            let ph = rng.range(0.0, std::f64::consts::TAU);
            [f * a.cos(), f * a.sin(), ph, amp / 1.8f64.powi(k)]
        })
        .collect();
    let mut out = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (f64::from(i), f64::from(j));
            let mut z: f64 = waves
                .iter()
                .map(|[fx, fy, ph, a]| a * (fx * x + fy * y + ph).sin())
                .sum();
            z += rng.range(-0.02, 0.02) * amp;
            if rng.next_u64().is_multiple_of(37) {
                z += 3.0 * amp;
            }
            if i == w / 3 || j == 2 * h / 3 || i == j {
                z += 2.0 * amp;
            }
            out.push(z as f32);
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Rays
// ---------------------------------------------------------------------------------

/// Smallest agreeing fraction of the rays of a case.
pub const MIN_AGREE: f64 = 0.9999;

/// How the rays of one case compare with the core, counted over the scenes (each test
/// counts more differences of its own beside these).
#[derive(Default)]
pub struct Agreement {
    /// Rays traced.
    pub rays: u64,
    /// Rays that agree.
    pub agree: u64,
    /// Agreeing hits.
    pub hits: u64,
    /// Largest difference of an agreeing hit's t (the test's measure).
    pub max_dt: f64,
    /// Agreeing rays whose fetch counts differ.
    pub fetches_differ: u64,
    /// Agreeing hits whose cells differ.
    pub cell_differ: u64,
    /// Every ray that does not agree, described.
    pub wrong: Vec<String>,
}

impl Agreement {
    /// Counts an agreeing hit: its t difference, and whether its cell differs.
    pub fn hit(&mut self, dt: f64, cell_differs: bool) {
        self.hits += 1;
        self.max_dt = self.max_dt.max(dt);
        self.cell_differ += u64::from(cell_differs);
    }

    /// Counts a ray: whether it agrees (else `wrong` describes it), and for an agreeing
    /// one whether its fetch count differs. Returns `agree`.
    pub fn ray(
        &mut self,
        agree: bool,
        fetches_differ: bool,
        wrong: impl FnOnce() -> String,
    ) -> bool {
        self.rays += 1;
        if !agree {
            self.wrong.push(wrong());
            return false;
        }
        self.agree += 1;
        self.fetches_differ += u64::from(fetches_differ);
        true
    }

    /// The agreeing fraction.
    pub fn rate(&self) -> f64 {
        self.agree as f64 / self.rays.max(1) as f64
    }

    /// Whether at least [`MIN_AGREE`] of the rays agree.
    pub fn passes(&self) -> bool {
        self.rate() >= MIN_AGREE
    }
}

/// A ray: the validated f32 query the core traces and the wrapper reads (origin, unit
/// direction so t is in texels, range).
pub type Ray = Query<f32>;

fn unit(d: [f64; 3]) -> [f32; 3] {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [(d[0] / l) as f32, (d[1] / l) as f32, (d[2] / l) as f32]
}

fn ray(o: [f64; 3], d: [f64; 3], t_min: f64, t_max: f64) -> Ray {
    Query::from_arrays(o.map(|v| v as f32), unit(d), t_min as f32, t_max as f32).expect("valid ray")
}

/// `n × n` pinhole-camera rays looking at the field's centre from `elevation` degrees
/// above the horizon at `azimuth` degrees, from 1.25 × max(W, H) away, field of view
/// 0.7 rad (the C renderer's camera).
pub fn camera_rays(scene: &Scene, elevation: f64, azimuth: f64, n: u32) -> Vec<Ray> {
    let hf = scene.hf();
    let size = f64::from(scene.w.max(scene.h));
    let target = [
        0.5 * f64::from(scene.w - 1),
        0.5 * f64::from(scene.h - 1),
        0.5 * (f64::from(hf.min_height()) + f64::from(hf.max_height())),
    ];
    let (el, az) = (elevation.to_radians(), azimuth.to_radians());
    let dist = 1.25 * size;
    let eye = [
        target[0] + dist * el.cos() * az.cos(),
        target[1] + dist * el.cos() * az.sin(),
        target[2] + dist * el.sin(),
    ];
    let f = unit([target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]]).map(f64::from);
    let right = unit([-f[1], f[0], 0.0]).map(f64::from);
    let up = [
        right[1] * f[2] - right[2] * f[1],
        right[2] * f[0] - right[0] * f[2],
        right[0] * f[1] - right[1] * f[0],
    ];
    let th = (0.5f64 * 0.7).tan();
    let mut rays = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let sx = (2.0 * (f64::from(x) + 0.5) / f64::from(n) - 1.0) * th;
            let sy = (2.0 * (f64::from(y) + 0.5) / f64::from(n) - 1.0) * th;
            let d = [0, 1, 2].map(|k| f[k] + sx * right[k] + sy * up[k]);
            rays.push(ray(eye, d, 0.0, f64::INFINITY));
        }
    }
    rays
}

/// The rays of each of `scenes` (scene `k` with seed `seed + k`): `n × n` camera rays
/// from 45° and 5° above the horizon, two azimuths each ([`camera_rays`]), then
/// `random` random rays ([`random_rays`]), then the light's rays to the first camera's
/// hits ([`light_rays`]).
pub fn scene_rays(scenes: &[Scene], seed: u64, n: u32, random: usize) -> Vec<Vec<Ray>> {
    let rays_of = |(k, scene): (usize, &Scene)| {
        let mut rays = Vec::new();
        for (el, az) in [(45.0, 34.0), (45.0, 215.0), (5.0, 71.0), (5.0, 290.0)] {
            rays.extend(camera_rays(scene, el, az, n));
        }
        rays.extend(random_rays(scene, seed + k as u64, random));
        rays.extend(light_rays(scene, &camera_rays(scene, 45.0, 34.0, n)));
        rays
    };
    scenes.iter().enumerate().map(rays_of).collect()
}

/// The shadow rays of the exact hits of `primary` traced from the light's side
/// (`Hit::shadow_query_from_light`, a light 58° above the horizon): rays from outside
/// the box over a negative `t` range ending at the lifted point, in an exterior set.
pub fn light_rays(scene: &Scene, primary: &[Ray]) -> Vec<Ray> {
    let hf = scene.hf();
    let light = [0.5, -0.3, 0.8];
    primary
        .iter()
        .filter_map(|q| {
            let hit = hfcast::dda::trace(&hf, Surface::Triangles, q).hit?;
            let m = q.origin().iter().fold(0f32, |m, v| m.max(v.abs()));
            hit.shadow_query_from_light(&hf, Surface::Triangles, light, m)
                .ok()
        })
        .collect()
}

/// `n` random rays in and around the field's box: origins above, inside (some under
/// the surface) and beside it; directions anywhere, upward, grazing (a few hundredths
/// off horizontal), axis-parallel, vertical; mostly `[0, ∞)`, some with a negative or
/// positive `t_min` and a finite `t_max`.
pub fn random_rays(scene: &Scene, seed: u64, n: usize) -> Vec<Ray> {
    let hf = scene.hf();
    let (xm, ym) = (f64::from(scene.w - 1), f64::from(scene.h - 1));
    let (zlo, zhi) = (f64::from(hf.min_height()), f64::from(hf.max_height()));
    let zr = (zhi - zlo).max(1.0);
    let mut rng = rng(seed);
    (0..n)
        .map(|_| {
            let o = [
                rng.range(-0.1 * xm, 1.1 * xm),
                rng.range(-0.1 * ym, 1.1 * ym),
                rng.range(zlo - 0.2 * zr, zhi + 0.5 * zr),
            ];
            let az = rng.range(0.0, std::f64::consts::TAU);
            let d = match rng.next_u64() % 6 {
                // Anywhere, a third of them upward.
                0 | 1 => {
                    let dz = rng.range(-1.0, 0.5);
                    [az.cos(), az.sin(), dz]
                }
                // Grazing.
                2 => [az.cos(), az.sin(), rng.range(-0.03, 0.01)],
                // Along x or y.
                3 => {
                    let s = if rng.next_u64().is_multiple_of(2) {
                        1.0
                    } else {
                        -1.0
                    };
                    let dz = rng.range(-0.3, 0.05);
                    if rng.next_u64().is_multiple_of(2) {
                        [s, 0.0, dz]
                    } else {
                        [0.0, s, dz]
                    }
                }
                // Vertical (down, sometimes up).
                4 => [
                    0.0,
                    0.0,
                    if rng.next_u64().is_multiple_of(8) {
                        1.0
                    } else {
                        -1.0
                    },
                ],
                // Steep.
                _ => [az.cos(), az.sin(), -rng.range(1.0, 8.0)],
            };
            let (t_min, t_max) = match rng.next_u64() % 8 {
                0 => (rng.range(-5.0, 5.0), f64::INFINITY),
                1 => {
                    let a = rng.range(0.0, 10.0);
                    (a, a + rng.range(0.0, 0.5 * (xm + ym)))
                }
                _ => (0.0, f64::INFINITY),
            };
            ray(o, d, t_min, t_max)
        })
        .collect()
}

// ---------------------------------------------------------------------------------
// GPU
// ---------------------------------------------------------------------------------

/// The device and queue of the Vulkan adapter.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter is (lavapipe: "llvmpipe", type Cpu).
    pub info: wgpu::AdapterInfo,
}

impl Gpu {
    /// Opens the first Vulkan adapter, a CPU one (lavapipe) included. Panics with a
    /// message naming the package to install when there is none: the tests must not
    /// pass without running the shaders.
    pub fn new() -> Gpu {
        quiet_runtime_dir();
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::default(),
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .unwrap_or_else(|e| {
            panic!(
                "no Vulkan adapter ({e}): the WGSL tests run the shaders through wgpu on \
                 Vulkan; install a driver, e.g. lavapipe: apt-get install mesa-vulkan-drivers \
                 libvulkan1"
            )
        });
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("hfcast-shadertest"),
            required_limits: adapter.limits(),
            // 64-bit floats where the adapter has them: the safety-distance bake.
            required_features: adapter.features() & wgpu::Features::SHADER_F64,
            ..wgpu::DeviceDescriptor::default()
        }))
        .unwrap_or_else(|e| panic!("cannot open {}: {e}", info.name));
        Gpu {
            device,
            queue,
            info,
        }
    }

    /// The adapter, for the report: name, type, backend and driver.
    pub fn describe(&self) -> String {
        let i = &self.info;
        format!(
            "adapter: {} ({:?}, {:?}, driver {} {})",
            i.name, i.device_type, i.backend, i.driver, i.driver_info
        )
    }

    fn texture(
        &self,
        w: u32,
        h: u32,
        format: wgpu::TextureFormat,
        data: &[u8],
    ) -> wgpu::TextureView {
        let tex = self.device.create_texture_with_data(
            &self.queue,
            &wgpu::TextureDescriptor {
                label: None,
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            data,
        );
        tex.create_view(&wgpu::TextureViewDescriptor::default())
    }

    fn buffer(&self, usage: wgpu::BufferUsages, data: &[u8]) -> wgpu::Buffer {
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: data,
                usage,
            })
    }

    /// A uniform buffer holding `data`.
    pub fn uniform(&self, data: &[u8]) -> wgpu::Buffer {
        self.buffer(wgpu::BufferUsages::UNIFORM, data)
    }

    /// An R32Float `w × h` texture of `heights` (what `hf_heights` binds).
    pub fn heights_texture(&self, w: u32, h: u32, heights: &[f32]) -> wgpu::TextureView {
        self.texture(w, h, wgpu::TextureFormat::R32Float, &f32_bytes(heights))
    }

    /// A storage buffer holding `words`, readable back ([`Gpu::read_u32`]).
    pub fn storage(&self, words: &[u32]) -> wgpu::Buffer {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        self.buffer(usage, &u32_bytes(words))
    }

    /// The first `n` words of `buffer` (made with `COPY_SRC`), read back.
    pub fn read_u32(&self, buffer: &wgpu::Buffer, n: usize) -> Vec<u32> {
        let enc = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        self.submit_and_read(enc, buffer, 4 * n as u64)
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }

    /// Runs `pipeline` on `rays`, 64 to a workgroup: group 0 is `group0`, group 1 (of
    /// `layout1`) the rays at binding 0 (each origin, t_min, direction, t_max as eight
    /// floats) and the output at binding 1, sixteen words a ray (as [`GpuHit::from_words`]
    /// reads them), read back.
    pub fn dispatch_rays(
        &self,
        pipeline: &wgpu::ComputePipeline,
        layout1: &wgpu::BindGroupLayout,
        group0: &wgpu::BindGroup,
        rays: &[Query<f32>],
    ) -> Vec<[u32; 16]> {
        let ray_words: Vec<u32> = rays
            .iter()
            .flat_map(|r| {
                let (o, d) = (r.origin(), r.dir());
                [o[0], o[1], o[2], r.t_min(), d[0], d[1], d[2], r.t_max()].map(f32::to_bits)
            })
            .collect();
        let ray_buf = self.storage(&ray_words);
        let out = self.storage(&vec![0; 16 * rays.len()]);
        let group1 = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: layout1,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: ray_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: out.as_entire_binding(),
                },
            ],
        });
        let mut enc = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group0, &[]);
            pass.set_bind_group(1, &group1, &[]);
            pass.dispatch_workgroups((rays.len() as u32).div_ceil(64), 1, 1);
        }
        self.submit_and_read(enc, &out, 64 * rays.len() as u64)
            .chunks_exact(64)
            .map(|c| {
                std::array::from_fn(|k| {
                    u32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
                })
            })
            .collect()
    }

    /// Submits `enc` with a copy of the first `size` bytes of `buffer` (made with
    /// `COPY_SRC`) appended, waits for it, and returns those bytes.
    fn submit_and_read(
        &self,
        mut enc: wgpu::CommandEncoder,
        buffer: &wgpu::Buffer,
        size: u64,
    ) -> Vec<u8> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        staging.map_async(wgpu::MapMode::Read, .., |r| r.expect("map the results"));
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("wait for the GPU");
        let bytes = staging
            .get_mapped_range(..)
            .expect("mapped results")
            .to_vec();
        staging.unmap();
        bytes
    }
}

/// Points `XDG_RUNTIME_DIR` at a private 0700 directory when it is unset, which
/// silences lavapipe's warning.
fn quiet_runtime_dir() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("hfcast-shadertest-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_ok() {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700));
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

/// `v` as little-endian bytes (a buffer's contents).
pub fn f32_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// `v` as little-endian bytes (a buffer's contents).
pub fn u32_bytes(v: &[u32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A scene's textures and uniform buffers in the layout of `shaders/wgsl`.
pub struct SceneGpu {
    heights: wgpu::TextureView,
    heights_u16: Option<wgpu::TextureView>,
    field: wgpu::Buffer,
    pyramid: wgpu::TextureView,
    maxmip: wgpu::Buffer,
    safety_dir: wgpu::TextureView,
    safety_iso: wgpu::TextureView,
    cone: wgpu::TextureView,
    qdm: wgpu::TextureView,
    relaxed: Option<wgpu::TextureView>,
    cc_map: wgpu::TextureView,
    cc: wgpu::Buffer,
    radius: wgpu::TextureView,
    /// The walls' corners, RGBA32Float 3·[`WALLS`] × 1 (`hf_occluders`).
    occluders: wgpu::TextureView,
    /// Per [`MAP_SETS`] entry: its classes, its rays, whether over the walls, and its
    /// maps' textures (directional and cylinder–cone W × nH, isotropic W × H).
    subsets: Vec<(u8, Rays, bool, ClassTextures)>,
}

/// The textures of one class set's maps.
struct ClassTextures {
    safety_dir: wgpu::TextureView,
    safety_iso: wgpu::TextureView,
    cc_map: wgpu::TextureView,
}

impl SceneGpu {
    /// Uploads `scene` (the C renderer's texture formats and uniform values).
    pub fn new(gpu: &Gpu, s: &Scene) -> SceneGpu {
        use wgpu::TextureFormat as F;
        let hf = s.hf();
        let (w, h) = (s.w, s.h);
        // FieldParams: size, height_range, height_step (then padding to 32 bytes).
        let step = s.samples.as_ref().map_or(0.0, |(_, step)| *step);
        let mut field = u32_bytes(&[w, h]);
        field.extend(f32_bytes(&[hf.min_height(), hf.max_height(), step, 0.0]));
        field.resize(32, 0);
        // The pyramid buffer in rows of PYRAMID_TEX_WIDTH texels, the last row padded.
        let rows = s.pyramid.len().div_ceil(PYRAMID_TEX_WIDTH as usize);
        let mut padded = s.pyramid.clone();
        padded.resize(rows * PYRAMID_TEX_WIDTH as usize, 0.0);
        // MaxMipParams: levels (i32, padded to 16 bytes), then (width, height, offset, 0)
        // per level.
        let layout = Layout::new(w, h).expect("layout");
        let mut levels = vec![0i32; 4 + 4 * maxmip::MAX_LEVELS];
        levels[0] = layout.levels() as i32;
        for l in 0..layout.levels() {
            let [lw, lh] = layout.dims(l);
            let k = 4 + 4 * l as usize;
            levels[k] = lw as i32;
            levels[k + 1] = lh as i32;
            levels[k + 2] = layout.offset(l) as i32;
        }
        let levels: Vec<u8> = levels.iter().flat_map(|v| v.to_le_bytes()).collect();
        // CcParams: the cap.
        let cc = u32_bytes(&[u32::from(CC_CAP)]);
        SceneGpu {
            heights: gpu.texture(w, h, F::R32Float, &f32_bytes(&s.heights)),
            heights_u16: s.samples.as_ref().map(|(samples, _)| {
                let bytes: Vec<u8> = samples.iter().flat_map(|v| v.to_le_bytes()).collect();
                gpu.texture(w, h, F::R16Uint, &bytes)
            }),
            field: gpu.uniform(&field),
            pyramid: gpu.texture(
                PYRAMID_TEX_WIDTH,
                rows as u32,
                F::R32Float,
                &f32_bytes(&padded),
            ),
            maxmip: gpu.uniform(&levels),
            // A map holding n ray classes: W x nH texels, texel (i, n j + slot).
            subsets: s
                .subsets
                .iter()
                .map(|m| {
                    let n = RayClasses(m.classes).count();
                    let tex = ClassTextures {
                        safety_dir: gpu.texture(w, n * h, F::R8Uint, &m.safety_dir),
                        safety_iso: gpu.texture(w, h, F::R8Uint, &m.safety_iso),
                        cc_map: gpu.texture(w, n * h, F::Rg8Uint, &m.cc),
                    };
                    (m.classes, m.rays, m.occluded, tex)
                })
                .collect(),
            safety_dir: gpu.texture(w, 4 * h, F::R8Uint, &s.safety_dir),
            safety_iso: gpu.texture(w, h, F::R8Uint, &s.safety_iso),
            cone: gpu.texture(w - 1, h - 1, F::Rg32Float, &f32_bytes(&s.cone)),
            qdm: gpu.texture(w - 1, h - 1, F::Rgba32Float, &f32_bytes(&s.qdm)),
            relaxed: s
                .relaxed
                .as_ref()
                .map(|r| gpu.texture(w, h, F::R32Float, &f32_bytes(r))),
            cc_map: gpu.texture(w, 4 * h, F::Rg8Uint, &s.cc),
            cc: gpu.uniform(&cc),
            radius: gpu.texture(w, h, F::R8Uint, &s.radius),
            occluders: {
                let texels: Vec<f32> = (s.walls.iter())
                    .flat_map(|o| o.corners)
                    .flat_map(|[x, y, z]| [x, y, z, 0.0])
                    .collect();
                gpu.texture(3 * WALLS as u32, 1, F::Rgba32Float, &f32_bytes(&texels))
            },
        }
    }
}

impl SceneGpu {
    /// The directional and isotropic safety and the cylinder–cone textures of the maps
    /// holding `classes` for the rays `rays` (the whole maps for 15 and every ray).
    fn maps(
        &self,
        classes: u8,
        rays: Rays,
        occluded: bool,
    ) -> (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView) {
        if classes == 15 && rays.is_all() {
            return (&self.safety_dir, &self.safety_iso, &self.cc_map);
        }
        let (_, _, _, t) = self
            .subsets
            .iter()
            .find(|(c, r, o, _)| *c == classes && *r == rays && *o == occluded)
            .unwrap_or_else(|| panic!("no textures of the classes {classes:#06b} for {rays}"));
        (&t.safety_dir, &t.safety_iso, &t.cc_map)
    }
}

/// One ray's answer from the GPU, as `hf_hit` holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuHit {
    /// `Trace::hit.is_some()`.
    pub hit: bool,
    /// Trace flags or'ed with the hit's.
    pub flags: u32,
    /// Texture fetches.
    pub fetches: u32,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point.
    pub point: [f32; 3],
    /// Normal at the hit.
    pub normal: [f32; 3],
    /// `Trace::clearance`.
    pub clearance: f32,
    /// The hit's cell.
    pub cell: [u32; 2],
}

impl GpuHit {
    /// The hit of a test kernel's sixteen output words: has_hit, flags, fetches, (a
    /// kernel's own word), point, t, normal, clearance, cell.
    pub fn from_words(w: &[u32; 16]) -> GpuHit {
        let f = |k: usize| f32::from_bits(w[k]);
        GpuHit {
            hit: w[0] != 0,
            flags: w[1],
            fetches: w[2],
            t: f(7),
            point: [f(4), f(5), f(6)],
            normal: [f(8), f(9), f(10)],
            clearance: f(11),
            cell: [w[12], w[13]],
        }
    }
}

/// One ray and both answers, for a failure message: the CPU's and the GPU's hit (t,
/// point, normal, cell, flags, fetches, clearance) or miss.
pub fn describe(r: &Ray, cpu: &Trace<f32>, g: &GpuHit) -> String {
    let c = match cpu.hit {
        Some(h) => format!(
            "hit t {} point {:?} normal {:?} cell {:?} flags {} fetches {}",
            h.t,
            h.point.to_array(),
            h.normal.to_array(),
            h.cell,
            cpu.flags.0 | h.flags.0,
            cpu.fetches
        ),
        None => format!("miss flags {} fetches {}", cpu.flags.0, cpu.fetches),
    };
    let gs = if g.hit {
        format!(
            "hit t {} point {:?} normal {:?} cell {:?} flags {} fetches {}",
            g.t, g.point, g.normal, g.cell, g.flags, g.fetches
        )
    } else {
        format!("miss flags {} fetches {}", g.flags, g.fetches)
    };
    format!(
        "origin {:?} dir {:?} t [{}, {}]: cpu {c} clearance {}; gpu {gs} clearance {}",
        r.origin(),
        r.dir(),
        r.t_min(),
        r.t_max(),
        cpu.clearance,
        g.clearance
    )
}

/// The bind group layout entry of binding `b` of group 0 (`int_heights`: the heights
/// are a `texture_2d<u32>`).
fn layout_entry(b: u32, int_heights: bool) -> wgpu::BindGroupLayoutEntry {
    let float = wgpu::TextureSampleType::Float { filterable: false };
    let texture = |sample_type| wgpu::BindingType::Texture {
        sample_type,
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    };
    let ty = match b {
        binding::HEIGHTS if int_heights => texture(wgpu::TextureSampleType::Uint),
        binding::HEIGHTS
        | binding::PYRAMID
        | binding::CONE_MAP
        | binding::QDM_MAP
        | binding::RELAXED_MAP
        | binding::OCCLUDERS => texture(float),
        binding::SAFETY_MAP | binding::CC_MAP | binding::RADIUS_MAP => {
            texture(wgpu::TextureSampleType::Uint)
        }
        _ => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    };
    wgpu::BindGroupLayoutEntry {
        binding: b,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    }
}

/// The compute stage's layout entry of storage buffer `b`, `read_only` or not.
pub fn storage_entry(b: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: b,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A case's compiled pipeline and its bind group layouts.
pub struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout0: wgpu::BindGroupLayout,
    layout1: wgpu::BindGroupLayout,
}

impl Kernel {
    /// Compiles `case`'s source with the test entry point and its override values,
    /// panicking with wgpu's message when the module or the pipeline is refused.
    pub fn new(gpu: &Gpu, case: &Case) -> Kernel {
        let dev = &gpu.device;
        let src = case.source();
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(case.method.name()),
            source: wgpu::ShaderSource::Wgsl(src.as_str().into()),
        });
        let entries0: Vec<_> = case
            .bindings()
            .iter()
            .map(|&b| layout_entry(b, case.int_heights))
            .collect();
        let layout0 = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &entries0,
        });
        let layout1 = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[storage_entry(0, true), storage_entry(1, false)],
        });
        let pipeline_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout0), Some(&layout1)],
            immediate_size: 0,
        });
        let constants = case.constants(&src);
        let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(case.method.name()),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("test_main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                zero_initialize_workgroup_memory: true,
            },
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("{}: wgpu refused the shader or pipeline: {e}", case.label());
        }
        Kernel {
            pipeline,
            layout0,
            layout1,
        }
    }
}

/// Runs `kernel` (compiled for `case`) over `rays` on the scene `sg` and reads the
/// answers back.
pub fn run_kernel(
    gpu: &Gpu,
    kernel: &Kernel,
    sg: &SceneGpu,
    case: &Case,
    rays: &[Ray],
) -> Vec<GpuHit> {
    let dev = &gpu.device;
    let bindings = case.bindings();
    let params = gpu.uniform(&u32_bytes(&case.params));
    // WorldParams: offset (then padding to 16 bytes), scale (then padding).
    let t = case.world.unwrap_or_default();
    let [ox, oy] = t.origin();
    let [sx, sy] = t.spacing();
    let (oz, sz) = (t.height_offset(), t.height_scale());
    let world = [ox, oy, oz, 0.0, sx, sy, sz, 0.0].map(|v| v as f32);
    let world = gpu.uniform(&f32_bytes(&world));
    let (safety_dir, safety_iso, cc_map) = sg.maps(case.classes, case.rays, case.occluders);
    let resource = |b: u32| -> wgpu::BindingResource<'_> {
        match b {
            binding::HEIGHTS if case.int_heights => {
                wgpu::BindingResource::TextureView(sg.heights_u16.as_ref().expect("16-bit samples"))
            }
            binding::HEIGHTS => wgpu::BindingResource::TextureView(&sg.heights),
            binding::FIELD => sg.field.as_entire_binding(),
            binding::PARAMS => params.as_entire_binding(),
            binding::PYRAMID => wgpu::BindingResource::TextureView(&sg.pyramid),
            binding::MAXMIP => sg.maxmip.as_entire_binding(),
            binding::SAFETY_MAP => wgpu::BindingResource::TextureView(match case.variant {
                Variant::Directional => safety_dir,
                Variant::Isotropic => safety_iso,
            }),
            binding::CONE_MAP => wgpu::BindingResource::TextureView(&sg.cone),
            binding::QDM_MAP => wgpu::BindingResource::TextureView(&sg.qdm),
            binding::RELAXED_MAP => {
                wgpu::BindingResource::TextureView(sg.relaxed.as_ref().expect("relaxed bake"))
            }
            binding::CC_MAP => wgpu::BindingResource::TextureView(cc_map),
            binding::CC => sg.cc.as_entire_binding(),
            binding::RADIUS_MAP => wgpu::BindingResource::TextureView(&sg.radius),
            binding::WORLD => world.as_entire_binding(),
            binding::OCCLUDERS => wgpu::BindingResource::TextureView(&sg.occluders),
            other => panic!("no resource for binding {other}"),
        }
    };
    let group0 = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &kernel.layout0,
        entries: &bindings
            .iter()
            .map(|&b| wgpu::BindGroupEntry {
                binding: b,
                resource: resource(b),
            })
            .collect::<Vec<_>>(),
    });

    gpu.dispatch_rays(&kernel.pipeline, &kernel.layout1, &group0, rays)
        .iter()
        .map(GpuHit::from_words)
        .collect()
}

// ---------------------------------------------------------------------------------
// Six-field impostors (wgsl_impostor.rs, wgsl_impostor_render.rs)
// ---------------------------------------------------------------------------------

/// The Stanford bunny of `data/`, read as the CLI reads it.
pub fn bunny() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/mesh_stanford_bunny.obj"
    );
    let m = hfcast_tools::impostor::load_mesh(std::path::Path::new(path))
        .unwrap_or_else(|e| panic!("{e}"));
    (m.positions, m.triangles)
}

/// The six padded fields of `mesh` on `layout`, `side` × `side` each, stacked: face
/// k's rows follow the faces before it (the texture of `side × 6·side`).
pub fn impostor_capture(
    mesh: &hfcast::impostor::Mesh,
    layout: &hfcast::impostor::Layout,
    side: u32,
) -> Vec<f32> {
    let n = (side * side) as usize;
    let mut stacked = vec![0.0; 6 * n];
    for (face, h) in stacked.chunks_exact_mut(n).enumerate() {
        let map = layout.face_map(face, side).unwrap();
        hfcast::impostor::rasterize(mesh, &map, side, h, None).unwrap();
        hfcast::impostor::pad_silhouettes(h, side).unwrap();
    }
    stacked
}

/// The rows of `m` in f32.
pub fn mat4_rows(m: &hfcast::projective::Mat4) -> impl Iterator<Item = f32> + '_ {
    m.iter().flatten().map(|&v| v as f32)
}

/// The group-0 layout of impostor.wgsl seen by the `visibility` stages: the stacked
/// heights (binding 0), the field params (1), the field ranges (20), the
/// ImpostorParams (21) and, with `view_proj`, hf_view_proj (22).
pub fn impostor_layout0(
    dev: &wgpu::Device,
    visibility: wgpu::ShaderStages,
    view_proj: bool,
) -> wgpu::BindGroupLayout {
    let uniform = wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let heights = wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable: false },
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    };
    let mut entries = vec![(binding::HEIGHTS, heights)];
    let mut uniforms = vec![binding::FIELD, binding::FIELD_RANGES, binding::IMPOSTOR];
    if view_proj {
        uniforms.push(binding::VIEW_PROJ);
    }
    entries.extend(uniforms.into_iter().map(|b| (b, uniform)));
    let entries: Vec<_> = entries
        .into_iter()
        .map(|(binding, ty)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty,
            count: None,
        })
        .collect();
    dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &entries,
    })
}

/// The uniforms of impostor.wgsl for `imp` with fields of side `side`, as its header
/// asks: the field params (binding 1), the field ranges (binding 20) and the
/// ImpostorParams (binding 21), in that order.
pub fn impostor_uniforms(
    gpu: &Gpu,
    imp: &hfcast::impostor::Impostor,
    side: u32,
) -> [wgpu::Buffer; 3] {
    // FieldParams: size (the side of one field), height_range and height_step
    // unused, padded to 32 bytes.
    let mut field = u32_bytes(&[side, side]);
    field.resize(32, 0);
    let field = gpu.uniform(&field);
    let ranges: Vec<f32> = (0..6)
        .flat_map(|k| {
            let hf = imp.field(k);
            [hf.min_height(), hf.max_height(), 0.0, 0.0]
        })
        .collect();
    let ranges = gpu.uniform(&f32_bytes(&ranges));
    // ImpostorParams: the six maps, the six inverses, the cube.
    let l = imp.layout();
    let mut params: Vec<f32> = (0..6)
        .flat_map(|k| mat4_rows(imp.map(k).matrix()))
        .collect();
    params.extend((0..6).flat_map(|k| mat4_rows(imp.map(k).inverse())));
    params.extend(l.center().map(|v| v as f32));
    params.push(l.half() as f32);
    let params = gpu.uniform(&f32_bytes(&params));
    [field, ranges, params]
}
