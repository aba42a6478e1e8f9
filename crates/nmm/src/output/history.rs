//! `history.csv`: one row per time step, written as the run goes.
//!
//! Owns the CSV layout and the number format; knows nothing of what the columns mean (the
//! simulation passes the column names of its monitors, in file order).
//!
//! # Layout
//! ```text
//! step,time,<column 1>,...,<column n>,iterations[,<text>][,<count 1>,...]
//! 0,0,0,...,0,0
//! 1,0.001,1.2345678901234567e-7,...,3
//! ```
//! The header is quoted by the `csv` crate only when a name needs it (a comma, a quote, a
//! line break). `step`, `iterations` and the trailing counts (the simulation's `solves`
//! and `cuts`, [`HistoryWriter::create_with_counts`]) are unsigned integers.
//!
//! # Numbers
//! Every `f64` is written with the *shortest* decimal string that parses back to the same
//! bits (Rust's `Display`/`LowerExp` without precision), so `pandas.read_csv`,
//! `numpy.loadtxt` and Python's `float()` read back exactly the value computed:
//! * plain decimal (`Display`) when `x == 0` or `1e-5 <= |x| < 1e16`, e.g. `0.001`, `-12.5`;
//! * exponent notation (`LowerExp`) otherwise, e.g. `1.5e-9`, `2e20`, so that tiny or huge
//!   values do not expand into hundreds of digits.
//!
//! # Non-finite values (decision)
//! A NaN or an infinity means the step diverged. The writer does **not** panic (not even in
//! debug builds: the rows of a diverging run are the most useful ones to keep) and does not
//! leave the field empty (an empty field would look like a missing monitor). It writes
//! `nan`, `inf` or `-inf`, the spellings that Python's `float()`, pandas and numpy all parse
//! back to the same non-finite value, and counts them: [`HistoryWriter::non_finite_count`]
//! lets the caller warn or stop the run.
//!
//! # Durability
//! Rows are buffered and flushed to the operating system every [`HistoryWriter::flush_every`]
//! rows (by default every row: a step costs far more than a `write` call), on
//! [`HistoryWriter::flush`] and on drop, so an interrupted run keeps every row written so far.

use std::fs::File;
use std::io;
use std::path::Path;

/// Default number of rows between automatic flushes.
pub const DEFAULT_FLUSH_EVERY: usize = 1;

/// Streaming writer of `history.csv`.
pub struct HistoryWriter {
    writer: csv::Writer<File>,
    n_values: usize,
    flush_every: usize,
    rows_since_flush: usize,
    rows: usize,
    non_finite: usize,
    field: String,
    /// A text column after `iterations` (e.g. `stage`), if any.
    text_column: bool,
    /// Integer columns after those (their number).
    n_counts: usize,
}

impl HistoryWriter {
    /// Creates (truncates) `path` and writes the header `step,time,<columns...>,iterations`.
    ///
    /// Fails if the file cannot be created, or if a column is named `step`, `time` or
    /// `iterations` or appears twice (the header would then be ambiguous).
    pub fn create(path: &Path, columns: &[String]) -> io::Result<Self> {
        Self::create_with_counts(path, columns, None, &[])
    }

