//! The text format of `hfcast trace`: one ray per line in, one answer per line out.
//!
//! In: `ox oy oz dx dy dz [t_min t_max]` (whitespace separated, grid space; `t_min`
//! defaults to 0, `t_max` to `inf`); `#` starts a comment. Out:
//! `hit t x y z cell_i cell_j nx ny nz fetches flags` (flags as the bit value of
//! [`hfcast::Flags`]), `miss fetches`, or `error <message>`.

use hfcast::{HeightField, Method, Query, Surface, Trace};

/// Parses one input line; `Ok(None)` for a blank or comment-only line.
pub fn parse_ray(line: &str) -> Result<Option<Query<f32>>, String> {
    let text = line.split('#').next().unwrap_or("");
    let fields: Vec<&str> = text.split_whitespace().collect();
    if fields.is_empty() {
        return Ok(None);
    }
    parse_fields(&fields).map(Some)
}

/// Parses `ox oy oz dx dy dz [t_min t_max]` from separate words.
pub fn parse_fields(fields: &[&str]) -> Result<Query<f32>, String> {
    if fields.len() != 6 && fields.len() != 8 {
        return Err(format!(
            "expected 6 or 8 numbers (ox oy oz dx dy dz [t_min t_max]), got {}",
            fields.len()
        ));
    }
    let mut v = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, f32::INFINITY];
    for (slot, word) in v.iter_mut().zip(fields) {
        *slot = word
            .parse()
            .map_err(|_| format!("not a number: {word:?}"))?;
    }
    Query::from_arrays([v[0], v[1], v[2]], [v[3], v[4], v[5]], v[6], v[7])
        .map_err(|e| e.to_string())
}

/// Formats a trace as one output line (without the newline).
pub fn format_trace(tr: &Trace<f32>) -> String {
    match tr.hit {
        Some(h) => format!(
            "hit {} {} {} {} {} {} {} {} {} {} {}",
            h.t,
            h.point.x,
            h.point.y,
            h.point.z,
            h.cell[0],
            h.cell[1],
            h.normal.x,
            h.normal.y,
            h.normal.z,
            tr.fetches,
            h.flags.0
        ),
        None => format!("miss {}", tr.fetches),
    }
}

/// Answers one input line: `None` for blank and comment lines, else the output line
/// and whether it is an error.
pub fn answer_line(
    hf: &HeightField,
    method: Method,
    surface: Surface,
    line: &str,
) -> Option<(String, bool)> {
    match parse_ray(line) {
        Ok(None) => None,
        Ok(Some(q)) => Some((format_trace(&method.trace(hf, surface, &q)), false)),
        Err(e) => Some((format!("error {e}"), true)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines() {
        let h = [0.0f32, 1.0, 1.0, 2.0];
        let hf = HeightField::new(&h, 2, 2, 2).unwrap();
        let ask = |l: &str| answer_line(&hf, Method::Exact, Surface::Triangles, l);
        assert_eq!(ask("  # nothing"), None);
        assert_eq!(ask(""), None);
        let (out, err) = ask("0.5 0.5 5 0 0 -1 # down").unwrap();
        assert!(!err && out.starts_with("hit 4 0.5 0.5 1 0 0 "), "{out}");
        assert_eq!(ask("5 5 5 0 0 1").unwrap(), ("miss 0".into(), false));
        assert!(ask("0 0 0 0 0 0").unwrap().1);
        assert!(ask("0 0 0 1 0").unwrap().1);
        assert!(ask("0 0 0 1 0 x").unwrap().1);
        assert!(ask("0 0 0 1 0 0 2 1").unwrap().1);
    }
}
