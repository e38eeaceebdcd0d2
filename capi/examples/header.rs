//! Prints the C header of the library built with the same cargo features:
//! `include/hfcast.h` (the full build's) without the declarations of the methods this
//! build leaves out.
//!
//! ```sh
//! cargo build --release -p hfcast-capi --no-default-features --features cone
//! cargo run --release -p hfcast-capi --no-default-features --features cone \
//!     --example header > hfcast.h
//! ```
//!
//! The full header wraps each method's declarations in `#if defined(HF_HAVE_<FEATURE>)`
//! (cbindgen's defines, from the registry's features: capi/tests/header.rs) and defines
//! every `HF_HAVE_*`. This
//! keeps the `#define`s of the features on, removes the others and every block whose
//! condition is then false, and leaves the rest of the text as it is, so a C file that
//! calls a function the build lacks fails to compile. With every feature on, the output
//! is the committed header itself.

/// The full build's header.
const FULL: &str = include_str!("../../include/hfcast.h");

#[path = "../src/features.rs"]
pub mod features;

/// The `HF_HAVE_*` macros of the methods this build has (the capi crate's features).
pub fn this_build() -> Vec<&'static str> {
    let on = hfcore::scene::FEATURES
        .iter()
        .filter(|f| features::feature_on(f.name) == Some(true));
    on.map(|f| f.have_macro).collect()
}

/// A `#if` condition over `HF_HAVE_*` macros, as cbindgen writes them: `defined(X)`,
/// `!`, `&&`, `||` and parentheses. `None` when it names anything else.
fn eval(cond: &str, on: &[&str]) -> Option<bool> {
    let tokens: Vec<String> = {
        let mut t = Vec::new();
        let mut rest = cond.trim();
        while !rest.is_empty() {
            let tok = ["&&", "||", "!", "(", ")"]
                .into_iter()
                .find(|p| rest.starts_with(p))
                .map(str::to_string)
                .or_else(|| {
                    let d = rest.strip_prefix("defined(")?;
                    let end = d.find(')')?;
                    Some(format!("defined({})", &d[..end]))
                })?;
            rest = rest[tok.len()..].trim_start();
            t.push(tok);
        }
        t
    };
    let mut pos = 0;
    let v = or(&tokens, &mut pos, on)?;
    (pos == tokens.len()).then_some(v)
}

/// `a || b || …`
fn or(t: &[String], pos: &mut usize, on: &[&str]) -> Option<bool> {
    let mut v = and(t, pos, on)?;
    while t.get(*pos).map(String::as_str) == Some("||") {
        *pos += 1;
        v |= and(t, pos, on)?;
    }
    Some(v)
}

/// `a && b && …`
fn and(t: &[String], pos: &mut usize, on: &[&str]) -> Option<bool> {
    let mut v = unary(t, pos, on)?;
    while t.get(*pos).map(String::as_str) == Some("&&") {
        *pos += 1;
        v &= unary(t, pos, on)?;
    }
    Some(v)
}

/// `!a`, `(a)` or `defined(HF_HAVE_X)`.
fn unary(t: &[String], pos: &mut usize, on: &[&str]) -> Option<bool> {
    let tok = t.get(*pos)?.as_str();
    *pos += 1;
    match tok {
        "!" => unary(t, pos, on).map(|v| !v),
        "(" => {
            let v = or(t, pos, on)?;
            (t.get(*pos).map(String::as_str) == Some(")")).then(|| *pos += 1)?;
            Some(v)
        }
        _ => {
            let name = tok.strip_prefix("defined(")?.strip_suffix(')')?;
            name.starts_with("HF_HAVE_").then(|| on.contains(&name))
        }
    }
}

/// `full` for a build with the macros `on`: the `#define HF_HAVE_*` lines of the
/// others and every `#if` block over `HF_HAVE_*` that is false removed (with the blank
/// line after it), everything else kept.
pub fn strip(full: &str, on: &[&str]) -> String {
    let mut out = String::new();
    // One entry per open #if: whether its body is dropped.
    let mut stack: Vec<bool> = Vec::new();
    let mut skip_blank = false;
    for line in full.split_inclusive('\n') {
        let text = line.trim_end();
        let dropping = stack.iter().any(|&d| d);
        if let Some(cond) = text.strip_prefix("#if ") {
            let drop = eval(cond, on) == Some(false);
            stack.push(drop);
            if dropping || drop {
                continue;
            }
        } else if text.starts_with("#ifdef") || text.starts_with("#ifndef") {
            stack.push(false);
            if dropping {
                continue;
            }
        } else if text.starts_with("#endif") {
            let drop = stack.pop().unwrap_or(false);
            if dropping {
                skip_blank = drop && !stack.iter().any(|&d| d);
                continue;
            }
        } else if dropping {
            continue;
        } else if let Some(name) = text
            .strip_prefix("#define ")
            .and_then(|d| d.split_whitespace().next())
        {
            if name.starts_with("HF_HAVE_") && !on.contains(&name) {
                continue;
            }
        }
        if skip_blank && text.is_empty() {
            skip_blank = false;
            continue;
        }
        skip_blank = false;
        out.push_str(line);
    }
    out
}

fn main() {
    print!("{}", strip(FULL, &this_build()));
}
