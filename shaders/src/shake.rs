//! The tree shaker: splits GLSL or WGSL source into top-level items (functions,
//! prototypes, structs, constants, uniforms, bindings, overrides) by brace matching,
//! and keeps the items reachable from the entry points by identifier references.

use std::collections::{BTreeMap, BTreeSet};

/// A top-level declaration.
#[derive(Clone, Debug)]
pub(crate) struct Item {
    /// The name it declares.
    pub name: String,
    /// What it declares.
    pub kind: Kind,
    /// Its text, comments above it excluded, ending in a newline.
    pub text: String,
    /// The identifiers its code mentions (member names after `.` excluded).
    pub refs: BTreeSet<String>,
}

/// What an [`Item`] declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A function definition.
    Function,
    /// A function prototype (GLSL).
    Prototype,
    /// A struct.
    Struct,
    /// A constant.
    Const,
    /// A uniform, texture binding or override: what the caller must provide.
    Input,
    /// A module-scope variable of the shader's own (WGSL `var<private>`, a GLSL global
    /// that is not a uniform).
    Global,
}

/// A piece of a file.
#[derive(Clone, Debug)]
pub(crate) enum Seg {
    /// A blank line.
    Blank,
    /// Consecutive comment lines.
    Comment(String),
    /// A declaration.
    Item(Item),
}

/// The code of a line: without its `//` comment.
fn code(line: &str) -> &str {
    line.find("//").map_or(line, |k| &line[..k])
}

/// The identifiers of `text` (comments stripped), except member names after `.`.
pub(crate) fn identifiers(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        for (start, word, _) in tokens(code(line)) {
            let prev = code(line)[..start].trim_end().chars().last();
            if prev != Some('.') {
                out.insert(word.to_string());
            }
        }
    }
    out
}

/// `(start, identifier, end)` of each identifier of `s` (numbers are skipped).
fn tokens(s: &str) -> Vec<(usize, &str, usize)> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let c = b[k];
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = k;
            while k < b.len() && (b[k].is_ascii_alphanumeric() || b[k] == b'_') {
                k += 1;
            }
            out.push((start, &s[start..k], k));
        } else if c.is_ascii_digit() {
            // A number, with its suffix (1u, 0x7F800000u, 1e-3).
            while k < b.len() && (b[k].is_ascii_alphanumeric() || b[k] == b'_' || b[k] == b'.') {
                k += 1;
            }
        } else {
            k += 1;
        }
    }
    out
}

/// `text` with every identifier in `names` replaced by its value (comments too, so
/// that they keep naming the renamed function).
pub(crate) fn rename(text: &str, names: &BTreeMap<String, String>) -> String {
    let mut out = String::with_capacity(text.len() + 64);
    let mut last = 0;
    for (start, word, end) in tokens(text) {
        if let Some(new) = names.get(word) {
            let prev = text[..start].trim_end().chars().last();
            if prev != Some('.') {
                out.push_str(&text[last..start]);
                out.push_str(new);
                last = end;
            }
        }
    }
    out.push_str(&text[last..]);
    out
}

/// The declared name and kind of an item's code.
fn declared(text: &str) -> Result<(String, Kind), String> {
    // The code with attributes (`@group(0)`, `@binding(1)`, `@must_use`) removed.
    let mut head = String::new();
    for line in text.lines() {
        head.push_str(code(line));
        head.push(' ');
    }
    while let Some(at) = head.find('@') {
        let rest = &head[at + 1..];
        let word_end = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        let mut end = at + 1 + word_end;
        if head[end..].trim_start().starts_with('(') {
            end = head[end..].find(')').map_or(head.len(), |k| end + k + 1);
        }
        head.replace_range(at..end, " ");
    }
    let stop = head
        .find(['{', ';', '=', '(', '[', ':'])
        .ok_or_else(|| format!("cannot read the declaration {text:?}"))?;
    let words: Vec<&str> = tokens(&head[..stop]).iter().map(|t| t.1).collect();
    let name = words
        .last()
        .ok_or_else(|| format!("no name in {text:?}"))?
        .to_string();
    let first = words[0];
    let kind = match first {
        "struct" | "alias" => Kind::Struct,
        "const" => Kind::Const,
        "var" if head.trim_start().starts_with("var<private>") => Kind::Global,
        "uniform" | "override" | "var" => Kind::Input,
        // `type name;` or `type name = value;`: a GLSL global.
        _ if words.len() == 2 && matches!(head.as_bytes()[stop], b';' | b'=') => Kind::Global,
        _ if head.as_bytes()[stop] == b'(' => {
            let after = head[stop..].trim_end();
            if after.ends_with(';') && !after.contains('{') {
                Kind::Prototype
            } else {
                Kind::Function
            }
        }
        _ => return Err(format!("unknown declaration {text:?}")),
    };
    Ok((name, kind))
}

