//! Words shared by the findings: numbers, p-values, lists, and what a residual's sign means.

use super::cells::Family;

/// `p = 0.003`, `p = 2e-7`, `p < 1e-15`.
pub fn fmt_p(p: f64) -> String {
    if p < 1e-15 {
        "p < 1e-15".into()
    } else if p < 1e-3 {
        format!("p = {p:.0e}")
    } else {
        format!("p = {p:.3}")
    }
}

/// A signed number to about two significant digits.
pub fn signed(v: f64) -> String {
    let a = v.abs();
    if a >= 10.0 {
        format!("{v:+.0}")
    } else if a >= 1.0 {
        format!("{v:+.1}")
    } else {
        format!("{v:+.2}")
    }
}

/// The text with its first letter in upper case.
pub fn capital(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
        .unwrap_or_default()
}

/// What a residual of this sign means, in the words of the output (bending or force).
pub fn meaning(f: Family, v: f64) -> &'static str {
    match (f.bends_too_far(v), v > 0.0) {
        (Some(true), _) => "bends too far",
        (Some(false), _) => "does not bend far enough",
        (None, true) => "predicts too much force",
        (None, false) => "predicts too little force",
    }
}

/// `all 9 cells`, `8 of 9 cells`.
pub fn count(on: usize, cells: usize) -> String {
    if on == cells {
        format!("all {cells} cells")
    } else {
        format!("{on} of {cells} cells")
    }
}

/// `a`, `a and b`, `a, b and c`.
pub fn and_list(v: Vec<String>) -> String {
    match v.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => v.join(""),
    }
}

/// ` mm` after a number, nothing for a dimensionless `1`.
pub fn unit_suffix(unit: &str) -> String {
    if unit == "1" || unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}
