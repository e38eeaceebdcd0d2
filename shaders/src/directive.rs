//! The specialisation markers: a line-based directive language in comments, the same
//! in GLSL and WGSL (WGSL has no preprocessor).
//!
//! ```text
//! //#if a|b|c      keep the lines up to the matching //#else or //#endif when any
//!                  of the flags a, b, c is set
//! //#else          keep the lines up to //#endif when the //#if did not hold
//! //#endif
//! //#wgsl          WGSL-only lines up to //#end (kept here: these are WGSL files)
//! //#glsl          GLSL-only lines up to //#end, commented out (dropped here)
//! //#end
//! ```
//!
//! The language regions appear only in the WGSL files the GLSL ports are generated
//! from (`crate::translate`); the generated GLSL has none.
//!
//! Blocks nest. A marker line is a line whose first non-blank characters are `//#`;
//! marker lines never reach the output. Flag names are those of [`crate::FLAGS`];
//! an unknown name is an error, so a typo cannot silently drop code.

use crate::FLAGS;

/// One open `//#if` block.
struct Open {
    /// Whether the lines around the block are kept.
    outer: bool,
    /// Whether the condition held.
    cond: bool,
    /// Whether the `//#else` was seen.
    in_else: bool,
}

/// Keeps the lines of `text` that the markers select when exactly the flags for
/// which `set` is true are set, and drops the marker lines. `file` names the text in
/// errors.
pub(crate) fn evaluate(
    text: &str,
    file: &str,
    set: &dyn Fn(&str) -> bool,
) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    let mut stack: Vec<Open> = Vec::new();
    let mut glsl_only = false;
    let active = |stack: &[Open]| {
        stack
            .last()
            .is_none_or(|o| o.outer && (o.cond != o.in_else))
    };
    for (n, line) in text.lines().enumerate() {
        let at = || format!("{file}:{}", n + 1);
        let Some(directive) = line.trim_start().strip_prefix("//#") else {
            if active(&stack) && !glsl_only {
                out.push_str(line);
                out.push('\n');
            }
            continue;
        };
        let mut words = directive.split_whitespace();
        match (words.next(), words.next(), words.next()) {
            (Some("if"), Some(cond), None) => {
                let mut any = false;
                for name in cond.split('|') {
                    if !FLAGS.iter().any(|(f, _)| *f == name) {
                        return Err(format!("{}: unknown flag {name:?} in //#if", at()));
                    }
                    any |= set(name);
                }
                let outer = active(&stack);
                stack.push(Open {
                    outer,
                    cond: any,
                    in_else: false,
                });
            }
            (Some("else"), None, None) => match stack.last_mut() {
                Some(o) if !o.in_else => o.in_else = true,
                _ => return Err(format!("{}: //#else without //#if", at())),
            },
            (Some("wgsl"), None, None) => {}
            (Some("glsl"), None, None) => glsl_only = true,
            (Some("end"), None, None) => glsl_only = false,
            (Some("endif"), None, None) => {
                if stack.pop().is_none() {
                    return Err(format!("{}: //#endif without //#if", at()));
                }
            }
            _ => return Err(format!("{}: bad marker {line:?}", at())),
        }
    }
    if !stack.is_empty() {
        return Err(format!("{file}: //#if without //#endif"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::evaluate;

    const TEXT: &str = "a\n//#if triangles|bilinear\nb\n  //#if upward\nc\n  //#else\nd\n  //#endif\n//#else\ne\n//#endif\nf\n";

    fn run(flags: &[&str]) -> String {
        evaluate(TEXT, "t", &|f| flags.contains(&f)).unwrap()
    }

    #[test]
    fn blocks_nest_and_else_inverts() {
        assert_eq!(run(&["bilinear", "upward"]), "a\nb\nc\nf\n");
        assert_eq!(run(&["triangles"]), "a\nb\nd\nf\n");
        assert_eq!(run(&["upward"]), "a\ne\nf\n");
    }

    #[test]
    fn malformed_markers_are_errors() {
        let set = |_: &str| true;
        assert!(evaluate("//#if nonsense\n//#endif\n", "t", &set).is_err());
        assert!(evaluate("//#if upward\n", "t", &set).is_err());
        assert!(evaluate("//#endif\n", "t", &set).is_err());
        assert!(evaluate("//#if upward\n//#else\n//#else\n//#endif\n", "t", &set).is_err());
        assert!(evaluate("//#ifdef upward\n", "t", &set).is_err());
    }
}
