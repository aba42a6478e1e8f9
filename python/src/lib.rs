//! `nmm._nmm`: the compiled core of the `nmm` Python package (the pure-Python part,
//! `python/nmm/`, wraps it: DataFrames, temporary folders, studies).
//!
//! A [`Model`] keeps the model's TOML text, the folder relative file names resolve against
//! and the name of its source (a file, `<string>` or `<dict>`), together with the model the
//! library validated from them. Every change made from Python edits the text (a
//! `toml_edit` document, so the rest of the text keeps its layout and lines) and validates
//! it again with the library's own validation: a change that the file format refuses is
//! refused with the same one-line error, as `nmm.ModelError`, and leaves the model as it was.

use pyo3::create_exception;
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;
use toml_edit::{Array, ArrayOfTables, DocumentMut, InlineTable, Item, Table, Value};

create_exception!(
    nmm,
    ModelError,
    PyValueError,
    "A model the file format refuses: the same one-line message as `nmm check`/`nmm run`."
);
create_exception!(
    nmm,
    RunError,
    PyRuntimeError,
    "A run that stopped on an error (a step that did not converge, an output that could not be written); the outputs written so far are kept."
);

fn model_error(e: impl std::fmt::Display) -> PyErr {
    ModelError::new_err(one_line(&e.to_string()))
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A validated model: its TOML text, the folder its relative file names resolve against,
/// and the name of its source in error messages.
#[pyclass(module = "nmm")]
struct Model {
    text: String,
    base_dir: PathBuf,
    source: String,
    model: nmm::model::Model,
}

impl Model {
    fn build(text: String, base_dir: PathBuf, source: String) -> PyResult<Model> {
        let model =
            nmm::model::parse_model_named(&text, &base_dir, &source).map_err(model_error)?;
        Ok(Model {
            text,
            base_dir,
            source,
            model,
        })
    }

    fn document(&self) -> PyResult<DocumentMut> {
        self.text.parse::<DocumentMut>().map_err(model_error)
    }

    /// A new model: this one's text changed by `f`, validated again.
    fn edited(&self, f: impl FnOnce(&mut DocumentMut) -> PyResult<()>) -> PyResult<Model> {
        let mut doc = self.document()?;
        f(&mut doc)?;
        Model::build(doc.to_string(), self.base_dir.clone(), self.source.clone())
    }
}

/// One segment of a key path: a key, an index or a name (in an array of tables).
fn segments(path: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    if let Ok(s) = path.cast::<PyString>() {
        let s = s.to_cow()?;
        if s.is_empty() {
            return Err(PyKeyError::new_err("empty key path"));
        }
        return Ok(s.split('.').map(str::to_string).collect());
    }
    let items: Vec<Bound<'_, PyAny>> = if let Ok(t) = path.cast::<PyTuple>() {
        t.iter().collect()
    } else if let Ok(l) = path.cast::<PyList>() {
        l.iter().collect()
    } else {
        return Err(PyTypeError::new_err(
            "a key path is a string \"table.key\" or a tuple/list of keys, indices and names",
        ));
    };
    items
        .iter()
        .map(|i| {
            if i.cast::<PyInt>().is_ok() {
                Ok(i.extract::<i64>()?.to_string())
            } else {
                Ok(i.extract::<String>()?)
            }
        })
        .collect()
}

/// The index of the entry of an array of tables (or an inline array of inline tables)
/// picked by `seg`: an index from 0 (negative from the end) or the value of the entries'
/// `name`.
fn index_of(item: &Item, seg: &str, at: &str) -> PyResult<usize> {
    let names: Vec<Option<&str>> = match item {
        Item::ArrayOfTables(a) => a
            .iter()
            .map(|t| t.get("name").and_then(|n| n.as_str()))
            .collect(),
        Item::Value(Value::Array(a)) => a
            .iter()
            .map(|v| {
                v.as_inline_table()
                    .and_then(|t| t.get("name"))
                    .and_then(|n| n.as_str())
            })
            .collect(),
        _ => {
            return Err(PyKeyError::new_err(format!(
                "`{at}` is not an array of tables"
            )))
        }
    };
    let len = names.len();
    match seg.parse::<i64>() {
        Ok(i) => {
            let j = if i < 0 { len as i64 + i } else { i };
            if j < 0 || j as usize >= len {
                return Err(PyKeyError::new_err(format!(
                    "`{at}` has {len} entries, no entry {i}"
                )));
            }
            Ok(j as usize)
        }
        Err(_) => names
            .iter()
            .position(|n| *n == Some(seg))
            .ok_or_else(|| PyKeyError::new_err(format!("`{at}` has no entry named \"{seg}\""))),
    }
}

/// The entry of an array of tables picked by `seg` ([`index_of`]).
fn pick<'a>(item: &'a mut Item, seg: &str, at: &str) -> PyResult<&'a mut dyn toml_edit::TableLike> {
    let index = index_of(item, seg, at)?;
    match item {
        Item::ArrayOfTables(a) => Ok(a.get_mut(index).expect("index checked")),
        Item::Value(Value::Array(a)) => a
            .get_mut(index)
            .and_then(|v| v.as_inline_table_mut())
            .map(|t| t as &mut dyn toml_edit::TableLike)
            .ok_or_else(|| PyKeyError::new_err(format!("`{at}.{seg}` is not a table"))),
        _ => unreachable!("index_of checked the kind"),
    }
}

