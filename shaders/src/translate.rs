//! The GLSL ports generated from the WGSL ones: the marches are written once, in WGSL,
//! and [`glsl_from_wgsl`] writes each file's GLSL 3.30 mirror line by line (committed
//! in `glsl/`, checked for drift by `tests/validate.rs`; regenerate with
//! `HFCAST_BLESS=1 cargo test -p hfcast-shaders`). Files whose resources differ by
//! language (`field`, `field_int`, `world`, the `method_*` files) stay hand-written in
//! both.
//!
//! The WGSL these files use is a subset the translation keeps exact, statement by
//! statement:
//! - every `let`, `var` and `const` names its type (`let t: f32 = …`);
//! - pointer parameters (`p: ptr<function, T>`) become `inout T p`, `*p` and `&p` the
//!   plain name;
//! - `select(f, t, c)` becomes `((c) ? (t) : (f))`, `loop` `for (;;)`, `bitcast` and
//!   `textureLoad` their GLSL names, `override` a uniform with its default,
//!   `@binding` textures samplers;
//! - what has no such mirror (a uniform struct, a builtin GLSL 3.30 lacks) sits in a
//!   region of its own: lines between `//#wgsl` and `//#end` are WGSL only; lines
//!   between `//#glsl` and `//#end` are GLSL only, written as comments (`// code`) in
//!   the WGSL file. The specialisation markers (`//#if`, …) and comments pass through.
//!
//! Anything else the translation does not know (an untyped `let`, a uniform outside a
//! region) is an error naming the line, so a construct without an exact mirror cannot
//! slip through.

/// The files written in both languages: those whose resources differ by language (the
/// field's textures, the world uniforms, each method's parameters in its `method_*`
/// file) and the shared constants generated from Rust (`hfcast_shared`).
pub const BOTH_LANGUAGES: [&str; 4] = ["hfcast_shared", "field", "field_int", "world"];

/// Whether the GLSL of the file `stem` is generated from its WGSL: every file but the
/// [`BOTH_LANGUAGES`] ones and the `method_*` files. The GPU bakes are translated too:
/// their GLSL is a whole GLSL 4.30 compute shader (its `#version` line and `main` in
/// `//#glsl` regions).
pub fn is_translated(stem: &str) -> bool {
    !BOTH_LANGUAGES.contains(&stem) && !stem.starts_with("method_")
}

/// Whether `stem` is a GPU bake (`bake_*`: a compute shader of its own, not part of a
/// march; complete in either language, with its own bindings and entry point).
pub fn is_gpu_bake(stem: &str) -> bool {
    stem.starts_with("bake_")
}

/// Which language's region a line is in.
#[derive(Clone, Copy, PartialEq)]
enum Region {
    Both,
    WgslOnly,
    GlslOnly,
}

