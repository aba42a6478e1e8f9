//! NIED K-NET / KiK-net ASCII acceleration records (`*.NS`, `*.EW`, `*.UD`,
//! `*.NS1`, `*.EW2`, ...).
//!
//! Layout: 17 header lines, each a label then its value, in this order, then
//! integer counts (8 per line in NIED files; any count per line is read):
//!
//! ```text
//! Origin Time       2011/03/11 14:46:00
//! Lat.              38.103
//! Long.             142.860
//! Depth. (km)       24
//! Mag.              9.0
//! Station Code      MYG004
//! Station Lat.      38.7292
//! Station Long.     141.0217
//! Station Height(m) 230
//! Record Time       2011/03/11 14:46:29
//! Sampling Freq(Hz) 100Hz
//! Duration Time(s)  300
//! Dir.              N-S
//! Scale Factor      3920(gal)/6182761
//! Max. Acc. (gal)   2700.214
//! Last Correction   2011/03/11 14:46:14
//! Memo.
//!    -2119   -2120   -2122 ...
//! ```
//!
//! Every label must be present, in order (a missing or misplaced line is an
//! error naming it). `Dir.` is `N-S`, `E-W`, `U-D` (K-NET) or `1`…`6`
//! (KiK-net: 1–3 borehole, 4–6 surface); it is checked but the axis driven is
//! the caller's `component`.
//!
//! Conversion, with `S = num/den` from `Scale Factor  num(gal)/den`:
//!
//! ```text
//! a_i [m/s²] = 0.01 · S · (c_i − mean(c))        t_i = i / f_s
//! ```
//!
//! The mean of the whole record is subtracted, as NIED recommends for its raw
//! counts (the recorder's zero offset is not removed in the distributed files).
//! 1 gal = 1 cm/s² = 0.01 m/s².

use super::{err_at, parse_number, shorten, single_component};

/// Header labels of a K-NET/KiK-net ASCII file, in order (lines 1–17).
pub const LABELS: [&str; 17] = [
    "Origin Time",
    "Lat.",
    "Long.",
    "Depth. (km)",
    "Mag.",
    "Station Code",
    "Station Lat.",
    "Station Long.",
    "Station Height(m)",
    "Record Time",
    "Sampling Freq(Hz)",
    "Duration Time(s)",
    "Dir.",
    "Scale Factor",
    "Max. Acc. (gal)",
    "Last Correction",
    "Memo.",
];

/// Parse K-NET/KiK-net ASCII text (see the module doc). `file` names the file in errors.
pub fn parse(file: &str, text: &str, component: &str) -> Result<Vec<[f64; 3]>, String> {
    let place = single_component(file, component)?;
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let mut values: [&str; 17] = [""; 17];
    for (k, label) in LABELS.iter().enumerate() {
        let line_no = k + 1;
        let Some((_, line)) = lines.next() else {
            return Err(err_at(
                file,
                line_no,
                format!("missing K-NET header line '{label}' (file ends in the header)"),
            ));
        };
        let Some(rest) = line.trim_start().strip_prefix(label) else {
            return Err(err_at(
                file,
                line_no,
                format!(
                    "expected K-NET header line '{label}', found '{}'",
                    shorten(line.trim())
                ),
            ));
        };
        values[k] = rest.trim();
    }
    let freq = sampling_frequency(file, 11, values[10])?;
    let duration = parse_number(file, 12, values[11])?;
    if duration < 0.0 {
        return Err(err_at(file, 12, "negative duration"));
    }
    check_direction(file, 13, values[12])?;
    let scale = scale_factor(file, 14, values[13])?;
    parse_number(file, 15, values[14])?;

    let mut counts: Vec<(usize, i64)> = Vec::new();
    for (line_no, line) in lines {
        for tok in line.split_whitespace() {
            let c = tok.parse::<i64>().map_err(|_| {
                err_at(
                    file,
                    line_no,
                    format!("cannot read integer count '{}'", shorten(tok)),
                )
            })?;
            counts.push((line_no, c));
        }
    }
    if counts.is_empty() {
        return Err(err_at(
            file,
            18,
            "empty record: no counts after the 17 header lines",
        ));
    }
    let mean = counts.iter().map(|&(_, c)| c as f64).sum::<f64>() / counts.len() as f64;
    let to_ms2 = 0.01 * scale;
    let mut samples = Vec::with_capacity(counts.len());
    for (i, &(line_no, c)) in counts.iter().enumerate() {
        let a = (c as f64 - mean) * to_ms2;
        if !a.is_finite() {
            return Err(err_at(file, line_no, "acceleration overflows once scaled"));
        }
        samples.push(place(i as f64 / freq, a));
    }
    Ok(samples)
}