/// Splits one file into blank lines, comment blocks and items.
pub(crate) fn parse(text: &str, file: &str) -> Result<Vec<Seg>, String> {
    let mut segs = Vec::new();
    let mut lines = text.lines().enumerate().peekable();
    while let Some((n, line)) = lines.next() {
        let t = line.trim();
        if t.is_empty() {
            segs.push(Seg::Blank);
            continue;
        }
        if t.starts_with("//") {
            let mut c = format!("{line}\n");
            while let Some((_, l)) = lines.peek() {
                if !l.trim_start().starts_with("//") {
                    break;
                }
                c.push_str(l);
                c.push('\n');
                lines.next();
            }
            segs.push(Seg::Comment(c));
            continue;
        }
        // An item: up to a `;` or a closing brace at depth 0.
        let mut item = String::new();
        let mut depth = 0i32;
        let mut cur = (n, line);
        loop {
            item.push_str(cur.1);
            item.push('\n');
            let mut closed = false;
            for ch in code(cur.1).chars() {
                match ch {
                    '{' | '(' | '[' => depth += 1,
                    '}' | ')' | ']' => {
                        depth -= 1;
                        closed |= ch == '}' && depth == 0;
                    }
                    _ => {}
                }
            }
            let tail = code(cur.1).trim_end();
            if depth == 0 && (closed || tail.ends_with(';')) {
                break;
            }
            cur = lines
                .next()
                .ok_or_else(|| format!("{file}:{}: unterminated declaration", n + 1))?;
        }
        let (name, kind) = declared(&item).map_err(|e| format!("{file}:{}: {e}", n + 1))?;
        let refs = identifiers(&item);
        segs.push(Seg::Item(Item {
            name,
            kind,
            text: item,
            refs,
        }));
    }
    Ok(segs)
}

/// Every item of `files` reachable from `roots`: a set of `(file, segment)` indices.
pub(crate) fn reachable(files: &[Vec<Seg>], roots: &[&str]) -> BTreeSet<(usize, usize)> {
    let mut by_name: BTreeMap<&str, Vec<(usize, usize)>> = BTreeMap::new();
    for (f, segs) in files.iter().enumerate() {
        for (k, s) in segs.iter().enumerate() {
            if let Seg::Item(it) = s {
                by_name.entry(it.name.as_str()).or_default().push((f, k));
            }
        }
    }
    let mut keep = BTreeSet::new();
    let mut todo: Vec<&str> = roots.to_vec();
    let mut seen: BTreeSet<&str> = BTreeSet::new();
    while let Some(name) = todo.pop() {
        if !seen.insert(name) {
            continue;
        }
        for &(f, k) in by_name.get(name).into_iter().flatten() {
            keep.insert((f, k));
            if let Seg::Item(it) = &files[f][k] {
                todo.extend(it.refs.iter().map(String::as_str));
            }
        }
    }
    keep
}