/// The GLSL of the WGSL file `text` (named `file` in errors and in the generated
/// header line).
pub fn glsl_from_wgsl(text: &str, file: &str) -> Result<String, String> {
    let mut out = format!(
        "// Generated from shaders/wgsl/{file}.wgsl by shaders/src/translate.rs: do not edit.\n\
         // Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate\n"
    );
    let mut region = Region::Both;
    let mut in_struct = false;
    let mut pending: Option<(usize, String, String)> = None;
    for (n, line) in text.lines().enumerate() {
        let at = |why: &str| format!("{file}.wgsl:{}: {why}: {line:?}", n + 1);
        let trimmed = line.trim_start();
        let indent = &line[..line.len() - trimmed.len()];
        match trimmed {
            "//#wgsl" | "//#glsl" if region != Region::Both => {
                return Err(at("a region inside a region"));
            }
            "//#wgsl" => {
                region = Region::WgslOnly;
                continue;
            }
            "//#glsl" => {
                region = Region::GlslOnly;
                continue;
            }
            "//#end" if region == Region::Both => return Err(at("//#end outside a region")),
            "//#end" => {
                region = Region::Both;
                continue;
            }
            _ => {}
        }
        match region {
            Region::WgslOnly => continue,
            Region::GlslOnly => {
                let code = trimmed
                    .strip_prefix("//")
                    .ok_or_else(|| at("a GLSL-only line is not a comment"))?;
                out.push_str(indent);
                out.push_str(code.strip_prefix(' ').unwrap_or(code));
                out.push('\n');
                continue;
            }
            Region::Both => {}
        }
        // Comments and markers pass through; code loses its trailing comment for the
        // rewrite and gets it back.
        let (code, comment) = match line.find("//") {
            Some(k) => (&line[..k], &line[k..]),
            None => (line, ""),
        };
        if code.trim().is_empty() && pending.is_none() {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        // A statement or signature may span lines: gather it up to balanced
        // parentheses (and a signature to its `{`), then translate it as one line.
        let code = match pending.take() {
            Some((start, mut joined, first_indent)) => {
                joined.push(' ');
                joined.push_str(code.trim());
                (start, joined, first_indent)
            }
            None => (n, code.trim().to_string(), indent.to_string()),
        };
        let is_fn = code.1.starts_with("fn ");
        if depth(&code.1) > 0 || (is_fn && !code.1.contains('{')) {
            pending = Some(code);
            continue;
        }
        let (start, code, indent) = code;
        let at = |why: &str| format!("{file}.wgsl:{}: {why}: {code:?}", start + 1);
        if is_fn {
            let head = function(&code).map_err(|e| at(&e))?;
            out.push_str(&indent);
            out.push_str(&head);
            if !comment.is_empty() {
                out.push(' ');
                out.push_str(comment);
            }
            out.push('\n');
            continue;
        }
        let code = format!("{indent}{code}");
        let code = if in_struct {
            if code.trim() == "}" {
                in_struct = false;
                format!("{indent}}};")
            } else {
                member(&code).ok_or_else(|| at("not a struct member"))?
            }
        } else if let Some(name) = code.trim().strip_prefix("struct ") {
            in_struct = true;
            format!("{indent}struct {}", name.trim())
        } else {
            statement(&code).map_err(|e| at(&e))?
        };
        out.push_str(code.trim_end());
        if !comment.is_empty() {
            out.push(' ');
            out.push_str(comment);
        }
        out.push('\n');
    }
    if region != Region::Both {
        return Err(format!("{file}.wgsl: a region without //#end"));
    }
    if pending.is_some() {
        return Err(format!(
            "{file}.wgsl: a statement or signature without its end"
        ));
    }
    Ok(out)
}

/// `fn name(params) -> ret { rest` as GLSL.
fn function(sig: &str) -> Result<String, String> {
    let sig = sig.strip_prefix("fn ").unwrap_or(sig);
    let open = sig.find('(').ok_or("a function without parameters")?;
    let close = matching(sig, open).ok_or("unbalanced parameters")?;
    let name = sig[..open].trim();
    let params = split_args(&sig[open + 1..close], true);
    let after = sig[close + 1..].trim_start();
    let (ret, body) = match after.strip_prefix("->") {
        Some(r) => {
            let brace = r.find('{').ok_or("no body")?;
            (ty(r[..brace].trim())?, &r[brace..])
        }
        None => ("void".to_string(), after),
    };
    let params = params
        .iter()
        .filter(|p| !p.trim().is_empty())
        .map(|p| {
            let (n, t) = p
                .split_once(':')
                .ok_or_else(|| format!("untyped parameter {p:?}"))?;
            let t = t.trim();
            Ok(
                match t
                    .strip_prefix("ptr<function,")
                    .and_then(|t| t.strip_suffix('>'))
                {
                    Some(inner) => format!("inout {} {}", ty(inner.trim())?, n.trim()),
                    None => format!("{} {}", ty(t)?, n.trim()),
                },
            )
        })
        .collect::<Result<Vec<_>, String>>()?;
    let body = if body.trim() == "{" {
        "{".to_string()
    } else {
        statement(body)?
    };
    Ok(format!(
        "{ret} {name}({}) {}",
        params.join(", "),
        body.trim()
    ))
}

/// A struct member `name: type,` as `type name;`.
fn member(code: &str) -> Option<String> {
    let indent = &code[..code.len() - code.trim_start().len()];
    let (name, t) = code.trim().trim_end_matches(',').split_once(':')?;
    Some(format!("{indent}{};", decl(name.trim(), t.trim()).ok()?))
}

/// `type name` in GLSL order (arrays as `T[N] name`).
fn decl(name: &str, t: &str) -> Result<String, String> {
    Ok(format!("{} {name}", ty(t)?))
}

/// A WGSL type as GLSL.
fn ty(t: &str) -> Result<String, String> {
    if let Some(inner) = t.strip_prefix("array<").and_then(|r| r.strip_suffix('>')) {
        let (elem, len) = inner
            .rsplit_once(',')
            .ok_or_else(|| format!("an array without a length: {t}"))?;
        return Ok(format!("{}[{}]", ty(elem.trim())?, len.trim()));
    }
    Ok(types(t))
}

/// Every WGSL type name in `code` replaced by its GLSL name.
fn types(code: &str) -> String {
    let mut s = code.to_string();
    for n in ["2", "3", "4"] {
        for (elem, prefix) in [
            ("f32", ""),
            ("f64", "d"),
            ("u32", "u"),
            ("i32", "i"),
            ("bool", "b"),
        ] {
            s = s.replace(&format!("vec{n}<{elem}>"), &format!("{prefix}vec{n}"));
        }
    }
    for (w, g) in [
        ("f32", "float"),
        ("f64", "double"),
        ("u32", "uint"),
        ("i32", "int"),
    ] {
        s = replace_word(&s, w, g);
    }
    s
}

/// One line of code (not a signature, not a struct member) as GLSL.
fn statement(code: &str) -> Result<String, String> {
    let indent = &code[..code.len() - code.trim_start().len()];
    let body = code.trim_start();
    if body.starts_with("@group") {
        return binding(body).map(|b| format!("{indent}{b}"));
    }
    if body.starts_with("var<") {
        return Err("a uniform or storage buffer outside a //#wgsl region".into());
    }
    let mut s = body.to_string();
    if s.starts_with("loop {") {
        s = s.replacen("loop {", "for (;;) {", 1);
    }
    s = declarations(&s)?;
    for (from, to) in [
        ("bitcast<u32>(", "floatBitsToUint("),
        ("bitcast<i32>(", "floatBitsToInt("),
        ("bitcast<f32>(", "uintBitsToFloat("),
    ] {
        s = s.replace(from, to);
    }
    s = arrays(&s)?;
    s = types(&s);
    s = calls(&s, "select", &|a| {
        (a.len() == 3).then(|| format!("(({}) ? ({}) : ({}))", a[2], a[1], a[0]))
    })?;
    s = calls(&s, "textureLoad", &|a| {
        (a.len() == 3).then(|| format!("texelFetch({}, {}, {})", a[0], int_coords(&a[1]), a[2]))
    })?;
    s = pointers(&s);
    s = int_literals(&s);
    // WGSL builtins GLSL 3.30 lacks or names otherwise, which the translation does not
    // rewrite: write their GLSL in a //#glsl region.
    for word in [
        "countOneBits",
        "countLeadingZeros",
        "countTrailingZeros",
        "firstLeadingBit",
        "firstTrailingBit",
        "reverseBits",
        "extractBits",
        "insertBits",
        "inverseSqrt",
        "arrayLength",
        "textureDimensions",
        "modf",
        "frexp",
    ] {
        if contains_word(&s, word) {
            return Err(format!("`{word}` has no GLSL 3.30 mirror: {s}"));
        }
    }
    for word in ["let ", "var ", "fn ", "override ", "ptr<"] {
        if contains_word(&s, word.trim_end()) {
            return Err(format!("`{}` left after translation: {s}", word.trim()));
        }
    }
    Ok(format!("{indent}{s}"))
}

/// `let|var|const name: type = …` and `var name: type;` (also in a `for` header) as
/// GLSL declarations; `override name: type = v;` as a uniform with that default.
fn declarations(s: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = s;
    loop {
        let found = ["let ", "var ", "const ", "override "]
            .iter()
            .filter_map(|k| find_word(rest, k.trim_end()).map(|p| (p, *k)))
            .min_by_key(|(p, _)| *p);
        let Some((p, keyword)) = found else {
            out.push_str(rest);
            return Ok(out);
        };
        out.push_str(&rest[..p]);
        let after = &rest[p + keyword.len()..];
        let end = after
            .find(['=', ';'])
            .ok_or_else(|| format!("a declaration without `=` or `;`: {s}"))?;
        let (name, t) = after[..end]
            .split_once(':')
            .ok_or_else(|| format!("an untyped {}: {s}", keyword.trim()))?;
        let d = decl(name.trim(), t.trim())?;
        match keyword {
            "const " => out.push_str("const "),
            "override " => out.push_str("uniform "),
            _ => {}
        }
        out.push_str(&d);
        rest = &after[end..];
        if rest.starts_with('=') {
            out.push(' ');
        }
    }
}

/// A texture binding as a GLSL sampler uniform.
fn binding(s: &str) -> Result<String, String> {
    let (_, var) = s
        .split_once("var ")
        .ok_or_else(|| format!("a binding that is not a var: {s}"))?;
    let (name, t) = var
        .trim_end_matches(';')
        .split_once(':')
        .ok_or_else(|| format!("an untyped binding: {s}"))?;
    let sampler = match t.trim() {
        "texture_2d<f32>" => "sampler2D",
        "texture_2d<u32>" => "usampler2D",
        "texture_2d<i32>" => "isampler2D",
        other => {
            return Err(format!(
                "a binding of type {other} outside a //#wgsl region"
            ))
        }
    };
    Ok(format!("uniform {sampler} {};", name.trim()))
}

/// Every call `name(args…)` in `s` rewritten by `f` (innermost first).
fn calls(s: &str, name: &str, f: &dyn Fn(&[String]) -> Option<String>) -> Result<String, String> {
    let mut s = s.to_string();
    while let Some(p) = rfind_word(&s, name) {
        let open = p + name.len();
        if s.as_bytes().get(open) != Some(&b'(') {
            return Err(format!("`{name}` not called: {s}"));
        }
        let close = matching(&s, open).ok_or_else(|| format!("unbalanced `{name}(`: {s}"))?;
        let args: Vec<String> = split_args(&s[open + 1..close], false)
            .iter()
            .map(|a| a.trim().to_string())
            .collect();
        let new = f(&args).ok_or_else(|| format!("`{name}` with {} arguments: {s}", args.len()))?;
        s.replace_range(p..=close, &new);
    }
    Ok(s)
}

/// Texel coordinates as the `ivec2` `texelFetch` takes: a `uvec2(…)` or `ivec2(…)`
/// constructor's arguments in an `ivec2(…)`, anything else converted.
fn int_coords(c: &str) -> String {
    for ctor in ["uvec2(", "ivec2("] {
        if let Some(inner) = c.strip_prefix(ctor).and_then(|r| r.strip_suffix(')')) {
            if matching(c, ctor.len() - 1) == Some(c.len() - 1) {
                return format!("ivec2({inner})");
            }
        }
    }
    format!("ivec2({c})")
}

/// `*p` and `&p` (a pointer's use and a variable's address) as the plain name: a `*`
/// or `&` right before a name or `(` that does not follow an operand (a product
/// `a * b` and a bitwise `a & b` keep theirs).
fn pointers(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = String::with_capacity(s.len());
    for (k, c) in s.char_indices() {
        let before_operand = b.get(k + 1).is_some_and(|&n| is_name(n) || n == b'(');
        if (c == '*' || c == '&') && before_operand && !after_operand(&b[..k]) {
            continue;
        }
        out.push(c);
    }
    out
}

/// Whether the code `before` ends with an operand (a name other than `return`, a
/// number, `)` or `]`), ignoring spaces.
fn after_operand(before: &[u8]) -> bool {
    let trimmed = before.trim_ascii_end();
    let Some(&last) = trimmed.last() else {
        return false;
    };
    if last == b')' || last == b']' {
        return true;
    }
    if !is_name(last) {
        return false;
    }
    let start = trimmed
        .iter()
        .rposition(|&c| !is_name(c))
        .map_or(0, |p| p + 1);
    &trimmed[start..] != b"return"
}

/// Integer literals with WGSL's `i` suffix without it (`0i` → `0`).
fn int_literals(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = String::with_capacity(s.len());
    for (k, c) in s.char_indices() {
        if c == 'i'
            && k > 0
            && b[k - 1].is_ascii_digit()
            && b.get(k + 1).is_none_or(|&n| !is_name(n))
        {
            let start = b[..k]
                .iter()
                .rposition(|c| !c.is_ascii_digit())
                .map_or(0, |p| p + 1);
            let in_name = start > 0 && (is_name(b[start - 1]) || b[start - 1] == b'.');
            if !in_name {
                continue;
            }
        }
        out.push(c);
    }
    out
}

/// Array constructors `array<T, N>(…)` as GLSL's `T[N](…)`.
fn arrays(s: &str) -> Result<String, String> {
    let mut s = s.to_string();
    while let Some(p) = find_word(&s, "array") {
        let open = p + "array".len();
        if s.as_bytes().get(open) != Some(&b'<') {
            return Err(format!("`array` without a type: {s}"));
        }
        let mut depth = 0;
        let close = s[open..]
            .char_indices()
            .find_map(|(k, c)| {
                match c {
                    '<' => depth += 1,
                    '>' => depth -= 1,
                    _ => {}
                }
                (depth == 0).then_some(open + k)
            })
            .ok_or_else(|| format!("unbalanced `array<`: {s}"))?;
        let t = ty(&s[p..=close])?;
        s.replace_range(p..=close, &t);
    }
    Ok(s)
}

/// How many more `(` than `)` `code` has.
fn depth(code: &str) -> i32 {
    code.chars().fold(0, |d, c| match c {
        '(' => d + 1,
        ')' => d - 1,
        _ => d,
    })
}

/// The index of the `)` matching the `(` at `open`.
fn matching(s: &str, open: usize) -> Option<usize> {
    let mut depth = 0;
    for (k, c) in s[open..].char_indices() {
        match c {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(open + k);
                }
            }
            _ => {}
        }
    }
    None
}