/// The table holding the last segment of `segs` (created on the way where missing) and
/// that last key.
fn parent<'a>(
    doc: &'a mut DocumentMut,
    segs: &'a [String],
) -> PyResult<(&'a mut dyn toml_edit::TableLike, &'a str)> {
    let (last, init) = segs.split_last().expect("non-empty path");
    let mut table: &mut dyn toml_edit::TableLike = doc.as_table_mut();
    let mut at = String::new();
    let mut i = 0;
    while i < init.len() {
        let seg = &init[i];
        if !at.is_empty() {
            at.push('.');
        }
        at.push_str(seg);
        let is_array = matches!(
            table.get(seg),
            Some(Item::ArrayOfTables(_)) | Some(Item::Value(Value::Array(_)))
        );
        if is_array {
            if i + 1 == init.len() {
                return Err(PyKeyError::new_err(format!(
                    "`{at}` is an array of tables: give an entry (index or name) and a key, e.g. `{at}.0.{last}`"
                )));
            }
            let next = &init[i + 1];
            let item = table.get_mut(seg).expect("present");
            table = pick(item, next, &at)?;
            at.push('.');
            at.push_str(next);
            i += 2;
            continue;
        }
        if table.get(seg).is_none() {
            table.insert(seg, Item::Table(Table::new()));
        }
        let item = table.get_mut(seg).expect("present");
        table = match item {
            Item::Table(t) => t,
            Item::Value(Value::InlineTable(t)) => t,
            _ => return Err(PyKeyError::new_err(format!("`{at}` is not a table"))),
        };
        i += 1;
    }
    Ok((table, last.as_str()))
}

