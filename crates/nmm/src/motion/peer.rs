//! PEER NGA strong-motion records (`.AT2`), NGA-West2 and the older PEER layout.
//!
//! Layout (four header lines, then the values):
//!
//! ```text
//! PEER NGA STRONG MOTION DATABASE RECORD                       line 1: free text
//! Imperial Valley-06, 10/15/1979, El Centro Array #6, 230      line 2: free text
//! ACCELERATION TIME SERIES IN UNITS OF G                       line 3: quantity and units
//! NPTS=  7807, DT=   .0050 SEC                                 line 4: count and step
//!   .3468084E-03  .3498234E-03  .3498970E-03 ...               values, any count per line
//! ```
//!
//! The older PEER layout has line 4 as `3901    0.01000    NPTS, DT` and line 3
//! as `ACCELERATION TIME HISTORY IN UNITS OF G`; both are accepted.
//!
//! Units (the word after `UNITS OF` on line 3): `G` → ×9.80665 m/s²;
//! `CM/S/S`, `CM/S^2`, `CM/S2`, `CM/SEC/SEC`, `GAL` → ×0.01; `M/S/S`, `M/S^2`,
//! `M/S2` → ×1. Any other unit, or a line 3 that is not an acceleration, is an
//! error. The number of values must equal NPTS. Samples: `t_i = i·DT`,
//! `i = 0 … NPTS−1`, driving the axis named by `component`.

use super::{err_at, parse_number, shorten, single_component};

/// Standard gravity (m/s²), the PEER unit `G`.
pub use super::G;

/// Parse `.AT2` text (see the module doc). `file` names the file in errors.
pub fn parse(file: &str, text: &str, component: &str) -> Result<Vec<[f64; 3]>, String> {
    let place = single_component(file, component)?;
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let mut header = Vec::with_capacity(4);
    for _ in 0..4 {
        match lines.next() {
            Some((_, l)) => header.push(l),
            None => {
                return Err(err_at(
                    file,
                    header.len() + 1,
                    "missing PEER header line (a .AT2 file has 4 header lines: title, \
                     event/station, units, NPTS/DT)",
                ))
            }
        }
    }
    let factor = units_factor(file, 3, header[2])?;
    let (npts, dt) = npts_dt(file, 4, header[3])?;

    let mut samples = Vec::with_capacity(npts.min(1 << 20));
    for (line_no, line) in lines {
        for tok in line.split_whitespace() {
            let v = parse_number(file, line_no, tok)?;
            if samples.len() == npts {
                return Err(err_at(
                    file,
                    line_no,
                    format!("more values than NPTS={npts} (header line 4)"),
                ));
            }
            let a = v * factor;
            if !a.is_finite() {
                return Err(err_at(
                    file,
                    line_no,
                    format!("value '{}' overflows once scaled", shorten(tok)),
                ));
            }
            let t = samples.len() as f64 * dt;
            samples.push(place(t, a));
        }
    }
    if samples.len() != npts {
        return Err(err_at(
            file,
            4,
            format!(
                "NPTS={npts} but only {} values (truncated file?)",
                samples.len()
            ),
        ));
    }
    Ok(samples)
}

/// Factor to m/s² from the units line (`... ACCELERATION ... IN UNITS OF G`).
///
/// The unit is the phrase after `UNITS OF` (else after `UNITS`, else after the last
/// ` IN `), read as abbreviations or in words: `G`, `GS`, `G'S`, `GRAVITY` → g;
/// `CM/S/S`, `CM/S^2`, `CM/SEC/SEC`, `GAL`, `GALS`, `CENTIMETERS PER SECOND PER SECOND`,
/// `CM PER SEC SQUARED`, … → 0.01; `MM/S/S`, `MILLIMETRES PER SECOND SQUARED` → 0.001;
/// `M/S/S`, `METERS PER SECOND PER SECOND`, `METRES/SEC**2`, … → 1. Anything else (feet,
/// a length without two time units, no unit) is refused rather than guessed.
fn units_factor(file: &str, line_no: usize, line: &str) -> Result<f64, String> {
    let upper = line.to_ascii_uppercase();
    if !upper.contains("ACCEL") {
        let msg = if upper.contains("UNITS") || upper.contains("VELOC") || upper.contains("DISPL") {
            format!(
                "not an acceleration record: '{}' (only acceleration .AT2 files are read)",
                shorten(line.trim())
            )
        } else {
            format!(
                "expected the units line 'ACCELERATION TIME SERIES IN UNITS OF G', found '{}'",
                shorten(line.trim())
            )
        };
        return Err(err_at(file, line_no, msg));
    }
    let phrase = if let Some(p) = upper.find("UNITS OF") {
        &upper[p + "UNITS OF".len()..]
    } else if let Some(p) = upper.find("UNITS") {
        upper[p + "UNITS".len()..].trim_start_matches([':', '=', ' '])
    } else if let Some(p) = upper.rfind(" IN ") {
        &upper[p + " IN ".len()..]
    } else {
        return Err(err_at(
            file,
            line_no,
            format!(
                "no unit on the units line '{}' (expected e.g. 'IN UNITS OF G')",
                shorten(line.trim())
            ),
        ));
    };
    if phrase.trim().is_empty() {
        return Err(err_at(file, line_no, "no unit after 'UNITS OF'"));
    }
    match unit_phrase(phrase) {
        Some(f) => Ok(f),
        None => Err(err_at(
            file,
            line_no,
            format!(
                "unknown acceleration unit '{}' (expected G, CM/S/S, M/S/S or these in words)",
                shorten(phrase.split_whitespace().next().unwrap_or(""))
            ),
        )),
    }
}