/// The text of `files` keeping only the items `emit` gives text for (`None`: drop).
/// A comment block is kept when an item after it in its paragraph (up to the next
/// comment block) is; a file's free-standing comments (a comment paragraph) are kept
/// when any of its items is. `header(f)` comes before file `f`'s first kept line.
pub(crate) fn emit(
    files: &[Vec<Seg>],
    mut item_text: impl FnMut(usize, usize, &Item) -> Option<String>,
    header: impl Fn(usize) -> String,
) -> String {
    let mut out = String::new();
    for (f, segs) in files.iter().enumerate() {
        let texts: Vec<Option<String>> = segs
            .iter()
            .enumerate()
            .map(|(k, s)| match s {
                Seg::Item(it) => item_text(f, k, it),
                _ => None,
            })
            .collect();
        if texts.iter().all(Option::is_none) {
            continue;
        }
        if !out.is_empty() && !out.ends_with("\n\n") {
            out.push('\n');
        }
        out.push_str(&header(f));
        let mut pending_blank = false;
        let push = |out: &mut String, text: &str, pending_blank: &mut bool| {
            if *pending_blank && !out.ends_with("\n\n") && !out.is_empty() {
                out.push('\n');
            }
            *pending_blank = false;
            out.push_str(text);
        };
        for (k, s) in segs.iter().enumerate() {
            match s {
                Seg::Blank => pending_blank = true,
                Seg::Item(_) => {
                    if let Some(t) = &texts[k] {
                        push(&mut out, t, &mut pending_blank);
                    }
                }
                Seg::Comment(c) => {
                    // The items this comment speaks for: up to the next blank or comment.
                    let mut any_item = false;
                    let mut kept = false;
                    for (j, s2) in segs.iter().enumerate().skip(k + 1) {
                        match s2 {
                            Seg::Item(_) => {
                                any_item = true;
                                kept |= texts[j].is_some();
                            }
                            Seg::Comment(_) | Seg::Blank => break,
                        }
                    }
                    // A paragraph of comments alone describes the file: it stays.
                    if kept || !any_item {
                        push(&mut out, c, &mut pending_blank);
                    }
                }
            }
        }
        if !out.ends_with('\n') {
            out.push('\n');
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glsl_and_wgsl_declarations_are_named() {
        let src = "\
uniform ivec2 hf_level_dims[HF_MAX_LEVELS];
const float REAL_EPSILON = 1.1920929e-07;
struct Span {
    float t0;
};
int cone_march_step(uvec2 cell, vec3 p,
                    out uint fetches);
float real_min(float a, float b) { return b < a ? b : a; }
@group(0) @binding(1) var<uniform> hf_field: FieldParams;
override hf_surface: u32 = 0u;
const HF_X: u32 = 0u;
var<private> hf_slot: u32 = 0u;
uint hf_slot_glsl = 0u;
fn f(a: vec3<f32>) -> f32 {
    return a.x + g(a);
}
";
        let segs = parse(src, "t").unwrap();
        let named: Vec<(String, Kind)> = segs
            .iter()
            .filter_map(|s| match s {
                Seg::Item(it) => Some((it.name.clone(), it.kind)),
                _ => None,
            })
            .collect();
        let want = [
            ("hf_level_dims", Kind::Input),
            ("REAL_EPSILON", Kind::Const),
            ("Span", Kind::Struct),
            ("cone_march_step", Kind::Prototype),
            ("real_min", Kind::Function),
            ("hf_field", Kind::Input),
            ("hf_surface", Kind::Input),
            ("HF_X", Kind::Const),
            ("hf_slot", Kind::Global),
            ("hf_slot_glsl", Kind::Global),
            ("f", Kind::Function),
        ];
        assert_eq!(named.len(), want.len());
        for ((n, k), (wn, wk)) in named.iter().zip(want) {
            assert_eq!((n.as_str(), *k), (wn, wk));
        }
        let Seg::Item(f) = &segs[10] else { panic!() };
        assert!(f.refs.contains("g") && !f.refs.contains("x"));
    }

    #[test]
    fn rename_skips_members_and_other_words() {
        let names = BTreeMap::from([("cone_march".to_string(), "cone_march_qdm".to_string())]);
        assert_eq!(
            rename(
                "x = cone_march(q); y = s.cone_march; cone_marcher();",
                &names
            ),
            "x = cone_march_qdm(q); y = s.cone_march; cone_marcher();"
        );
    }
}