/// A Python value as a TOML value: bool, int, float, str, a list/tuple of them, a dict.
fn to_value(v: &Bound<'_, PyAny>) -> PyResult<Value> {
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(Value::from(b.is_true()));
    }
    if v.cast::<PyInt>().is_ok() {
        return Ok(Value::from(v.extract::<i64>()?));
    }
    if let Ok(f) = v.cast::<PyFloat>() {
        return Ok(Value::from(f.value()));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(Value::from(s.to_cow()?.as_ref()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = InlineTable::new();
        for (k, x) in d.iter() {
            t.insert(&k.extract::<String>()?, to_value(&x)?);
        }
        return Ok(Value::InlineTable(t));
    }
    if v.cast::<PyList>().is_ok() || v.cast::<PyTuple>().is_ok() || v.hasattr("tolist")? {
        let seq = if v.hasattr("tolist")? {
            v.call_method0("tolist")?
        } else {
            v.clone()
        };
        if seq.cast::<PyList>().is_ok() || seq.cast::<PyTuple>().is_ok() {
            let mut a = Array::new();
            for x in seq.try_iter()? {
                a.push(to_value(&x?)?);
            }
            return Ok(Value::Array(a));
        }
        // a numpy scalar: tolist() gives a Python number
        return to_value(&seq);
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(Value::from(i));
    }
    if let Ok(f) = v.extract::<f64>() {
        return Ok(Value::from(f));
    }
    Err(PyTypeError::new_err(format!(
        "cannot write a {} into a model (bool, int, float, str, list, tuple or dict)",
        v.get_type().name()?
    )))
}

/// A dict as a TOML table (nested dicts as tables, lists of dicts as arrays of tables).
fn to_table(d: &Bound<'_, PyDict>) -> PyResult<Table> {
    let mut t = Table::new();
    for (k, v) in d.iter() {
        let key = k.extract::<String>()?;
        t.insert(&key, to_item(&v)?);
    }
    Ok(t)
}

fn to_item(v: &Bound<'_, PyAny>) -> PyResult<Item> {
    if let Ok(d) = v.cast::<PyDict>() {
        return Ok(Item::Table(to_table(d)?));
    }
    if let Ok(l) = v.cast::<PyList>() {
        if !l.is_empty() && l.iter().all(|x| x.cast::<PyDict>().is_ok()) {
            let mut a = ArrayOfTables::new();
            for x in l.iter() {
                a.push(to_table(x.cast::<PyDict>()?)?);
            }
            return Ok(Item::ArrayOfTables(a));
        }
    }
    Ok(Item::Value(to_value(v)?))
}

/// A dict of the given keys whose value is not None, then the extra keywords.
fn entry<'py, const N: usize>(
    pairs: [(&str, Option<Bound<'py, PyAny>>); N],
    extra: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let py = pairs
        .iter()
        .find_map(|(_, v)| v.as_ref().map(|v| v.py()))
        .expect("every entry has a required key");
    let dict = PyDict::new(py);
    for (k, v) in pairs {
        if let Some(v) = v {
            if !v.is_none() {
                dict.set_item(k, v)?;
            }
        }
    }
    if let Some(extra) = extra {
        for (k, v) in extra.iter() {
            dict.set_item(k, v)?;
        }
    }
    Ok(dict)
}

/// A TOML value as a Python object (tables as dicts).
fn value_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(value_to_py(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, value_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let json = py.import("json")?;
    json.call_method1("loads", (v.to_string(),))
}

fn apply_set(doc: &mut DocumentMut, segs: &[String], value: &Bound<'_, PyAny>) -> PyResult<()> {
    let (table, key) = parent(doc, segs)?;
    if value.is_none() {
        if table.remove(key).is_none() {
            return Err(PyKeyError::new_err(format!(
                "`{}` is not in the model",
                segs.join(".")
            )));
        }
        return Ok(());
    }
    // at the top level a dict is a table (`[base_motion]`) and a list of dicts an array of
    // tables; below it, an inline table or array (valid wherever the key is written)
    let item = if segs.len() == 1 {
        to_item(value)?
    } else {
        Item::Value(to_value(value)?)
    };
    match table.get_mut(key) {
        Some(Item::Value(old)) => {
            if let Item::Value(mut v) = item {
                // keep the key's place and the comments around the value
                *v.decor_mut() = old.decor().clone();
                *old = v;
            } else {
                table.insert(key, item);
            }
        }
        _ => {
            table.insert(key, item);
        }
    }
    Ok(())
}

#[pymethods]
impl Model {
    /// A model from TOML text; relative file names (a motion record) resolve against
    /// `base_dir`; errors name the source `<string>` (or `source`).
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = None, source = None))]
    fn from_toml(
        text: String,
        base_dir: Option<PathBuf>,
        source: Option<String>,
    ) -> PyResult<Model> {
        Model::build(
            text,
            base_dir.unwrap_or_else(|| PathBuf::from(".")),
            source.unwrap_or_else(|| "<string>".into()),
        )
    }

    /// A model file (errors name the file, as `nmm check` does).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Model> {
        let text = std::fs::read_to_string(&path).map_err(|e| {
            model_error(format!(
                "{}: cannot read the model file: {e}",
                path.display()
            ))
        })?;
        let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let dir = if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir
        };
        Model::build(text, dir, path.display().to_string())
    }

    /// A model from a dict laid out as the file (`{"analysis": {...}, "block": [{...}, ...]}`),
    /// validated as the file would be; errors name the source `<dict>`.
    #[staticmethod]
    #[pyo3(signature = (tables, base_dir = None))]
    fn from_dict(tables: &Bound<'_, PyDict>, base_dir: Option<PathBuf>) -> PyResult<Model> {
        let mut doc = DocumentMut::new();
        for (k, v) in tables.iter() {
            doc.insert(&k.extract::<String>()?, to_item(&v)?);
        }
        Model::build(
            doc.to_string(),
            base_dir.unwrap_or_else(|| PathBuf::from(".")),
            "<dict>".into(),
        )
    }

    /// Rebuild from the parts `__reduce__` gives (pickling, e.g. to a Dask worker).
    #[staticmethod]
    fn _from_parts(text: String, base_dir: PathBuf, source: String) -> PyResult<Model> {
        Model::build(text, base_dir, source)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let me = slf.borrow();
        let ctor = slf.get_type().getattr("_from_parts")?;
        let args = (me.text.clone(), me.base_dir.clone(), me.source.clone()).into_pyobject(py)?;
        PyTuple::new(py, [ctor, args.into_any()])
    }

    /// Sets `key_path` (e.g. `"analysis.dt"`, `"interface.0.friction_angle"`,
    /// `"material.rock.young"`, `("block", "slider", "fixed")`) to `value` (None removes the
    /// key) and validates the model again; a refused change raises `ModelError` and leaves
    /// the model as it was. Returns the model (calls chain).
    fn set<'py>(
        mut slf: PyRefMut<'py, Self>,
        key_path: &Bound<'py, PyAny>,
        value: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let segs = segments(key_path)?;
        let new = slf.edited(|doc| apply_set(doc, &segs, value))?;
        *slf = new;
        Ok(slf)
    }

    /// An independent copy.
    fn copy(&self) -> Model {
        Model {
            text: self.text.clone(),
            base_dir: self.base_dir.clone(),
            source: self.source.clone(),
            model: self.model.clone(),
        }
    }

    /// A new model with every `key_path: value` of `overrides` set, validated once at the end.
    fn with_overrides(&self, overrides: &Bound<'_, PyDict>) -> PyResult<Model> {
        self.edited(|doc| {
            for (k, v) in overrides.iter() {
                apply_set(doc, &segments(&k)?, &v)?;
            }
            Ok(())
        })
    }

    /// Adds one entry (a dict) to the array of tables `table` (`"block"`, `"material"`,
    /// `"interface"`, `"joint"`, `"joint_set"`, `"monitor"`, `"load"`, …) and validates the
    /// model again (a refused entry raises `ModelError`, the model stays as it was).
    fn add<'py>(
        mut slf: PyRefMut<'py, Self>,
        table: &str,
        entry: &Bound<'py, PyDict>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let entry = to_table(entry)?;
        let new = slf.edited(|doc| {
            let root = doc.as_table_mut();
            match root.get_mut(table) {
                None => {
                    let mut a = ArrayOfTables::new();
                    a.push(entry);
                    root.insert(table, Item::ArrayOfTables(a));
                }
                Some(Item::ArrayOfTables(a)) => a.push(entry),
                Some(Item::Value(Value::Array(a))) => {
                    a.push(Value::InlineTable(entry.into_inline_table()))
                }
                Some(_) => {
                    return Err(PyKeyError::new_err(format!(
                        "`{table}` is not an array of tables"
                    )))
                }
            }
            Ok(())
        })?;
        *slf = new;
        Ok(slf)
    }

    /// Adds a `[[material]]` (Pa, kg/m³; `plane` "strain" | "stress"; `damping` a dict, see
    /// docs/model-format.md).
    #[pyo3(signature = (name, density, young, poisson, plane = None, damping = None, **extra))]
    #[allow(clippy::too_many_arguments)]
    fn add_material<'py>(
        slf: PyRefMut<'py, Self>,
        name: Bound<'py, PyAny>,
        density: Bound<'py, PyAny>,
        young: Bound<'py, PyAny>,
        poisson: Bound<'py, PyAny>,
        plane: Option<Bound<'py, PyAny>>,
        damping: Option<Bound<'py, PyAny>>,
        extra: Option<Bound<'py, PyDict>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("name", Some(name)),
                ("density", Some(density)),
                ("young", Some(young)),
                ("poisson", Some(poisson)),
                ("plane", plane),
                ("damping", damping),
            ],
            extra,
        )?;
        Model::add(slf, "material", &e)
    }

    /// Adds a `[[block]]`: a simple polygon `[[x, y], ...]` of a material; `fixed` holds it.
    #[pyo3(signature = (name, material, vertices, fixed = None, **extra))]
    fn add_block<'py>(
        slf: PyRefMut<'py, Self>,
        name: Bound<'py, PyAny>,
        material: Bound<'py, PyAny>,
        vertices: Bound<'py, PyAny>,
        fixed: Option<Bound<'py, PyAny>>,
        extra: Option<Bound<'py, PyDict>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("name", Some(name)),
                ("material", Some(material)),
                ("vertices", Some(vertices)),
                ("fixed", fixed),
            ],
            extra,
        )?;
        Model::add(slf, "block", &e)
    }

    /// Adds an `[[interface]]`: the default (neither `blocks` nor `joint`), a block pair's
    /// or a joint's contact properties (degrees, Pa, N/m).
    #[pyo3(signature = (friction_angle, normal_penalty, shear_penalty, blocks = None, joint = None, cohesion = None, **extra))]
    #[allow(clippy::too_many_arguments)]
    fn add_interface<'py>(
        slf: PyRefMut<'py, Self>,
        friction_angle: Bound<'py, PyAny>,
        normal_penalty: Bound<'py, PyAny>,
        shear_penalty: Bound<'py, PyAny>,
        blocks: Option<Bound<'py, PyAny>>,
        joint: Option<Bound<'py, PyAny>>,
        cohesion: Option<Bound<'py, PyAny>>,
        extra: Option<Bound<'py, PyDict>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("blocks", blocks),
                ("joint", joint),
                ("friction_angle", Some(friction_angle)),
                ("cohesion", cohesion),
                ("normal_penalty", Some(normal_penalty)),
                ("shear_penalty", Some(shear_penalty)),
            ],
            extra,
        )?;
        Model::add(slf, "interface", &e)
    }

    /// Adds a `[[joint]]`: a polyline `[[x, y], ...]` cutting `blocks` (default: every block
    /// that is not fixed).
    #[pyo3(signature = (name, points, blocks = None, **extra))]
    fn add_joint<'py>(
        slf: PyRefMut<'py, Self>,
        name: Bound<'py, PyAny>,
        points: Bound<'py, PyAny>,
        blocks: Option<Bound<'py, PyAny>>,
        extra: Option<Bound<'py, PyDict>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("name", Some(name)),
                ("points", Some(points)),
                ("blocks", blocks),
            ],
            extra,
        )?;
        Model::add(slf, "joint", &e)
    }

    /// Adds a `[[joint_set]]`: parallel traces at `angle` (degrees) `spacing` apart through
    /// `origin`; `trace_length`/`bridge` and more keys as keywords.
    #[pyo3(signature = (name, angle, spacing, origin = None, blocks = None, **extra))]
    #[allow(clippy::too_many_arguments)]
    fn add_joint_set<'py>(
        slf: PyRefMut<'py, Self>,
        name: Bound<'py, PyAny>,
        angle: Bound<'py, PyAny>,
        spacing: Bound<'py, PyAny>,
        origin: Option<Bound<'py, PyAny>>,
        blocks: Option<Bound<'py, PyAny>>,
        extra: Option<Bound<'py, PyDict>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("name", Some(name)),
                ("angle", Some(angle)),
                ("spacing", Some(spacing)),
                ("origin", origin),
                ("blocks", blocks),
            ],
            extra,
        )?;
        Model::add(slf, "joint_set", &e)
    }

    /// Adds a `[[monitor]]`: a material `point` or an `interface` pair of blocks.
    #[pyo3(signature = (name, point = None, interface = None))]
    fn add_monitor<'py>(
        slf: PyRefMut<'py, Self>,
        name: Bound<'py, PyAny>,
        point: Option<Bound<'py, PyAny>>,
        interface: Option<Bound<'py, PyAny>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("name", Some(name)),
                ("point", point),
                ("interface", interface),
            ],
            None,
        )?;
        Model::add(slf, "monitor", &e)
    }

    /// Sets `[base_motion]` (replacing any): a `table` of rows `[t, ax, ay]`, or a record
    /// `file` (relative to `base_dir`) with `format`, `component` and `scale`.
    #[pyo3(signature = (table = None, file = None, format = None, component = None, scale = None))]
    fn set_base_motion<'py>(
        mut slf: PyRefMut<'py, Self>,
        table: Option<Bound<'py, PyAny>>,
        file: Option<Bound<'py, PyAny>>,
        format: Option<Bound<'py, PyAny>>,
        component: Option<Bound<'py, PyAny>>,
        scale: Option<Bound<'py, PyAny>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let e = entry(
            [
                ("table", table),
                ("file", file),
                ("format", format),
                ("component", component),
                ("scale", scale),
            ],
            None,
        )?;
        let t = to_table(&e)?;
        let new = slf.edited(|doc| {
            doc.as_table_mut().insert("base_motion", Item::Table(t));
            Ok(())
        })?;
        *slf = new;
        Ok(slf)
    }

    /// Removes the entry `index_or_name` of the array of tables `table` and validates the
    /// model again.
    fn remove<'py>(
        mut slf: PyRefMut<'py, Self>,
        table: &str,
        index_or_name: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let seg = segments(&PyTuple::new(index_or_name.py(), [index_or_name])?.into_any())?;
        let new = slf.edited(|doc| {
            let root = doc.as_table_mut();
            let item = root
                .get_mut(table)
                .ok_or_else(|| PyKeyError::new_err(format!("`{table}` is not in the model")))?;
            let idx = index_of(item, &seg[0], table)?;
            match item {
                Item::ArrayOfTables(a) => a.remove(idx),
                Item::Value(Value::Array(a)) => {
                    a.remove(idx);
                }
                _ => unreachable!(),
            }
            Ok(())
        })?;
        *slf = new;
        Ok(slf)
    }

    /// The value at `key_path` (tables as dicts).
    fn get<'py>(
        &self,
        py: Python<'py>,
        key_path: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let segs = segments(key_path)?;
        let root: toml::Table = toml::from_str(&self.text).map_err(model_error)?;
        let mut v = toml::Value::Table(root);
        let mut at = String::new();
        for s in &segs {
            if !at.is_empty() {
                at.push('.');
            }
            at.push_str(s);
            v = match v {
                toml::Value::Table(mut t) => t
                    .remove(s)
                    .ok_or_else(|| PyKeyError::new_err(format!("`{at}` is not in the model")))?,
                toml::Value::Array(a) => {
                    let found = match s.parse::<i64>() {
                        Ok(i) => {
                            let j = if i < 0 { a.len() as i64 + i } else { i };
                            (j >= 0).then(|| a.get(j as usize).cloned()).flatten()
                        }
                        Err(_) => a
                            .iter()
                            .find(|e| e.get("name").and_then(|n| n.as_str()) == Some(s.as_str()))
                            .cloned(),
                    };
                    found
                        .ok_or_else(|| PyKeyError::new_err(format!("`{at}` is not in the model")))?
                }
                _ => return Err(PyKeyError::new_err(format!("`{at}` is not in the model"))),
            };
        }
        value_to_py(py, &v)
    }

    /// The model as a dict laid out as the file.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let root: toml::Table = toml::from_str(&self.text).map_err(model_error)?;
        value_to_py(py, &toml::Value::Table(root))
    }

    /// The model's TOML text (every change made from Python included).
    fn to_toml(&self) -> String {
        self.text.clone()
    }

    /// The model's content in one canonical form (keys sorted, no comments or layout): two
    /// texts that mean the same model give the same string (studies hash it).
    fn canonical(&self) -> PyResult<String> {
        let root: toml::Table = toml::from_str(&self.text).map_err(model_error)?;
        toml::to_string(&root).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    /// The files the model reads (its motion record), resolved against `base_dir`.
    fn files(&self) -> PyResult<Vec<PathBuf>> {
        let root: toml::Table = toml::from_str(&self.text).map_err(model_error)?;
        Ok(root
            .get("base_motion")
            .and_then(|b| b.get("file"))
            .and_then(|f| f.as_str())
            .map(|f| vec![self.base_dir.join(f)])
            .unwrap_or_default())
    }

    /// The folder relative file names resolve against.
    #[getter]
    fn base_dir(&self) -> PathBuf {
        self.base_dir.clone()
    }

    /// The source named in errors: the file, `<string>` or `<dict>`.
    #[getter]
    fn source(&self) -> String {
        self.source.clone()
    }

    /// History columns, as history.csv has them.
    #[getter]
    fn history_columns(&self) -> Vec<String> {
        nmm::simulation::history_header(&self.model)
    }

    /// Monitor columns (those between `time` and `iterations`).
    #[getter]
    fn monitor_columns(&self) -> Vec<String> {
        nmm::simulation::history_columns(&self.model)
    }

    /// The model's warnings (a valid model likely to mislead), one line each.
    fn warnings(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let model = self.model.clone();
        let sim = py
            .detach(move || nmm::simulation::Simulation::new(model))
            .map_err(model_error)?;
        Ok(sim.warnings())
    }

    /// The blocks after cutting (pieces `NAME.k` of blocks cut by joints, small pieces
    /// merged), in block-id order (the ids of blocks.csv and the VTK `block` arrays), as a
    /// DataFrame made by `nmm._frames.blocks_table`.
    fn blocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = &self.model;
        let rows = PyList::empty(py);
        for b in &m.blocks {
            let row = PyDict::new(py);
            row.set_item("name", &b.name)?;
            row.set_item(
                "material",
                m.materials.get(b.material).map(|mat| mat.name.as_str()),
            )?;
            row.set_item("fixed", b.fixed)?;
            row.set_item("area", b.area())?;
            row.set_item("parent", b.parent.as_deref())?;
            row.set_item("polygon", f64_bytes(py, b.vertices.iter().flatten()))?;
            row.set_item(
                "joints",
                b.edge_joint
                    .iter()
                    .map(|j| j.map_or(-1, |j| j as i64))
                    .collect::<Vec<i64>>(),
            )?;
            rows.append(row)?;
        }
        let joints: Vec<&str> = m.joints.iter().map(|j| j.name.as_str()).collect();
        py.import("nmm._frames")?
            .call_method1("blocks_table", (rows, joints))
    }

    fn __repr__(&self) -> String {
        format!(
            "nmm.Model(source={:?}, blocks={}, steps={})",
            self.source,
            self.model.blocks.len(),
            self.model.analysis.steps
        )
    }
}