/// The factor to m/s² of a unit written at the start of `phrase` (upper case), or
/// `None` when it is not a known acceleration unit.
fn unit_phrase(phrase: &str) -> Option<f64> {
    // words, with the punctuation that ends a sentence or a clause taken off
    let words: Vec<&str> = phrase
        .split_whitespace()
        .map(|w| w.trim_matches(|c: char| matches!(c, '.' | ',' | ';' | ':' | '(' | ')')))
        .filter(|w| !w.is_empty())
        .collect();
    let first = *words.first()?;
    match first {
        "G" | "GS" | "G'S" | "GRAVITY" => return Some(G),
        "GAL" | "GALS" | "GALILEO" => return Some(0.01),
        _ => {}
    }
    // a length, then `/ time / time`, `PER time PER time`, `PER time SQUARED`, … : the
    // words joined and normalised to LENGTH/S2
    let mut joined = String::new();
    for (k, w) in words.iter().enumerate() {
        let piece = match *w {
            "PER" => "/",
            "SQUARED" | "**2" | "^2" => "^2",
            w if k == 0 || w.starts_with('/') || w.starts_with("SEC") || w.starts_with('S') => w,
            _ => break,
        };
        // a time word must follow PER or a slash
        joined.push_str(piece);
    }
    let mut s = joined;
    for (long, short) in [
        ("CENTIMETERS", "CM"),
        ("CENTIMETRES", "CM"),
        ("CENTIMETER", "CM"),
        ("CENTIMETRE", "CM"),
        ("MILLIMETERS", "MM"),
        ("MILLIMETRES", "MM"),
        ("MILLIMETER", "MM"),
        ("MILLIMETRE", "MM"),
        ("METERS", "M"),
        ("METRES", "M"),
        ("METER", "M"),
        ("METRE", "M"),
        ("SECONDS", "S"),
        ("SECOND", "S"),
        ("SECS", "S"),
        ("SEC", "S"),
    ] {
        s = s.replace(long, short);
    }
    let s = s
        .replace("**2", "2")
        .replace("^2", "2")
        .replace("/S/S", "/S2");
    match s.as_str() {
        "CM/S2" => Some(0.01),
        "MM/S2" => Some(0.001),
        "M/S2" => Some(1.0),
        _ => None,
    }
}