/// `args` split at its top-level commas (with `angles`, the angle brackets of WGSL
/// types count as nesting; expressions compare with them).
fn split_args(args: &str, angles: bool) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut depth = 0i32;
    for c in args.chars() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            '<' if angles => depth += 1,
            '>' if angles => depth -= 1,
            _ => {}
        }
        if c == ',' && depth == 0 {
            out.push(String::new());
        } else if let Some(last) = out.last_mut() {
            last.push(c);
        }
    }
    out
}

/// Whether `c` can be part of a name.
fn is_name(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The first position of `word` in `s` as a whole word.
fn find_word(s: &str, word: &str) -> Option<usize> {
    positions(s, word).next()
}

/// The last position of `word` in `s` as a whole word.
fn rfind_word(s: &str, word: &str) -> Option<usize> {
    positions(s, word).last()
}

/// Whether `s` holds `word` as a whole word.
fn contains_word(s: &str, word: &str) -> bool {
    find_word(s, word).is_some()
}

/// The positions of `word` in `s` as a whole word.
fn positions<'a>(s: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    let b = s.as_bytes();
    s.match_indices(word).map(|(p, _)| p).filter(move |&p| {
        let before = p == 0 || !is_name(b[p - 1]);
        let after = b.get(p + word.len()).is_none_or(|&c| !is_name(c));
        before && after
    })
}