/// What `nmm check --json` prints for the model, as a dict.
#[pyfunction]
fn check<'py>(py: Python<'py>, model: &Bound<'py, Model>) -> PyResult<Bound<'py, PyAny>> {
    let m = model.borrow();
    let inner = m.model.clone();
    let source = m.source.clone();
    let v = py
        .detach(move || {
            nmm::simulation::Simulation::new(inner)
                .map(|sim| nmm::check::check_json(&sim, &source))
                .map_err(|e| format!("{source}: {e}"))
        })
        .map_err(model_error)?;
    json_to_py(py, &v)
}

/// The stop flags of the runs going on in this process ([`stop_all`]).
static RUNNING: std::sync::Mutex<Vec<std::sync::Weak<AtomicBool>>> =
    std::sync::Mutex::new(Vec::new());

/// Stops every run going on in this process cleanly after its current step, as Ctrl-C
/// stops one (a study stopped by Ctrl-C stops the runs of its in-process workers so).
/// Returns how many runs were asked to stop.
#[pyfunction]
fn stop_all() -> usize {
    let mut running = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
    running.retain(|w| w.strong_count() > 0);
    running
        .iter()
        .filter_map(|w| w.upgrade())
        .map(|f| f.store(true, Ordering::SeqCst))
        .count()
}