/// NPTS and DT from line 4: `NPTS=  5590, DT=   .0050 SEC` or `5590   .0050   NPTS, DT`.
fn npts_dt(file: &str, line_no: usize, line: &str) -> Result<(usize, f64), String> {
    let upper = line.to_ascii_uppercase();
    let bad = |what: &str| {
        err_at(
            file,
            line_no,
            format!(
                "{what} in '{}' (expected 'NPTS=  5590, DT=   .0050 SEC' or '5590   .0050   NPTS, DT')",
                shorten(line.trim())
            ),
        )
    };
    let (n_tok, dt_tok): (String, String) = if upper.contains("NPTS=") || upper.contains("NPTS =") {
        let after = |key: &str| -> Option<String> {
            let p = upper.find(key)? + key.len();
            let rest = upper[p..].trim_start().trim_start_matches('=').trim_start();
            let tok: String = rest
                .chars()
                .take_while(|c| !c.is_whitespace() && *c != ',')
                .collect();
            Some(tok)
        };
        let n = after("NPTS").ok_or_else(|| bad("no NPTS"))?;
        let dt = upper
            .find("DT")
            .and_then(|_| after("DT"))
            .ok_or_else(|| bad("no DT"))?;
        (n, dt)
    } else if upper.contains("NPTS") && upper.contains("DT") {
        let mut toks = upper
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty());
        let n = toks.next().ok_or_else(|| bad("no NPTS"))?.to_string();
        let dt = toks.next().ok_or_else(|| bad("no DT"))?.to_string();
        (n, dt)
    } else {
        return Err(bad("no NPTS/DT"));
    };
    // NPTS is an integer, though some writers print "5590." .
    let n = parse_number(file, line_no, &n_tok)?;
    if n < 1.0 || n.fract() != 0.0 || n > 1e12 {
        return Err(bad(&format!(
            "NPTS '{n_tok}' is not a positive whole number"
        )));
    }
    let dt = parse_number(file, line_no, &dt_tok)?;
    if dt <= 0.0 {
        return Err(bad(&format!("DT '{dt_tok}' is not positive")));
    }
    Ok((n as usize, dt))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_npts_layouts() {
        assert_eq!(
            npts_dt("f", 4, "NPTS=  5590, DT=   .0050 SEC").unwrap(),
            (5590, 0.005)
        );
        assert_eq!(
            npts_dt("f", 4, "NPTS= 7807, DT= 0.0050 SEC,").unwrap(),
            (7807, 0.005)
        );
        assert_eq!(
            npts_dt("f", 4, " 5590   .0050   NPTS, DT").unwrap(),
            (5590, 0.005)
        );
        assert!(npts_dt("f", 4, "NPTS=  -3, DT= .01 SEC").is_err());
        assert!(npts_dt("f", 4, "NPTS=  3, DT= 0 SEC").is_err());
        assert!(npts_dt("f", 4, "hello")
            .unwrap_err()
            .starts_with("f: line 4:"));
    }

    #[test]
    fn units() {
        assert_eq!(
            units_factor("f", 3, "ACCELERATION TIME SERIES IN UNITS OF G").unwrap(),
            G
        );
        assert_eq!(
            units_factor("f", 3, "ACCELERATION TIME HISTORY IN UNITS OF G.").unwrap(),
            G
        );
        assert_eq!(
            units_factor("f", 3, "ACCELERATION TIME SERIES IN UNITS OF CM/S/S").unwrap(),
            0.01
        );
        assert_eq!(
            units_factor("f", 3, "ACCELERATION TIME SERIES IN UNITS OF CM/S^2").unwrap(),
            0.01
        );
        assert_eq!(
            units_factor("f", 3, "ACCELERATION TIME SERIES IN UNITS OF M/S/S").unwrap(),
            1.0
        );
        assert!(units_factor("f", 3, "ACCELERATION TIME SERIES IN UNITS OF FT/S/S").is_err());
        // older headers: units in words
        for (line, f) in [
            (
                "ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.1 Hz",
                G,
            ),
            ("ACCELERATION IN G", G),
            ("Acceleration time history, units: g", G),
            ("ACCELERATION IN UNITS OF GRAVITY", G),
            (
                "ACCELERATION TIME HISTORY IN CENTIMETERS PER SECOND PER SECOND",
                0.01,
            ),
            ("ACCELERATION IN UNITS OF CM/SEC**2", 0.01),
            (
                "ACCELERATION, UNITS OF CENTIMETRES PER SECOND SQUARED",
                0.01,
            ),
            ("ACCELERATION IN UNITS OF GALS", 0.01),
            ("ACCELERATION IN METERS PER SECOND PER SECOND", 1.0),
            ("ACCELERATION IN UNITS OF METRES/SEC/SEC.", 1.0),
            ("ACCELERATION IN MILLIMETRES PER SECOND SQUARED", 0.001),
        ] {
            assert_eq!(units_factor("f", 3, line).unwrap(), f, "{line}");
        }
        for line in [
            "ACCELERATION IN FEET PER SECOND PER SECOND",
            "ACCELERATION TIME HISTORY",
            "ACCELERATION IN UNITS OF CENTIMETERS",
            "ACCELERATION IN UNITS OF METERS PER SECOND",
        ] {
            assert!(units_factor("f", 3, line).is_err(), "{line}");
        }
        assert!(units_factor("f", 3, "VELOCITY TIME SERIES IN UNITS OF CM/S").is_err());
    }
}
