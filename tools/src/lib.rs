//! # hfcast-tools — the std side of hfcast
//!
//! The library behind the `hfcast` command-line tool, shared with its tests and later
//! report tools: loading the real height maps ([`maps`]), a pinhole camera and a
//! shaded, shadowed renderer ([`render`]), the traversal benchmark ([`bench`](mod@bench)), the
//! error-against-time report ([`report`]), the method table ([`MethodSpec`],
//! [`parse_method`]), baking and tracing with any method and the text format of
//! `hfcast trace` ([`trace`]), and the method choice of `hfcast advise` ([`advise`]).

use hfcast::march::MarchOptions;
use hfcast::scene::{Accuracy, MethodKind};
use hfcast::Surface;
use std::sync::Mutex;

pub mod advise;
pub mod bench;
pub mod impostor;
pub mod maps;
pub mod render;
pub mod report;
pub mod table1;
pub mod trace;

/// The most march parameters a method of the registry takes (`MethodInfo::steps`).
const MAX_STEPS: usize = 2;

/// A marching method as the command line names it: a method of the registry with its
/// march parameters. The one method table of `trace`, `render`, `bench` and `advise`
/// ([`parse_method`] reads it, [`MethodSpec::name`] writes it); [`trace::Tracer`]
/// bakes and traces it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MethodSpec {
    /// The method.
    kind: MethodKind,
    /// Its march parameters in the registry's order (`MethodInfo::steps`); the rest 0.
    steps: [u32; MAX_STEPS],
}

/// Help text of the method names, for usage messages: every method of the registry,
/// with its march parameters (`exact | linear-binary[:N:M] | secant[:N] | …`).
pub fn method_names() -> String {
    let names = MethodKind::ALL.into_iter().map(|k| {
        let letters = ["N", "M"].iter().take(k.info().steps.len());
        let steps: String = letters.map(|l| format!(":{l}")).collect();
        match steps.is_empty() {
            true => word(k).to_string(),
            false => format!("{}[{steps}]", word(k)),
        }
    });
    names.collect::<Vec<_>>().join(" | ")
}

/// The command line's word for `kind`: its registry name, `secant` for the
/// linear-secant search.
fn word(kind: MethodKind) -> &'static str {
    match kind {
        MethodKind::LinearSecant => "secant",
        k => k.name(),
    }
}

/// The help text of the methods and surfaces: every method of the registry with its
/// parameters' defaults, the exact ones, and the surfaces each traces (`hfcast help`).
pub fn methods_help() -> String {
    let names = method_names();
    let defaults: Vec<String> = MethodKind::ALL
        .into_iter()
        .filter(|k| !k.info().steps.is_empty())
        .map(|k| MethodSpec::of(k).name())
        .collect();
    let exact: Vec<String> = MethodSpec::exact().iter().map(|m| m.name()).collect();
    let mut by_surfaces: Vec<(&[Surface], Vec<&str>)> = Vec::new();
    for k in MethodKind::ALL {
        let s = k.info().surfaces;
        match by_surfaces.iter_mut().find(|(t, _)| *t == s) {
            Some((_, v)) => v.push(k.name()),
            None => by_surfaces.push((s, vec![k.name()])),
        }
    }
    let traces: Vec<String> = by_surfaces
        .iter()
        .map(|(s, ks)| {
            let s: Vec<&str> = s.iter().map(|s| s.name()).collect();
            format!("{}: {}", ks.join(" "), s.join(" "))
        })
        .collect();
    let surfaces: Vec<&str> = Surface::ALL.iter().map(|s| s.name()).collect();
    [
        (
            "methods (render: maxmip, trace and bench: exact, by default)",
            names,
        ),
        ("defaults", defaults.join(" ")),
        ("exact", exact.join(" ")),
        ("surfaces they trace", traces.join("; ")),
        ("surfaces", surfaces.join(" | ")),
    ]
    .map(|(label, text)| wrap(&format!("{label}: {text}"), 88, "         "))
    .concat()
}

/// `text` broken at spaces into lines of at most `width` columns, the later ones
/// starting with `indent`, each ending in a newline.
fn wrap(text: &str, width: usize, indent: &str) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split(' ') {
        if !line.trim().is_empty() && line.len() + 1 + word.len() > width {
            out += &line;
            out.push('\n');
            line = indent.to_string();
        } else if !line.is_empty() {
            line.push(' ');
        }
        line += word;
    }
    out + &line + "\n"
}

impl MethodSpec {
    /// The method of `kind` with its default march parameters.
    pub fn of(kind: MethodKind) -> MethodSpec {
        let mut steps = [0; MAX_STEPS];
        for (s, p) in steps.iter_mut().zip(kind.info().steps) {
            *s = p.default;
        }
        MethodSpec { kind, steps }
    }

