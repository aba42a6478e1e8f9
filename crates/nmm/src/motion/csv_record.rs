//! CSV base motion records: columns `t,ax[,ay]`, values in s and m/s².
//!
//! * Comma separated; spaces around fields are ignored.
//! * Blank lines and lines starting with `#` are ignored.
//! * The first remaining line is a header when none of its fields is a
//!   number (e.g. `t,ax,ay` or `time (s),accel (m/s2)`); it is skipped.
//!   Columns are positional: the header's names are not interpreted.
//! * Every data line has the same number of fields as the first, 2 or 3.
//!   With 3, `component` is ignored; with 2, the second column drives the
//!   axis named by `component` (`"x"` → ax, `"y"` → ay).
//! * Time must be strictly increasing; every value finite.

use super::{err_at, parse_number, shorten, single_component, Place};

/// Parse CSV text (see the module doc). `file` names the file in errors.
pub fn parse(file: &str, text: &str, component: &str) -> Result<Vec<[f64; 3]>, String> {
    let mut samples: Vec<[f64; 3]> = Vec::new();
    let mut ncols: Option<usize> = None;
    let mut seen_first = false;
    let mut place: Option<Place> = None;
    let mut last_line = 0;
    for (idx, raw) in text.lines().enumerate() {
        let line_no = idx + 1;
        last_line = line_no;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if !seen_first {
            seen_first = true;
            let any_number = fields.iter().any(|f| f.parse::<f64>().is_ok());
            if !any_number {
                continue; // header line
            }
        }
        let n = match ncols {
            Some(n) => n,
            None => {
                let n = fields.len();
                if !(2..=3).contains(&n) {
                    return Err(err_at(
                        file,
                        line_no,
                        format!("expected 2 or 3 columns (t,ax[,ay]), found {n}"),
                    ));
                }
                if n == 2 {
                    place = Some(single_component(file, component)?);
                }
                ncols = Some(n);
                n
            }
        };
        if fields.len() != n {
            return Err(err_at(
                file,
                line_no,
                format!(
                    "expected {n} columns like the first data line, found {} in '{}'",
                    fields.len(),
                    shorten(line)
                ),
            ));
        }
        let mut vals = [0.0; 3];
        for (v, f) in vals.iter_mut().zip(&fields) {
            *v = parse_number(file, line_no, f)?;
        }
        let sample = match place {
            Some(place) => place(vals[0], vals[1]),
            None => vals,
        };
        if let Some(prev) = samples.last() {
            if sample[0] <= prev[0] {
                return Err(err_at(
                    file,
                    line_no,
                    format!(
                        "time {} is not after the previous time {} (time must increase strictly)",
                        sample[0], prev[0]
                    ),
                ));
            }
        }
        samples.push(sample);
    }
    if samples.is_empty() {
        return Err(err_at(
            file,
            last_line.max(1),
            "empty record: no data lines",
        ));
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_two_or_three_columns() {
        let s = parse("m.csv", "t,ax,ay\n0,1,2\n\n0.5, -1 ,3\n", "x").unwrap();
        assert_eq!(s, vec![[0.0, 1.0, 2.0], [0.5, -1.0, 3.0]]);
        let s = parse("m.csv", "# comment\n0,1\n1,2\n", "y").unwrap();
        assert_eq!(s, vec![[0.0, 0.0, 1.0], [1.0, 0.0, 2.0]]);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse("m.csv", "t,ax\n0,1\n0,2\n", "x").unwrap_err();
        assert!(e.starts_with("m.csv: line 3:"), "{e}");
        let e = parse("m.csv", "t,ax\n0,1\n1,x\n", "x").unwrap_err();
        assert_eq!(e, "m.csv: line 3: cannot read number 'x'");
        let e = parse("m.csv", "0,1\n1,2,3\n", "x").unwrap_err();
        assert!(e.starts_with("m.csv: line 2:"), "{e}");
        let e = parse("m.csv", "t,ax\n\n", "x").unwrap_err();
        assert!(e.contains("empty record"), "{e}");
        let e = parse("m.csv", "0,1,2,3\n", "x").unwrap_err();
        assert!(e.starts_with("m.csv: line 1:"), "{e}");
    }
}