/// `s` with every whole-word `from` replaced by `to`.
fn replace_word(s: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut last = 0;
    for p in positions(s, from).collect::<Vec<_>>() {
        out.push_str(&s[last..p]);
        out.push_str(to);
        last = p + from.len();
    }
    out.push_str(&s[last..]);
    out
}

#[cfg(test)]
mod tests {
    use super::glsl_from_wgsl;

    fn body(wgsl: &str) -> String {
        let g = glsl_from_wgsl(wgsl, "t").unwrap();
        g.lines().skip(2).collect::<Vec<_>>().join("\n")
    }

    #[test]
    fn statements_translate() {
        assert_eq!(
            body("fn f(a: f32, b: ptr<function, vec3<f32>>) -> u32 {\n    let x: vec2<u32> = vec2<u32>(1u, 2u);\n    *b = vec3<f32>(select(a, 1.0, a < 0.0));\n    for (var k: i32 = 0i; k < 2; k++) {\n    }\n    return bitcast<u32>(a * *b.x);\n}"),
            "uint f(float a, inout vec3 b) {\n    uvec2 x = uvec2(1u, 2u);\n    b = vec3(((a < 0.0) ? (1.0) : (a)));\n    for (int k = 0; k < 2; k++) {\n    }\n    return floatBitsToUint(a * b.x);\n}"
        );
        assert_eq!(
            body("struct S {\n    a: f32,\n    b: array<f32, 2>,\n}\nvar x: S;\noverride o: u32 = 15u;"),
            "struct S {\n    float a;\n    float[2] b;\n};\nS x;\nuniform uint o = 15u;"
        );
        assert_eq!(
            body("fn g(p: ptr<function, f32>,\n     q: f32) {\n    g(&x, a & b);\n}"),
            "void g(inout float p, float q) {\n    g(x, a & b);\n}"
        );
    }

    #[test]
    fn regions_choose_a_language() {
        let t = "//#wgsl\nfn w() {}\n//#end\n//#glsl\n// void g() {}\n//#end\n//#if upward\n// c\n//#endif";
        assert_eq!(body(t), "void g() {}\n//#if upward\n// c\n//#endif");
    }

    #[test]
    fn what_has_no_mirror_is_an_error() {
        for bad in [
            "let x = 1.0;",
            "@group(0) @binding(1) var<uniform> u: U;",
            "var<uniform> u: U;",
            "//#wgsl\n",
            "//#end",
            "//#glsl\nnot a comment\n//#end",
            "fn f(v: u32) -> u32 { return countOneBits(v); }",
        ] {
            assert!(glsl_from_wgsl(bad, "t").is_err(), "{bad}");
        }
    }
}
