//! Base motion records: reading a ground-acceleration record file into samples
//! `(t, ax, ay)`.
//!
//! This module owns the file formats of base motion records and nothing else:
//! it knows no mechanics. It returns samples with
//!
//! * `t` in seconds, strictly increasing, every value finite;
//! * `ax`, `ay` in m/s², the record's **own** header scale factors applied
//!   (PEER units line, K-NET scale factor); the user's `scale` from the model
//!   file is applied by the caller.
//!
//! Sign convention: `ax` is positive toward +x, `ay` positive toward +y (up),
//! the axes of the model. A single-component record (PEER, K-NET, CSV with
//! only `t,ax`) drives the axis named by `component` (`"x"` or `"y"`); the
//! other axis is zero.
//!
//! Formats (see the submodules for the details of each):
//!
//! * `"csv"` ([`csv_record`]): columns `t,ax[,ay]`, comma separated, optional
//!   header line, blank lines and `#` comment lines ignored; values in m/s².
//! * `"peer"` ([`peer`]): PEER NGA(-West2) `.AT2`, four header lines then
//!   values; `t_i = i·DT`; units from line 3 (G → ×9.80665, CM/S/S → ×0.01,
//!   M/S/S → ×1).
//! * `"knet"` ([`knet`]): NIED K-NET / KiK-net ASCII, 17 header lines then
//!   integer counts; `a_i = c_i·S − mean(c·S)` with `S = num(gal)/den` and
//!   1 gal = 0.01 m/s²; `t_i = i/f_s`.
//! * `None`: inferred: extension `.AT2` (any case) → peer; contents starting
//!   with `Origin Time` → knet; otherwise csv.
//!
//! Errors are one line, `"<file>: line <n>: <what>"` (the line is omitted only
//! when no line applies, e.g. a file that cannot be opened). No input panics.

use std::path::Path;

pub mod csv_record;
pub mod knet;
pub mod peer;

/// Read a record file into samples `(t, ax, ay)` in m/s² (scale factors of the
/// record's own header applied; the user's `scale` is applied by the caller).
/// `format`: `Some("csv" | "peer" | "knet")`, or `None` to infer from the file.
/// `component`: which axis a single-component record drives (`"x"` or `"y"`).
pub fn read_record(
    path: &Path,
    format: Option<&str>,
    component: &str,
) -> Result<Vec<[f64; 3]>, String> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| format!("{file}: cannot read the file: {e}"))?;
    // Invalid UTF-8 becomes U+FFFD, which then fails to parse with a line number.
    let text = String::from_utf8_lossy(&bytes);
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let format = match format {
        Some(f) => f.trim().to_ascii_lowercase(),
        None => infer_format(path, text).to_string(),
    };
    let samples = match format.as_str() {
        "csv" => csv_record::parse(&file, text, component)?,
        "peer" | "at2" => peer::parse(&file, text, component)?,
        "knet" | "kik-net" | "kiknet" | "k-net" => knet::parse(&file, text, component)?,
        other => {
            return Err(format!(
                "{file}: unknown record format '{other}' (expected csv, peer or knet)"
            ))
        }
    };
    check_samples(&file, &samples)?;
    Ok(samples)
}

/// The format a file is read as when none is given: `.AT2` extension → `"peer"`,
/// text starting with `Origin Time` → `"knet"`, otherwise `"csv"`.
pub fn infer_format(path: &Path, text: &str) -> &'static str {
    let is_at2 = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if is_at2 {
        "peer"
    } else if text.trim_start().starts_with("Origin Time") {
        "knet"
    } else {
        "csv"
    }
}

/// Final guard shared by every format: non-empty, finite, strictly increasing t.
/// The readers already report these with exact line numbers; this catches what
/// arithmetic (scaling, i·DT rounding) could still produce.
fn check_samples(file: &str, samples: &[[f64; 3]]) -> Result<(), String> {
    if samples.is_empty() {
        return Err(format!("{file}: line 1: empty record (no samples)"));
    }
    for (i, s) in samples.iter().enumerate() {
        if !s.iter().all(|v| v.is_finite()) {
            return Err(format!(
                "{file}: sample {}: value not finite after scaling",
                i + 1
            ));
        }
        if i > 0 && s[0] <= samples[i - 1][0] {
            return Err(format!(
                "{file}: sample {}: time {} not after the previous {}",
                i + 1,
                s[0],
                samples[i - 1][0]
            ));
        }
    }
    Ok(())
}

/// Standard gravity g = 9.80665 m/s² (the unit `g` of PEER records and of
/// `[base_motion] pga`).
pub const G: f64 = 9.80665;