/// What the run shares with the thread that waits for it.
#[derive(Default)]
struct Shared {
    step: AtomicUsize,
    total: AtomicUsize,
    time_bits: AtomicU64,
}

struct Observer(Arc<Shared>);

impl nmm::simulation::RunObserver for Observer {
    fn start(&mut self, step: usize, total_steps: usize) {
        self.0.total.store(total_steps, Ordering::Relaxed);
        self.0.step.store(step, Ordering::Relaxed);
    }
    fn step_done(&mut self, step: usize, time: f64) {
        self.0.time_bits.store(time.to_bits(), Ordering::Relaxed);
        self.0.step.store(step, Ordering::Relaxed);
    }
}

/// Run `model` into `out` (as `nmm run`; VTK frames when `vtk`). The run computes on its own
/// thread without the GIL; this thread waits for it, checking for signals (Ctrl-C sets the
/// run's stop flag: it stops cleanly after the current step, as the CLI's does) and calling
/// `progress(step, total_steps, time)` about every 0.1 s. Returns (summary.json as a dict,
/// interrupted); raises `ModelError` for a model that cannot be discretised and `RunError`
/// for a run that stopped on an error (outputs kept).
///
/// `checkpoint_every`: also write a checkpoint every N steps (as `--checkpoint-every`);
/// `start_from`: a checkpoint file of another run to start from (as `--from`).
#[pyfunction]
#[pyo3(signature = (model, out, vtk = true, progress = None, threads = None, checkpoint_every = 0, start_from = None))]
#[allow(clippy::too_many_arguments)]
fn run_into<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    out: PathBuf,
    vtk: bool,
    progress: Option<Bound<'py, PyAny>>,
    threads: Option<usize>,
    checkpoint_every: usize,
    start_from: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyAny>, bool)> {
    let m = model.borrow();
    let inner = m.model.clone();
    let start = match start_from {
        None => nmm::simulation::Start::Fresh,
        Some(c) => nmm::simulation::branch_start(&inner, &m.source, &c)
            .map_err(|e| PyValueError::new_err(one_line(&e)))?,
    };
    // the model file, for summary.json and checkpoints (`nmm resume` reads it again), only
    // while it is what this model was made from (not after changes made in Python)
    let model_path = (m.source != "<string>" && m.source != "<dict>")
        .then(|| PathBuf::from(&m.source))
        .filter(|p| std::fs::read_to_string(p).is_ok_and(|t| t == m.text));
    let opts = nmm::simulation::RunOptions {
        interrupt: Some(Arc::new(AtomicBool::new(false))),
        vtk,
        model_path,
        threads,
        checkpoint_every,
        start,
        ..nmm::simulation::RunOptions::new()
    };
    let source = m.source.clone();
    drop(m);
    drive(py, inner, &source, out, opts, progress)
}