/// `100Hz` → 100.
fn sampling_frequency(file: &str, line_no: usize, value: &str) -> Result<f64, String> {
    let v = value.trim();
    let num = v
        .strip_suffix("Hz")
        .or_else(|| v.strip_suffix("HZ"))
        .or_else(|| v.strip_suffix("hz"))
        .unwrap_or(v);
    let f = parse_number(file, line_no, num)?;
    if f <= 0.0 {
        return Err(err_at(
            file,
            line_no,
            format!("sampling frequency '{}' is not positive", shorten(v)),
        ));
    }
    Ok(f)
}

/// `N-S`, `E-W`, `U-D`, or KiK-net channel `1`…`6`.
fn check_direction(file: &str, line_no: usize, value: &str) -> Result<(), String> {
    match value.trim() {
        "N-S" | "E-W" | "U-D" | "NS" | "EW" | "UD" | "1" | "2" | "3" | "4" | "5" | "6" => Ok(()),
        other => Err(err_at(
            file,
            line_no,
            format!(
                "unknown direction '{}' (expected N-S, E-W, U-D or a KiK-net channel 1-6)",
                shorten(other)
            ),
        )),
    }
}

/// `3920(gal)/6182761` → 3920/6182761 (gal per count).
fn scale_factor(file: &str, line_no: usize, value: &str) -> Result<f64, String> {
    let compact: String = value.chars().filter(|c| !c.is_whitespace()).collect();
    let bad = |why: &str| {
        err_at(
            file,
            line_no,
            format!(
                "bad scale factor '{}': {why} (expected like '3920(gal)/6182761')",
                shorten(value)
            ),
        )
    };
    let lower = compact.to_ascii_lowercase();
    let Some(p) = lower.find("(gal)/") else {
        return Err(bad("no '(gal)/'"));
    };
    let num = compact[..p]
        .parse::<f64>()
        .map_err(|_| bad("numerator is not a number"))?;
    let den = compact[p + "(gal)/".len()..]
        .parse::<f64>()
        .map_err(|_| bad("denominator is not a number"))?;
    if !(num.is_finite() && den.is_finite() && num > 0.0 && den > 0.0) {
        return Err(bad("numerator and denominator must be positive and finite"));
    }
    let s = num / den;
    if !(s.is_finite() && s > 0.0) {
        return Err(bad("ratio is not a positive finite number"));
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_fields() {
        assert_eq!(sampling_frequency("f", 11, "100Hz").unwrap(), 100.0);
        assert_eq!(sampling_frequency("f", 11, "200").unwrap(), 200.0);
        assert!(sampling_frequency("f", 11, "0Hz").is_err());
        assert_eq!(
            scale_factor("f", 14, "3920(gal)/6182761").unwrap(),
            3920.0 / 6182761.0
        );
        assert_eq!(
            scale_factor("f", 14, "7845(gal)/8223790").unwrap(),
            7845.0 / 8223790.0
        );
        assert!(scale_factor("f", 14, "3920/6182761").is_err());
        assert!(scale_factor("f", 14, "3920(gal)/0").is_err());
        assert!(scale_factor("f", 14, "x(gal)/5")
            .unwrap_err()
            .starts_with("f: line 14:"));
        assert!(check_direction("f", 13, "4").is_ok());
        assert!(check_direction("f", 13, "Z").is_err());
    }
}
