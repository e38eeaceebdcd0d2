//! Every function of `include/hfcast.h` states its thread safety (issue 26, item 4):
//! its comment says "Thread safe" (with what it shares: "reads the field only", "for
//! distinct output buffers", …) or what "exclusive access" it needs. The protocol
//! itself is stated once, in the header's preamble (capi/cbindgen.toml) and on
//! `hf_field` (capi/src/field.rs).

use std::path::PathBuf;

/// The phrases a thread-safety statement is made of.
const VOCABULARY: [&str; 2] = ["Thread safe", "exclusive access"];

/// The committed header.
fn header() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../include/hfcast.h");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

/// Each function declared in `header` with the text of the `//` comment just above it
/// (its lines joined by spaces, so a phrase broken across lines still reads whole).
fn functions(header: &str) -> Vec<(String, String)> {
    let lines: Vec<&str> = header.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let starts_decl = line.starts_with(|c: char| c.is_ascii_alphabetic())
            && !line.starts_with("typedef")
            && !line.starts_with("extern");
        let Some(open) = line.find('(').filter(|_| starts_decl) else {
            continue;
        };
        let Some(name) = line[..open]
            .rsplit([' ', '*'])
            .next()
            .filter(|n| n.starts_with("hf_"))
        else {
            continue;
        };
        let doc: Vec<&str> = lines[..i]
            .iter()
            .rev()
            .map_while(|l| l.strip_prefix("//"))
            .map(str::trim)
            .collect();
        let doc = doc.into_iter().rev().collect::<Vec<_>>().join(" ");
        out.push((name.to_string(), doc));
    }
    out
}

/// The functions of `header` whose comment has no thread-safety statement.
fn undocumented(header: &str) -> Vec<String> {
    functions(header)
        .into_iter()
        .filter(|(_, doc)| !VOCABULARY.iter().any(|v| doc.contains(v)))
        .map(|(name, _)| name)
        .collect()
}

#[test]
fn every_function_states_its_thread_safety() {
    let h = header();
    let n = functions(&h).len();
    // 51 exports since the traces are two functions and every bake goes through the
    // `hf_bake*` functions (0.2.0); a parser that finds far fewer is broken.
    assert!(
        n > 45,
        "only {n} functions found in include/hfcast.h: is the parser broken?"
    );
    let missing = undocumented(&h);
    assert!(
        missing.is_empty(),
        "{} of {n} functions do not state their thread safety (one of {VOCABULARY:?} in \
         the doc comment, before `# Safety`): {missing:?}",
        missing.len()
    );
}

#[test]
fn the_protocol_is_stated_in_the_preamble() {
    let h = header();
    let preamble = &h[..h.find("#ifndef HFCAST_H").expect("include guard")];
    let para = &preamble[preamble
        .find("Thread safety:")
        .expect("a Thread safety: paragraph")..];
    for f in [
        "hf_field_update_rect",
        "hf_field_set_transform",
        "hf_field_destroy",
    ] {
        assert!(
            para.contains(f),
            "the preamble's thread-safety paragraph omits {f}"
        );
    }
    assert!(para.contains("hf_maxmip_update_rect") && para.contains("readers-writer"));
}

/// The check itself: a function without a statement is reported, a wrapped one is not.
#[test]
fn the_check_finds_a_missing_statement() {
    let h = "// Does a thing. Thread\n// safe.\n//\n// # Safety\n// None.\n\
             hf_result hf_good(uint32_t a,\n                  uint32_t b);\n\n\
             // Does another thing.\nconst char *hf_bad(void);\n\
             // Frees it. Needs exclusive access to `x`.\nvoid hf_free(struct hf_x *x);\n";
    assert_eq!(functions(h).len(), 3);
    assert_eq!(undocumented(h), ["hf_bad"]);
}
