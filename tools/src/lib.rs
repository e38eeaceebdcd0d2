//! # hfcast-tools — the std side of hfcast
//!
//! The library behind the `hfcast` command-line tool, shared with its tests and later
//! report tools: loading the real height maps ([`maps`]), a pinhole camera and a
//! shaded, shadowed renderer ([`render`]), the traversal benchmark ([`bench`](mod@bench)), the
//! error-against-time report ([`report`]), the method table ([`MethodSpec`],
//! [`parse_method`]), baking and tracing with any method and the text format of
//! `hfcast trace` ([`trace`]), and the method choice of `hfcast advise` ([`advise`]).

use hfcast::march::MarchOptions;
use hfcast::relaxed::Steps as RelaxedSteps;
use hfcast::scene::MethodKind;
use hfcast::{Method, SearchSteps, Surface};
use std::sync::Mutex;

pub mod advise;
pub mod bench;
pub mod maps;
pub mod render;
pub mod report;
pub mod trace;

/// A marching method as the command line names it: a bake-free method of the core or
/// a baked one, with its march parameters. The one method table of `trace`, `render`,
/// `bench` and `advise` ([`parse_method`] reads it, [`MethodSpec::name`] writes it);
/// [`trace::Tracer`] bakes and traces it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodSpec {
    /// A bake-free method: `exact`, `linear-binary:N:M`, `secant:N`.
    Plain(Method),
    /// Maximum mipmaps, exact (`maxmip`).
    MaxMip,
    /// Safety distances, exact (`safety`); the layout follows the scene's bake plan.
    Safety,
    /// Cylinder–cone safety shapes with the exact slope, exact (`cc`).
    Cc,
    /// Safety radii, exact (`radius`).
    Radius,
    /// Conservative cone step mapping, at most `N` iterations (`cone:N`).
    Cone(u32),
    /// Quadratic displacement maps, at most `N` iterations (`qdm:N`).
    Qdm(u32),
    /// Relaxed cone stepping, then bisection (`relaxed:CONE:BINARY`); approximate.
    Relaxed(RelaxedSteps),
}

/// The march parameters of each method kind (the registry's, `MethodInfo::steps`):
/// `(names, default values)`; a method is written `kind` (the defaults) or
/// `kind:v1[:v2]` with every value given.
fn parameters(kind: MethodKind) -> (Vec<&'static str>, Vec<u32>) {
    let steps = kind.info().steps;
    (
        steps.iter().map(|p| p.name).collect(),
        steps.iter().map(|p| p.default).collect(),
    )
}

/// Help text of the method names, for usage messages.
pub const METHOD_NAMES: &str = "exact | linear-binary[:N:M] | secant[:N] | maxmip | safety | \
                                cc | radius | cone[:CAP] | qdm[:CAP] | relaxed[:N:M]";

impl MethodSpec {
    /// The exact methods, in the order `advise` lists them.
    pub const EXACT: [MethodSpec; 5] = [
        MethodSpec::Plain(Method::Exact),
        MethodSpec::MaxMip,
        MethodSpec::Safety,
        MethodSpec::Cc,
        MethodSpec::Radius,
    ];

    /// The core's number for the method (the scene description and the C API).
    pub fn kind(self) -> MethodKind {
        match self {
            MethodSpec::Plain(Method::Exact) => MethodKind::Exact,
            MethodSpec::Plain(Method::LinearBinary(_)) => MethodKind::LinearBinary,
            MethodSpec::Plain(Method::LinearSecant(_)) => MethodKind::LinearSecant,
            MethodSpec::MaxMip => MethodKind::MaxMip,
            MethodSpec::Safety => MethodKind::Safety,
            MethodSpec::Cc => MethodKind::Cc,
            MethodSpec::Radius => MethodKind::Radius,
            MethodSpec::Cone(_) => MethodKind::Cone,
            MethodSpec::Qdm(_) => MethodKind::Qdm,
            MethodSpec::Relaxed(_) => MethodKind::Relaxed,
        }
    }

    /// The march parameters, in [`parameters`] order.
    fn values(self) -> Vec<u32> {
        match self {
            MethodSpec::Plain(Method::LinearBinary(s)) => vec![s.linear, s.binary],
            MethodSpec::Plain(Method::LinearSecant(n))
            | MethodSpec::Cone(n)
            | MethodSpec::Qdm(n) => vec![n],
            MethodSpec::Relaxed(s) => vec![s.cone, s.binary],
            _ => Vec::new(),
        }
    }

    /// The core's march options of the method on `surface`: its parameters as the step
    /// budgets (the registry's order, `MethodInfo::steps`: first `steps`, then `binary_steps`).
    pub fn march_options(self, surface: Surface) -> MarchOptions {
        let mut o = MarchOptions::on(surface);
        let v = self.values();
        if let Some(&n) = v.first() {
            o.steps = n;
        }
        if let Some(&n) = v.get(1) {
            o.binary_steps = n;
        }
        o
    }

    /// The method of `kind` with march parameters `v` (as many as [`parameters`] names).
    fn of(kind: MethodKind, v: &[u32]) -> MethodSpec {
        match kind {
            MethodKind::Exact => MethodSpec::Plain(Method::Exact),
            MethodKind::LinearBinary => MethodSpec::Plain(Method::LinearBinary(SearchSteps {
                linear: v[0],
                binary: v[1],
            })),
            MethodKind::LinearSecant => MethodSpec::Plain(Method::LinearSecant(v[0])),
            MethodKind::MaxMip => MethodSpec::MaxMip,
            MethodKind::Safety => MethodSpec::Safety,
            MethodKind::Cc => MethodSpec::Cc,
            MethodKind::Radius => MethodSpec::Radius,
            MethodKind::Cone => MethodSpec::Cone(v[0]),
            MethodKind::Qdm => MethodSpec::Qdm(v[0]),
            MethodKind::Relaxed => MethodSpec::Relaxed(RelaxedSteps {
                cone: v[0],
                binary: v[1],
            }),
        }
    }