/// Resume the run in `out` from its latest checkpoint (as `nmm resume`), its model read
/// again from the file it was made from. Returns and raises as [`run_into`]; a folder
/// without a checkpoint, or a model file changed since, raises `ValueError` (one line).
#[pyfunction]
#[pyo3(signature = (out, progress = None, threads = None))]
fn resume_into<'py>(
    py: Python<'py>,
    out: PathBuf,
    progress: Option<Bound<'py, PyAny>>,
    threads: Option<usize>,
) -> PyResult<(Bound<'py, PyAny>, bool)> {
    let (model, path, mut opts) =
        nmm::simulation::resume_start(&out).map_err(|e| PyValueError::new_err(one_line(&e)))?;
    opts.threads = threads;
    opts.interrupt = Some(Arc::new(AtomicBool::new(false)));
    drive(py, model, &path.display().to_string(), out, opts, progress)
}

/// Runs `inner` into `out` with `opts` on a thread of its own (see [`run_into`]).
fn drive<'py>(
    py: Python<'py>,
    inner: nmm::model::Model,
    source: &str,
    out: PathBuf,
    opts: nmm::simulation::RunOptions,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, bool)> {
    let stop = opts.interrupt.clone().expect("set by the callers");
    {
        let mut running = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
        running.retain(|w| w.strong_count() > 0);
        running.push(Arc::downgrade(&stop));
    }
    let shared = Arc::new(Shared::default());
    let (tx, rx) = mpsc::channel();
    // the receiver is shared with the GIL-free waits (a `Receiver` is `Send`, not `Sync`)
    let rx = std::sync::Mutex::new(rx);
    let worker_shared = shared.clone();
    let worker_out = out.clone();
    let handle = std::thread::Builder::new()
        .name("nmm-run".into())
        .spawn(move || {
            let mut obs = Observer(worker_shared);
            let r = nmm::simulation::run_observed(inner, &worker_out, &opts, &mut obs);
            let _ = tx.send(r);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the run's thread: {e}")))?;
    let mut signal: Option<PyErr> = None;
    let mut last_step = usize::MAX;
    let mut callback_failed = false;
    let result = loop {
        match py.detach(|| {
            rx.lock()
                .expect("only this thread locks it")
                .recv_timeout(Duration::from_millis(100))
        }) {
            Ok(r) => break r,
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let _ = handle.join();
                return Err(PyRuntimeError::new_err(
                    "the run's thread ended without a result",
                ));
            }
        }
        if signal.is_none() {
            if let Err(e) = py.check_signals() {
                stop.store(true, Ordering::SeqCst);
                signal = Some(e);
            }
        }
        if let (Some(cb), None) = (&progress, &signal) {
            let step = shared.step.load(Ordering::Relaxed);
            if step != last_step {
                last_step = step;
                let time = f64::from_bits(shared.time_bits.load(Ordering::Relaxed));
                if let Err(e) = cb.call1((step, shared.total.load(Ordering::Relaxed), time)) {
                    // the callback's error stops the run (cleanly) and is raised after it
                    stop.store(true, Ordering::SeqCst);
                    signal = Some(e);
                    callback_failed = true;
                }
            }
        }
    };
    let _ = handle.join();
    if callback_failed {
        return Err(signal.expect("set with the flag"));
    }
    if let (Some(cb), None) = (&progress, &signal) {
        if let Ok(s) = &result {
            cb.call1((s.steps, shared.total.load(Ordering::Relaxed), s.time))?;
        }
    }
    match result {
        Ok(summary) => {
            let interrupted = summary.interrupted;
            if let Some(e) = signal {
                if !interrupted {
                    // the run finished in the same step as the signal: raise it as Python would
                    return Err(e);
                }
            }
            Ok((json_to_py(py, &summary.to_json())?, interrupted))
        }
        // a model that cannot be discretised: named as `nmm check` names it
        Err(nmm::simulation::RunError::Setup(e)) => Err(model_error(format!("{source}: {e}"))),
        Err(e) => Err(RunError::new_err(one_line(&e.to_string()))),
    }
}

/// f64 values as native-endian bytes (`numpy.frombuffer(b, dtype=float)` reads them).
fn f64_bytes<'a, 'py>(
    py: Python<'py>,
    values: impl IntoIterator<Item = &'a f64>,
) -> Bound<'py, PyBytes> {
    let bytes: Vec<u8> = values.into_iter().flat_map(|v| v.to_ne_bytes()).collect();
    PyBytes::new(py, &bytes)
}

