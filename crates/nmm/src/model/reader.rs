//! Typed access to the parsed TOML tree with error context.
//!
//! Every value read from the model file goes through this module, so that each
//! error names its place (`[analysis]`, `[[block]] "slider"`, …) and key, and
//! every number is checked to be finite (TOML allows `nan` and `inf`
//! literals) and every coordinate to be within [`MAX_COORD`].

use super::ModelError;
use crate::geometry::Vec2;
use toml::{Table, Value};

pub(crate) type R<T> = Result<T, ModelError>;

/// Largest accepted coordinate magnitude (m): keeps every geometric
/// computation (areas, squared distances) far from floating-point overflow.
pub const MAX_COORD: f64 = 1.0e12;

/// Make a one-line error (any line break in `s` becomes a space).
pub(crate) fn error(s: impl AsRef<str>) -> ModelError {
    ModelError(s.as_ref().split_whitespace().collect::<Vec<_>>().join(" "))
}

/// Short description of a value for messages: `string "abc"`, `float NaN`, `array` …
pub(crate) fn describe(v: &Value) -> String {
    match v {
        Value::String(s) => {
            let short: String = s.chars().take(40).collect();
            if short.len() < s.len() {
                format!("string {short:?}…")
            } else {
                format!("string {short:?}")
            }
        }
        Value::Integer(i) => format!("integer {i}"),
        Value::Float(f) => format!("float {}", fmt_num(*f)),
        Value::Boolean(b) => format!("boolean {b}"),
        Value::Datetime(_) => "a date-time".into(),
        Value::Array(a) => format!("an array of {} items", a.len()),
        Value::Table(_) => "a table".into(),
    }
}

/// Numbers in messages: `NaN`, `inf`, `-inf` or Rust's shortest round-trip form.
pub(crate) fn fmt_num(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else {
        format!("{x}")
    }
}

pub(crate) fn fmt_point(p: Vec2) -> String {
    format!("[{},{}]", fmt_num(p[0]), fmt_num(p[1]))
}

/// A finite number (TOML integer or float).
pub(crate) fn number(v: &Value) -> Result<f64, String> {
    match v {
        Value::Integer(i) => Ok(*i as f64),
        Value::Float(f) if f.is_nan() => Err("NaN is not allowed".into()),
        Value::Float(f) if f.is_infinite() => {
            Err(format!("infinite values are not allowed, got {f}"))
        }
        Value::Float(f) => Ok(*f),
        other => Err(format!("expected a number, got {}", describe(other))),
    }
}

/// An integer (a float with an integral value is accepted).
pub(crate) fn integer(v: &Value) -> Result<i64, String> {
    match v {
        Value::Integer(i) => Ok(*i),
        Value::Float(f) if f.is_finite() && f.fract() == 0.0 && f.abs() < 9.0e15 => Ok(*f as i64),
        Value::Float(f) => Err(format!("expected an integer, got {}", fmt_num(*f))),
        other => Err(format!("expected an integer, got {}", describe(other))),
    }
}

pub(crate) fn string(v: &Value) -> Result<&str, String> {
    match v {
        Value::String(s) => Ok(s),
        other => Err(format!("expected a string, got {}", describe(other))),
    }
}

pub(crate) fn boolean(v: &Value) -> Result<bool, String> {
    match v {
        Value::Boolean(b) => Ok(*b),
        other => Err(format!("expected true or false, got {}", describe(other))),
    }
}

pub(crate) fn array(v: &Value) -> Result<&[Value], String> {
    match v {
        Value::Array(a) => Ok(a),
        other => Err(format!("expected an array, got {}", describe(other))),
    }
}

/// A pair `[a, b]` of finite numbers.
pub(crate) fn pair(v: &Value) -> Result<Vec2, String> {
    let a = array(v).map_err(|_| format!("expected a pair [x, y], got {}", describe(v)))?;
    match a {
        [x, y] => Ok([number(x)?, number(y)?]),
        _ => Err(format!("expected a pair [x, y], got {} items", a.len())),
    }
}

/// A point `[x, y]` with |x|, |y| ≤ [`MAX_COORD`].
pub(crate) fn point(v: &Value) -> Result<Vec2, String> {
    let p = pair(v)?;
    if p.iter().any(|c| c.abs() > MAX_COORD) {
        return Err(format!(
            "coordinate out of range (|x|, |y| ≤ {MAX_COORD:e} m) in {}",
            fmt_point(p)
        ));
    }
    Ok(p)
}

/// A list of points `[[x, y], …]` (errors name the point, counting from 1).
pub(crate) fn points(v: &Value) -> Result<Vec<Vec2>, String> {
    array(v)?
        .iter()
        .enumerate()
        .map(|(i, p)| point(p).map_err(|e| format!("point {}: {e}", i + 1)))
        .collect()
}

/// A segment `[[x, y], [x, y]]`.
pub(crate) fn segment(v: &Value) -> Result<(Vec2, Vec2), String> {
    let a = array(v)
        .map_err(|_| format!("expected a segment [[x, y], [x, y]], got {}", describe(v)))?;
    match a {
        [p, q] => Ok((point(p)?, point(q)?)),
        _ => Err(format!(
            "expected a segment [[x, y], [x, y]], got {} items",
            a.len()
        )),
    }
}

/// A TOML table being read, with its place in the file for error messages.
pub(crate) struct Fields<'a> {
    place: String,
    table: &'a Table,
    /// Where the table is written: (document, top-level key, index in its array).
    at: Option<(&'a super::lines::Doc<'a>, &'static str, Option<usize>)>,
    /// A table inside the top-level table (`[base_motion.x]`): its key there.
    sub: Option<&'static str>,
}