    /// `true` for the methods that answer the exact traversal's hit (within rounding).
    pub fn is_exact(self) -> bool {
        MethodSpec::EXACT.contains(&self)
    }

    /// Whether the method traces `surface` (the registry's `MethodInfo::surfaces`).
    pub fn supports(self, surface: Surface) -> bool {
        self.kind().info().surfaces.contains(&surface)
    }

    /// The name [`parse_method`] reads back (`secant:N` for the linear-secant search).
    pub fn name(self) -> String {
        let kind = match self.kind() {
            MethodKind::LinearSecant => "secant",
            k => k.name(),
        };
        self.values()
            .iter()
            .fold(kind.to_string(), |s, v| format!("{s}:{v}"))
    }
}

/// Parses a method name: one of [`METHOD_NAMES`] (`linear-secant` is read as
/// `secant`); a method with march parameters takes all of them or none (defaults:
/// `linear-binary:64:8`, `secant:64`, `cone:64`, `qdm:64`, `relaxed:64:8`).
pub fn parse_method(name: &str) -> Result<MethodSpec, String> {
    let mut parts = name.split(':');
    let word = parts.next().unwrap_or("");
    let word = if word == "secant" {
        "linear-secant"
    } else {
        word
    };
    let kind = MethodKind::ALL
        .into_iter()
        .find(|k| k.name() == word)
        .ok_or_else(|| format!("unknown method {name:?} ({METHOD_NAMES})"))?;
    let (what, defaults) = parameters(kind);
    let given: Vec<&str> = parts.collect();
    if !given.is_empty() && given.len() != what.len() {
        return Err(format!(
            "method {name:?}: want {} value(s) ({}), got {}",
            what.len(),
            what.join(", "),
            given.len()
        ));
    }
    let values = given
        .iter()
        .zip(what)
        .map(|(s, w)| {
            s.parse()
                .map_err(|_| format!("method {name:?}: bad {w} {s:?}"))
        })
        .collect::<Result<Vec<u32>, String>>()?;
    Ok(MethodSpec::of(
        kind,
        if given.is_empty() { &defaults } else { &values },
    ))
}

/// The machine's available parallelism (1 when unknown).
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Runs `f(first_index, chunk)` over `data` cut into chunks of `chunk` elements, on
/// `threads` scoped threads that take chunks in order as they become free (so uneven
/// work balances). Returns when every chunk is done.
pub fn par_chunks<T: Send>(
    data: &mut [T],
    chunk: usize,
    threads: usize,
    f: impl Fn(usize, &mut [T]) + Sync,
) {
    let chunk = chunk.max(1);
    let next = Mutex::new(data.chunks_mut(chunk).enumerate());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let item = next.lock().expect("a worker panicked").next();
                let Some((k, c)) = item else { break };
                f(k * chunk, c);
            });
        }
    });
}

/// A small deterministic random generator ([`hfcast::rng::SplitMix`] with the seed as
/// its state), enough for test and benchmark rays; no dependency.
#[derive(Clone, Debug)]
pub struct Rng(hfcast::rng::SplitMix);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(hfcast::rng::SplitMix::from_state(seed))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0.unit()
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0.range(lo, hi)
    }

    /// A direction uniform on the unit sphere.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn method_names_round_trip() {
        for name in [
            "exact",
            "linear-binary:32:8",
            "secant:16",
            "maxmip",
            "safety",
            "cc",
            "radius",
            "cone:16",
            "qdm:64",
            "relaxed:32:4",
        ] {
            assert_eq!(parse_method(name).unwrap().name(), name);
        }
        // Every kind of the core by its own name; defaults filled in.
        for kind in MethodKind::ALL {
            assert_eq!(parse_method(kind.name()).unwrap().kind(), kind);
        }
        assert_eq!(parse_method("secant").unwrap().name(), "secant:64");
        assert_eq!(parse_method("relaxed").unwrap().name(), "relaxed:64:8");
        for bad in [
            "",
            "exact:1",
            "secant:x",
            "linear-binary:4",
            "cone:1:2",
            "dda",
            "auto",
        ] {
            assert!(parse_method(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn surfaces_of_the_methods() {
        assert!(MethodSpec::EXACT
            .iter()
            .all(|m| m.supports(Surface::Triangles)));
        assert!(MethodSpec::MaxMip.supports(Surface::Bilinear));
        assert!(MethodSpec::Cc.supports(Surface::ViewLinear));
        assert!(!MethodSpec::Safety.supports(Surface::Bilinear));
        assert!(!MethodSpec::Cone(8).supports(Surface::ViewLinear));
        assert!(!MethodSpec::Cone(64).is_exact() && MethodSpec::Radius.is_exact());
    }

    #[test]
    fn par_chunks_visits_everything_once() {
        let mut v = vec![0usize; 1001];
        par_chunks(&mut v, 7, 3, |start, c| {
            for (k, x) in c.iter_mut().enumerate() {
                *x += start + k;
            }
        });
        assert!(v.iter().enumerate().all(|(k, &x)| k == x));
    }
}