/// A grid read back from a `.vtu` (`nmm::output::vtk::ReadGrid`) as a dict: `points`
/// (x, y as f64 bytes), `cell_sizes` (points per cell), `connectivity` (point indices, in
/// cell order), `point_data` and `cell_data` (name → (components, f64 bytes)),
/// `field_strings` (name → list of str).
fn grid_to_py<'py>(
    py: Python<'py>,
    g: &nmm::output::vtk::ReadGrid,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("points", f64_bytes(py, g.points.iter().flatten()))?;
    d.set_item(
        "cell_sizes",
        g.cells.iter().map(Vec::len).collect::<Vec<usize>>(),
    )?;
    d.set_item(
        "connectivity",
        g.cells.iter().flatten().copied().collect::<Vec<usize>>(),
    )?;
    for (key, data) in [("point_data", &g.point_data), ("cell_data", &g.cell_data)] {
        let arrays = PyDict::new(py);
        let mut names: Vec<&String> = data.keys().collect();
        names.sort();
        for name in names {
            let (c, v) = &data[name];
            arrays.set_item(name, (*c, f64_bytes(py, v)))?;
        }
        d.set_item(key, arrays)?;
    }
    let strings = PyDict::new(py);
    for (name, v) in &g.field_strings {
        strings.set_item(name, v.clone())?;
    }
    d.set_item("field_strings", strings)?;
    Ok(d)
}