    /// The exact methods (the registry's, in its order), as `advise` lists them.
    pub fn exact() -> Vec<MethodSpec> {
        let exact = MethodKind::ALL
            .into_iter()
            .filter(|k| k.info().accuracy == Accuracy::Exact);
        exact.map(MethodSpec::of).collect()
    }

    /// The core's number for the method (the scene description and the C API).
    pub fn kind(self) -> MethodKind {
        self.kind
    }

    /// The march parameters, in the registry's order.
    fn values(&self) -> &[u32] {
        &self.steps[..self.kind.info().steps.len()]
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

    /// `true` for the methods that answer the exact traversal's hit (within rounding).
    pub fn is_exact(self) -> bool {
        self.kind.info().accuracy == Accuracy::Exact
    }

    /// Whether the method traces `surface` (the registry's `MethodInfo::surfaces`).
    pub fn supports(self, surface: Surface) -> bool {
        self.kind.info().surfaces.contains(&surface)
    }

    /// The name [`parse_method`] reads back (`secant:N` for the linear-secant search).
    pub fn name(self) -> String {
        self.values()
            .iter()
            .fold(word(self.kind).to_string(), |s, v| format!("{s}:{v}"))
    }
}

/// Parses a method name: one of [`method_names`] (`linear-secant` is read as
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
        .ok_or_else(|| format!("unknown method {name:?} ({})", method_names()))?;
    let params = kind.info().steps;
    let given: Vec<&str> = parts.collect();
    if !given.is_empty() && given.len() != params.len() {
        let what: Vec<&str> = params.iter().map(|p| p.name).collect();
        return Err(format!(
            "method {name:?}: want {} value(s) ({}), got {}",
            what.len(),
            what.join(", "),
            given.len()
        ));
    }
    let mut method = MethodSpec::of(kind);
    for ((slot, s), p) in method.steps.iter_mut().zip(&given).zip(params) {
        *slot = s
            .parse()
            .map_err(|_| format!("method {name:?}: bad {} {s:?}", p.name))?;
    }
    Ok(method)
}

/// The CLI's `--rays` value (`all`, `exterior`, `angle:A`, `exterior,angle:A`): a set
/// with occluders is refused, since the CLI takes no occluder list (the library does:
/// `Spec::bake_rows_over`, `hf_bake_options.occluders`).
pub fn parse_ray_set(text: Option<String>) -> Result<hfcast::rayset::Rays, String> {
    let Some(text) = text else {
        return Ok(hfcast::rayset::Rays::ALL);
    };
    let rays: hfcast::rayset::Rays = text.parse().map_err(|e| format!("--rays: {e}"))?;
    if rays.occluders != 0 {
        return Err("--rays: occluders need their triangles, which the CLI does not take".into());
    }
    Ok(rays)
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
    fn the_cli_ray_set_takes_no_occluders() {
        let set = |t: &str| parse_ray_set(Some(t.to_string()));
        assert_eq!(parse_ray_set(None), Ok(hfcast::rayset::Rays::ALL));
        assert_eq!(set("exterior"), Ok(hfcast::rayset::Rays::EXTERIOR));
        assert!(set("exterior,occluders:abcdef").is_err());
        assert!(set("sideways").is_err());
    }

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
        let of = |name| parse_method(name).unwrap();
        assert!(MethodSpec::exact()
            .iter()
            .all(|m| m.supports(Surface::Triangles)));
        assert!(of("maxmip").supports(Surface::Bilinear));
        assert!(of("cc").supports(Surface::ViewLinear));
        assert!(!of("safety").supports(Surface::Bilinear));
        assert!(!of("cone:8").supports(Surface::ViewLinear));
        assert!(!of("cone:64").is_exact() && of("radius").is_exact());
        let exact: Vec<String> = MethodSpec::exact().iter().map(|m| m.name()).collect();
        assert_eq!(exact, ["exact", "maxmip", "safety", "cc", "radius"]);
    }

    #[test]
    fn the_help_names_every_method() {
        assert_eq!(
            method_names(),
            "exact | linear-binary[:N:M] | secant[:N] | maxmip | safety | cone[:N] | \
             relaxed[:N:M] | qdm[:N] | cc | radius | multires[:N]"
        );
    }

    #[test]
    fn every_method_fits_its_parameters() {
        for kind in MethodKind::ALL {
            assert!(kind.info().steps.len() <= MAX_STEPS, "{}", kind.name());
            let m = MethodSpec::of(kind);
            assert_eq!(parse_method(&m.name()).unwrap(), m);
        }
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