/// The window `[start, start + duration]` of samples `(t, ax, ay)`, shifted so that
/// `start` becomes t = 0. Its ends are interpolated linearly where they fall inside the
/// record; a window starting before the record's first sample keeps the record's own
/// start (the motion is zero before it). `duration = None`: to the record's end.
/// Errors (plain text, the caller adds the place): a start at or after the record's last
/// sample, a window ending after it, or fewer than 2 samples left.
pub fn window(s: &[[f64; 3]], start: f64, duration: Option<f64>) -> Result<Vec<[f64; 3]>, String> {
    let (first, last) = match (s.first(), s.last()) {
        (Some(a), Some(b)) => (a[0], b[0]),
        _ => return Err("empty record".into()),
    };
    if start >= last {
        return Err(format!(
            "the window starts at {start} s, at or after the record's end at {last} s"
        ));
    }
    let end = match duration {
        Some(d) => start + d,
        None => last,
    };
    // a window end within 1e-9 of the record's duration of its last sample is its end
    if end > last + 1e-9 * (last - first).abs().max(1e-12) {
        return Err(format!(
            "the window ends at {end} s (start {start} s + duration {} s), after the record's end at {last} s",
            end - start
        ));
    }
    let end = end.min(last);
    let at = |t: f64| -> [f64; 3] {
        let i = s.partition_point(|r| r[0] <= t);
        if i == 0 {
            return [t, s[0][1], s[0][2]];
        }
        if i >= s.len() {
            let l = s[s.len() - 1];
            return [t, l[1], l[2]];
        }
        let (a, b) = (s[i - 1], s[i]);
        let f = (t - a[0]) / (b[0] - a[0]);
        [t, a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])]
    };
    let mut out = Vec::new();
    if start > first {
        out.push(at(start));
    }
    out.extend(s.iter().filter(|r| r[0] >= start && r[0] < end).copied());
    out.push(at(end));
    out.dedup_by(|b, a| a[0] == b[0]);
    for r in out.iter_mut() {
        r[0] -= start;
    }
    if out.len() < 2 {
        return Err(format!(
            "the window [{start}, {end}] s holds fewer than 2 samples"
        ));
    }
    Ok(out)
}

/// Peak |a| of each axis of samples `(t, ax, ay)`, m/s² (the peak of a record linear
/// between samples is at a sample).
pub fn peaks(s: &[[f64; 3]]) -> [f64; 2] {
    s.iter().fold([0.0f64; 2], |p, r| {
        [p[0].max(r[1].abs()), p[1].max(r[2].abs())]
    })
}

/// The smallest and largest interval between consecutive samples, s.
pub fn intervals(s: &[[f64; 3]]) -> (f64, f64) {
    s.windows(2)
        .map(|w| w[1][0] - w[0][0])
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        })
}

/// `"<file>: line <n>: <msg>"`.
pub(crate) fn err_at(file: &str, line: usize, msg: impl std::fmt::Display) -> String {
    format!("{file}: line {line}: {msg}")
}

/// Parse one number as written in record files: Rust float syntax plus
/// Fortran-style `D` exponents (`1.5D-03`) and leading `+`. Non-finite values
/// (`nan`, `inf`) are rejected here so every reader reports them with a line.
pub(crate) fn parse_number(file: &str, line: usize, tok: &str) -> Result<f64, String> {
    let tok = tok.trim();
    let parsed = if tok.contains(['D', 'd']) && !tok.to_ascii_lowercase().contains("inf") {
        tok.replace(['D', 'd'], "E").parse::<f64>()
    } else {
        tok.parse::<f64>()
    };
    match parsed {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(err_at(file, line, format!("value '{tok}' is not finite"))),
        Err(_) => Err(err_at(
            file,
            line,
            format!("cannot read number '{}'", shorten(tok)),
        )),
    }
}

/// A token cut to a readable length for error messages.
pub(crate) fn shorten(tok: &str) -> String {
    const MAX: usize = 40;
    if tok.chars().count() <= MAX {
        tok.to_string()
    } else {
        let head: String = tok.chars().take(MAX).collect();
        format!("{head}…")
    }
}

/// Builds a sample `(t, ax, ay)` from the time and one acceleration component.
pub(crate) type Place = fn(f64, f64) -> [f64; 3];

/// Place a single-component acceleration on the axis named by `component`.
pub(crate) fn single_component(file: &str, component: &str) -> Result<Place, String> {
    match component.trim() {
        "x" | "X" => Ok(|t, a| [t, a, 0.0]),
        "y" | "Y" => Ok(|t, a| [t, 0.0, a]),
        other => Err(format!(
            "{file}: single-component record: component must be \"x\" or \"y\", not '{}'",
            shorten(other)
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_fortran_style_and_non_finite() {
        assert_eq!(parse_number("f", 1, ".5E-02").unwrap(), 0.005);
        assert_eq!(parse_number("f", 1, "-.25").unwrap(), -0.25);
        assert_eq!(parse_number("f", 1, "1.5D+01").unwrap(), 15.0);
        assert_eq!(parse_number("f", 1, "+2").unwrap(), 2.0);
        let e = parse_number("a.AT2", 7, "abc").unwrap_err();
        assert_eq!(e, "a.AT2: line 7: cannot read number 'abc'");
        assert!(parse_number("f", 3, "NaN").unwrap_err().contains("line 3"));
        assert!(parse_number("f", 3, "inf")
            .unwrap_err()
            .contains("not finite"));
        assert!(parse_number("f", 3, "1e999")
            .unwrap_err()
            .contains("not finite"));
    }

    #[test]
    fn inference() {
        assert_eq!(infer_format(Path::new("a/RSN6.AT2"), "x"), "peer");
        assert_eq!(infer_format(Path::new("b.at2"), "x"), "peer");
        assert_eq!(
            infer_format(Path::new("MYG0041103111446.NS"), "Origin Time  2011/03/11"),
            "knet"
        );
        assert_eq!(infer_format(Path::new("m.csv"), "t,ax\n0,0"), "csv");
    }

    #[test]
    fn component_mapping() {
        assert_eq!(
            single_component("f", "x").unwrap()(1.0, 2.0),
            [1.0, 2.0, 0.0]
        );
        assert_eq!(
            single_component("f", "y").unwrap()(1.0, 2.0),
            [1.0, 0.0, 2.0]
        );
        assert!(single_component("f", "z").is_err());
    }
}