fn field_of(name: &str) -> PyResult<nmm::picture::Field> {
    nmm::picture::Field::parse(name)
        .map_err(|e| PyValueError::new_err(e.trim_start_matches("--").to_string()))
}

/// The frames of the run in `out` (its `blocks.pvd`): a list of (time, file, step).
#[pyfunction]
fn run_frames(out: PathBuf) -> PyResult<Vec<(f64, String, Option<usize>)>> {
    let frames = nmm::picture::run_frames(&out).map_err(PyValueError::new_err)?;
    Ok(frames
        .into_iter()
        .map(|(t, f)| {
            let step = nmm::picture::step_of(&f);
            (t, f, step)
        })
        .collect())
}

/// Frame `index` of the run in `out`, read by the library's VTK reader
/// (`nmm::picture::read_frame`, as `nmm plot RUN_DIR`): a dict with `index`, `time`,
/// `step`, `file`, `blocks` and `contacts` (grids, see `grid_to_py`; `contacts` None when
/// the step has no contact frame), `fields` (the values `nmm plot` colours the elements by:
/// `u`, `ux`, `uy`, `sxx`, `syy`, `sxy`, f64 bytes) and `outlines` (per block id, its
/// deformed outlines, f64 bytes each, the largest first).
#[pyfunction]
fn read_frame<'py>(py: Python<'py>, out: PathBuf, index: usize) -> PyResult<Bound<'py, PyDict>> {
    let (frame, values, outlines) = py
        .detach(move || -> Result<_, String> {
            let frame = nmm::picture::read_frame(&out, index)?;
            use nmm::picture::Field;
            let mut values = Vec::new();
            for (name, f) in [
                ("u", Field::U),
                ("ux", Field::Ux),
                ("uy", Field::Uy),
                ("sxx", Field::Sxx),
                ("syy", Field::Syy),
                ("sxy", Field::Sxy),
            ] {
                values.push((name, nmm::picture::cell_values(&frame.blocks, f)?));
            }
            let outlines = nmm::picture::block_outlines(&frame.blocks);
            Ok((frame, values, outlines))
        })
        .map_err(PyValueError::new_err)?;
    let d = PyDict::new(py);
    d.set_item("index", frame.index)?;
    d.set_item("time", frame.time)?;
    d.set_item("step", frame.step)?;
    d.set_item("file", &frame.file)?;
    d.set_item("blocks", grid_to_py(py, &frame.blocks)?)?;
    d.set_item(
        "contacts",
        frame
            .contacts
            .as_ref()
            .map(|c| grid_to_py(py, c))
            .transpose()?,
    )?;
    let fields = PyDict::new(py);
    for (name, v) in &values {
        fields.set_item(*name, f64_bytes(py, v))?;
    }
    d.set_item("fields", fields)?;
    let blocks = PyList::empty(py);
    for loops in &outlines {
        let l = PyList::empty(py);
        for ring in loops {
            l.append(f64_bytes(py, ring.iter().flatten()))?;
        }
        blocks.append(l)?;
    }
    d.set_item("outlines", blocks)?;
    Ok(d)
}

/// How `nmm plot` labels `field` (`u`, `ux`, `uy`, `sxx`, `syy`, `sxy`) for values up to
/// `max` in magnitude: (its name, the factor values are divided by, the unit).
#[pyfunction]
fn field_unit(field: &str, max: f64) -> PyResult<(&'static str, f64, &'static str)> {
    let f = field_of(field)?;
    let (factor, unit) = nmm::picture::unit(f, max);
    Ok((f.name(), factor, unit))
}

/// The library's version (summary.json's `nmm_version`).
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _nmm(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<Model>()?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(run_into, m)?)?;
    m.add_function(wrap_pyfunction!(resume_into, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(stop_all, m)?)?;
    m.add_function(wrap_pyfunction!(run_frames, m)?)?;
    m.add_function(wrap_pyfunction!(read_frame, m)?)?;
    m.add_function(wrap_pyfunction!(field_unit, m)?)?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("RunError", py.get_type::<RunError>())?;
    Ok(())
}