    /// As [`Self::create`], with a text column `text` after `iterations` and integer
    /// columns `counts` last (each row then gives their values to
    /// [`Self::write_row_counts`]).
    pub fn create_with_counts(
        path: &Path,
        columns: &[String],
        text: Option<&str>,
        counts: &[&str],
    ) -> io::Result<Self> {
        for (i, c) in columns.iter().enumerate() {
            if c == "step" || c == "time" || c == "iterations" {
                return Err(invalid(format!(
                    "history column name `{c}` is reserved (step, time, iterations)"
                )));
            }
            if columns[..i].contains(c) {
                return Err(invalid(format!("history column `{c}` appears twice")));
            }
            if counts.contains(&c.as_str()) || text == Some(c.as_str()) {
                return Err(invalid(format!(
                    "history column name `{c}` is reserved ({})",
                    text.iter()
                        .chain(counts)
                        .copied()
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
        }
        let file = File::create(path)?;
        let mut writer = csv::WriterBuilder::new()
            .has_headers(false)
            .terminator(csv::Terminator::Any(b'\n'))
            .from_writer(file);
        let mut names: Vec<&str> = Vec::with_capacity(columns.len() + 3);
        names.extend(["step", "time"]);
        names.extend(columns.iter().map(String::as_str));
        names.push("iterations");
        names.extend(text);
        names.extend(counts);
        writer.write_record(&names)?;
        writer.flush()?;
        Ok(Self::over(
            writer,
            columns.len(),
            text.is_some(),
            counts.len(),
        ))
    }

    /// A writer of rows of `n_values` monitor values (a text column, `n_counts` integer
    /// columns) onto `writer`.
    fn over(
        writer: csv::Writer<File>,
        n_values: usize,
        text_column: bool,
        n_counts: usize,
    ) -> Self {
        Self {
            writer,
            n_values,
            flush_every: DEFAULT_FLUSH_EVERY,
            rows_since_flush: 0,
            rows: 0,
            non_finite: 0,
            field: String::with_capacity(32),
            text_column,
            n_counts,
        }
    }

    /// Reopens a history written by [`Self::create_with_counts`] with the same columns (a
    /// text column or not, `n_counts` integer columns) to append rows after its first `len`
    /// bytes (a resumed run: later rows are dropped). Fails if the file is shorter than
    /// `len`.
    pub fn append_after(
        path: &Path,
        columns: &[String],
        text: bool,
        n_counts: usize,
        len: u64,
    ) -> io::Result<Self> {
        let file = std::fs::OpenOptions::new().write(true).open(path)?;
        let have = file.metadata()?.len();
        if have < len {
            return Err(invalid(format!(
                "has {have} bytes, fewer than the {len} written up to the checkpoint"
            )));
        }
        file.set_len(len)?;
        let mut file = file;
        io::Seek::seek(&mut file, io::SeekFrom::End(0))?;
        let writer = csv::WriterBuilder::new()
            .has_headers(false)
            .terminator(csv::Terminator::Any(b'\n'))
            .from_writer(file);
        Ok(Self::over(writer, columns.len(), text, n_counts))
    }

    /// Bytes written to the file so far (after a flush).
    pub fn position(&mut self) -> io::Result<u64> {
        self.flush()?;
        io::Seek::stream_position(&mut self.writer.get_ref())
    }

    /// Sets the number of rows between automatic flushes (at least 1).
    pub fn with_flush_every(mut self, rows: usize) -> Self {
        self.flush_every = rows.max(1);
        self
    }

    /// Number of rows between automatic flushes.
    pub fn flush_every(&self) -> usize {
        self.flush_every
    }

    /// Appends one row. `values` must have one entry per column given to [`Self::create`].
    pub fn write_row(
        &mut self,
        step: usize,
        time: f64,
        values: &[f64],
        iterations: usize,
    ) -> io::Result<()> {
        self.write_row_counts(step, time, values, iterations, None, &[])
    }

    /// An unsigned integer field (through the reused `field` buffer: no allocation).
    fn write_count(&mut self, x: usize) -> io::Result<()> {
        use std::fmt::Write;
        self.field.clear();
        write!(self.field, "{x}").expect("writing to a String");
        self.writer.write_field(&self.field)?;
        Ok(())
    }

    /// As [`Self::write_row`], with the value of the text column (required when the
    /// history has one, refused otherwise) and those of the integer columns (one each).
    pub fn write_row_counts(
        &mut self,
        step: usize,
        time: f64,
        values: &[f64],
        iterations: usize,
        text: Option<&str>,
        counts: &[usize],
    ) -> io::Result<()> {
        if counts.len() != self.n_counts {
            return Err(invalid(format!(
                "history row has {} counts, the header has {}",
                counts.len(),
                self.n_counts
            )));
        }
        if text.is_some() != self.text_column {
            return Err(invalid(
                "history row: a text value exactly when the header has a text column".into(),
            ));
        }
        if values.len() != self.n_values {
            return Err(invalid(format!(
                "history row has {} values, the header has {} columns",
                values.len(),
                self.n_values
            )));
        }
        self.write_count(step)?;
        for &v in std::iter::once(&time).chain(values) {
            self.field.clear();
            if !v.is_finite() {
                self.non_finite += 1;
            }
            format_f64(v, &mut self.field);
            self.writer.write_field(&self.field)?;
        }
        self.write_count(iterations)?;
        if let Some(t) = text {
            self.writer.write_field(t)?;
        }
        for &c in counts {
            self.write_count(c)?;
        }
        self.writer.write_record(None::<&[u8]>)?;
        self.rows += 1;
        self.rows_since_flush += 1;
        if self.rows_since_flush >= self.flush_every {
            self.flush()?;
        }
        Ok(())
    }

    /// Flushes buffered rows to the file.
    pub fn flush(&mut self) -> io::Result<()> {
        self.rows_since_flush = 0;
        self.writer.flush()
    }

    /// Rows written so far (header excluded).
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of NaN or infinite values written so far (time included).
    pub fn non_finite_count(&self) -> usize {
        self.non_finite
    }
}

impl Drop for HistoryWriter {
    fn drop(&mut self) {
        // Errors cannot be reported from drop; callers wanting them call `flush` first.
        let _ = self.writer.flush();
    }
}

/// Appends the shortest round-trip representation of `x` to `out` (see the module doc).
pub fn format_f64(x: f64, out: &mut String) {
    use std::fmt::Write;
    if x.is_nan() {
        out.push_str("nan");
    } else if x.is_infinite() {
        out.push_str(if x > 0.0 { "inf" } else { "-inf" });
    } else if x == 0.0 || (1e-5..1e16).contains(&x.abs()) {
        let _ = write!(out, "{x}");
    } else {
        let _ = write!(out, "{x:e}");
    }
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

#[cfg(test)]
mod tests {
    use super::format_f64;

    fn fmt(x: f64) -> String {
        let mut s = String::new();
        format_f64(x, &mut s);
        s
    }

    #[test]
    fn formats_are_plain_or_exponent() {
        assert_eq!(fmt(0.0), "0");
        assert_eq!(fmt(-0.0), "-0");
        assert_eq!(fmt(0.001), "0.001");
        assert_eq!(fmt(-12.5), "-12.5");
        assert_eq!(fmt(1.5e-9), "1.5e-9");
        assert_eq!(fmt(2e20), "2e20");
        assert_eq!(fmt(0.1 + 0.2), "0.30000000000000004");
        assert_eq!(fmt(f64::NAN), "nan");
        assert_eq!(fmt(f64::INFINITY), "inf");
        assert_eq!(fmt(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn formats_round_trip_bitwise() {
        // A deterministic spread over magnitudes, including subnormals and extremes.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f64::from_bits(x);
            if !v.is_finite() {
                continue;
            }
            let s = fmt(v);
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:e} written as {s}");
        }
        for v in [
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::MIN,
            1e-5,
            1e16 - 2.0,
        ] {
            let back: f64 = fmt(v).parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits());
        }
    }
}