impl<'a> Fields<'a> {
    pub fn new(place: impl Into<String>, table: &'a Table) -> Self {
        Fields {
            place: place.into(),
            table,
            at: None,
            sub: None,
        }
    }

    /// This is the table `sub` inside the located top-level table.
    pub fn within(mut self, sub: &'static str) -> Self {
        self.sub = Some(sub);
        self
    }

    /// Errors about this table will name its line in `doc`.
    pub fn located(
        mut self,
        doc: &'a super::lines::Doc<'a>,
        top: &'static str,
        index: Option<usize>,
    ) -> Self {
        self.at = Some((doc, top, index));
        self
    }

    /// ` (FILE, line N)` of `key` (or of the table's header), or nothing.
    fn line(&self, key: Option<&str>) -> String {
        match (self.at, self.sub) {
            (Some((doc, top, _)), Some(sub)) => doc.at_sub(top, sub, key),
            (Some((doc, top, index)), None) => doc.at(top, index, key),
            (None, _) => String::new(),
        }
    }

    pub fn set_place(&mut self, place: impl Into<String>) {
        self.place = place.into();
    }

    /// Refuse any key not in `allowed`.
    pub fn deny_unknown(&self, allowed: &[&str]) -> R<()> {
        match self.table.keys().find(|k| !allowed.contains(&k.as_str())) {
            Some(k) => Err(error(format!(
                "{}: unknown key `{}` (allowed: {}){}",
                self.place,
                k.escape_debug(),
                allowed.join(", "),
                self.line(Some(k))
            ))),
            None => Ok(()),
        }
    }

    /// An error about this table as a whole.
    pub fn fail(&self, msg: impl std::fmt::Display) -> ModelError {
        error(format!("{}: {msg}{}", self.place, self.line(None)))
    }

    /// An error about one key.
    pub fn err(&self, key: &str, msg: impl std::fmt::Display) -> ModelError {
        // a missing key is reported at its table's header
        let line = self.line(Some(key).filter(|k| self.table.contains_key(*k)));
        error(format!("{}: key `{key}`: {msg}{line}", self.place))
    }

    pub fn has(&self, key: &str) -> bool {
        self.table.contains_key(key)
    }

    /// A required key converted by `f`.
    pub fn req<T>(&self, key: &str, f: impl FnOnce(&'a Value) -> Result<T, String>) -> R<T> {
        match self.table.get(key) {
            Some(v) => f(v).map_err(|e| self.err(key, e)),
            None => Err(self.err(key, "missing (required)")),
        }
    }

    /// An optional key converted by `f`.
    pub fn opt<T>(
        &self,
        key: &str,
        f: impl FnOnce(&'a Value) -> Result<T, String>,
    ) -> R<Option<T>> {
        match self.table.get(key) {
            Some(v) => f(v).map(Some).map_err(|e| self.err(key, e)),
            None => Ok(None),
        }
    }

    /// A name: a non-empty string.
    pub fn name(&self, key: &str) -> R<String> {
        let s = self.req(key, string)?;
        if s.trim().is_empty() {
            return Err(self.err(key, "must not be empty"));
        }
        Ok(s.to_string())
    }
}

/// A single top-level table such as `[analysis]` (`None` if absent).
pub(crate) fn table<'a>(root: &'a super::lines::Doc<'a>, key: &str) -> R<Option<&'a Table>> {
    match root.get(key) {
        None => Ok(None),
        Some(Value::Table(t)) => Ok(Some(t)),
        Some(Value::Array(_)) => Err(error(format!(
            "[{key}]: must be a single table (write [{key}], not [[{key}]]){}",
            root.at_top(key)
        ))),
        Some(other) => Err(error(format!(
            "[{key}]: must be a table, got {}{}",
            describe(other),
            root.at_top(key)
        ))),
    }
}

/// A top-level array of tables such as `[[block]]` (empty if absent).
pub(crate) fn array_of_tables<'a>(root: &'a super::lines::Doc<'a>, key: &str) -> R<Vec<&'a Table>> {
    match root.get(key) {
        None => Ok(Vec::new()),
        Some(Value::Array(items)) => items
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                Value::Table(t) => Ok(t),
                other => Err(error(format!(
                    "[[{key}]] #{}: must be a table, got {}{}",
                    i + 1,
                    describe(other),
                    root.at_top(key)
                ))),
            })
            .collect(),
        Some(Value::Table(_)) => Err(error(format!(
            "[[{key}]]: must be an array of tables (write [[{key}]], not [{key}]){}",
            root.at_top(key)
        ))),
        Some(other) => Err(error(format!(
            "[[{key}]]: must be an array of tables, got {}{}",
            describe(other),
            root.at_top(key)
        ))),
    }
}

/// Turn a TOML syntax error into one line: `SOURCE: TOML syntax error at line L, column C: MESSAGE`.
pub(crate) fn syntax_error(source: &str, text: &str, e: &toml::de::Error) -> ModelError {
    let msg = e
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    match e.span().and_then(|s| text.get(..s.start)) {
        Some(before) => {
            let line = before.matches('\n').count() + 1;
            let line_start = before.rfind('\n').map_or(0, |i| i + 1);
            let column = before.get(line_start..).map_or(0, |l| l.chars().count()) + 1;
            error(format!(
                "{source}: TOML syntax error at line {line}, column {column}: {msg}"
            ))
        }
        None => error(format!("{source}: TOML syntax error: {msg}")),
    }
}
