//! VTK XML unstructured grids (`.vtu`) and their time collections (`.pvd`), for ParaView.
//!
//! Owns the file format only: a [`Grid`] is plain data (points, cells, arrays) that the
//! simulation fills; nothing here knows about blocks or contacts.
//!
//! # Conventions
//! * Points are 2-D; every point is written with `z = 0` (VTK points always have 3
//!   coordinates).
//! * Cell kinds and their VTK type codes: [`CellKind::Vertex`] = 1 (one point),
//!   [`CellKind::Line`] = 3 (two points), [`CellKind::Polygon`] = 7 (three or more points, in
//!   order around the boundary, counter-clockwise by the project's convention).
//! * A data array holds `n_tuples × components` values, tuple after tuple. A 2-component array
//!   flagged as a vector ([`DataArray::vector2`]) is written with 3 components, `z = 0`, so
//!   that ParaView treats it as a vector (glyphs, "Warp By Vector"). Other multi-component
//!   arrays (e.g. a plane stress `σxx, σyy, σxy`) carry their component names as the VTK
//!   attributes `ComponentName0…`, shown by ParaView instead of `0, 1, 2`.
//!
//! # Encoding (VTK file format, "XML file formats", `format="binary"` inline data)
//! The file header is `<VTKFile type="UnstructuredGrid" version="1.0"
//! byte_order="LittleEndian" header_type="UInt64">`. With [`Encoding::Binary`] (the default)
//! each `DataArray` body is the base64 encoding (standard alphabet, padded) of one stream
//! `[n_bytes: u64 little-endian][raw little-endian values]`, where `n_bytes` is the length of
//! the raw values in bytes (no compression). With [`Encoding::Ascii`] the values are written
//! as text, shortest round-trip decimals, separated by spaces.
//!
//! Cells are described by `connectivity` (Int64, point indices of all cells concatenated),
//! `offsets` (Int64, for each cell the index in `connectivity` one past its last point) and
//! `types` (UInt8, the type codes above). An empty grid (no points, no cells) is valid VTK:
//! its arrays are empty, as VTK itself writes an empty grid, and VTK's reader reads it. (meshio
//! 5.3 cannot read any unstructured grid without cells, VTK's own included; that is why the run
//! driver omits contact frames without contacts.)
//!
//! # Field data
//! Arrays of strings for the whole grid ([`FieldStrings`], e.g. block names) go in
//! `<FieldData>` before the `<Piece>`, as one `UInt8` `DataArray` of `NumberOfTuples` bytes:
//! every string's UTF-8 bytes followed by a 0 byte (in Python:
//! `bytes(a).decode().split("\0")[:-1]`). Not VTK's `type="String"` array: VTK and ParaView read
//! that, but meshio 5.3 refuses the whole file over it.
//!
//! # Collections
//! [`PvdWriter`] keeps the list of `(time, file)` frames and rewrites the whole `.pvd` after
//! each [`PvdWriter::add`], through a temporary file renamed over the old one, so that the
//! collection on disk is always complete and valid even if the run is interrupted. Write a
//! frame's `.vtu` first, then add it: the collection then never names a half-written frame.

use base64::Engine;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// The kind of a cell, with its VTK type code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellKind {
    /// One point (VTK_VERTEX = 1).
    Vertex,
    /// Two points (VTK_LINE = 3).
    Line,
    /// Three or more points around a boundary (VTK_POLYGON = 7).
    Polygon,
}

impl CellKind {
    /// The VTK cell type code.
    pub fn vtk_type(self) -> u8 {
        match self {
            CellKind::Vertex => 1,
            CellKind::Line => 3,
            CellKind::Polygon => 7,
        }
    }

    fn accepts(self, n: usize) -> bool {
        match self {
            CellKind::Vertex => n == 1,
            CellKind::Line => n == 2,
            CellKind::Polygon => n >= 3,
        }
    }
}

/// One cell: its kind and the indices of its points in [`Grid::points`].
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    pub kind: CellKind,
    pub points: Vec<usize>,
}

impl Cell {
    pub fn vertex(p: usize) -> Self {
        Self {
            kind: CellKind::Vertex,
            points: vec![p],
        }
    }
    pub fn line(a: usize, b: usize) -> Self {
        Self {
            kind: CellKind::Line,
            points: vec![a, b],
        }
    }
    pub fn polygon(points: Vec<usize>) -> Self {
        Self {
            kind: CellKind::Polygon,
            points,
        }
    }
}

/// The values of a data array.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Float64(Vec<f64>),
    Int32(Vec<i32>),
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Float64(v) => v.len(),
            Values::Int32(v) => v.len(),
        }
    }
}

/// A named array attached to the points or to the cells of a [`Grid`].
#[derive(Clone, Debug, PartialEq)]
pub struct DataArray {
    /// Name shown by ParaView; unique among the point (or cell) arrays of a grid.
    pub name: String,
    /// Values per tuple in `values` (1 to 9).
    pub components: usize,
    /// Write a 2-component array as a 3-component vector with `z = 0`.
    pub vector2: bool,
    /// Optional names of the components (empty, or one per component as stored).
    pub component_names: Vec<String>,
    pub values: Values,
}

impl DataArray {
    /// One `f64` per point or cell.
    pub fn scalars(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            components: 1,
            vector2: false,
            component_names: Vec::new(),
            values: Values::Float64(values),
        }
    }

    /// A 2-D vector per point or cell (`x0, y0, x1, y1, …`), written with `z = 0`.
    pub fn vector2(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            components: 2,
            vector2: true,
            component_names: Vec::new(),
            values: Values::Float64(values),
        }
    }

    /// `component_names.len()` values per point or cell, named (e.g. `sxx, syy, sxy`).
    pub fn named_components(
        name: impl Into<String>,
        component_names: &[&str],
        values: Vec<f64>,
    ) -> Self {
        Self {
            name: name.into(),
            components: component_names.len(),
            vector2: false,
            component_names: component_names.iter().map(|s| s.to_string()).collect(),
            values: Values::Float64(values),
        }
    }

    /// One `i32` per point or cell (block id, contact state, …).
    pub fn int32(name: impl Into<String>, values: Vec<i32>) -> Self {
        Self {
            name: name.into(),
            components: 1,
            vector2: false,
            component_names: Vec::new(),
            values: Values::Int32(values),
        }
    }

    /// Number of components as written to the file.
    pub fn written_components(&self) -> usize {
        if self.vector2 {
            3
        } else {
            self.components
        }
    }
}

/// A named array of strings that belongs to the whole grid (VTK field data), e.g. the block
/// names that a cell array of block ids refers to.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldStrings {
    /// Name shown by ParaView; unique among the grid's field arrays.
    pub name: String,
    /// The strings, which must not contain a NUL character.
    pub values: Vec<String>,
}

impl FieldStrings {
    pub fn new(name: impl Into<String>, values: Vec<String>) -> Self {
        Self {
            name: name.into(),
            values,
        }
    }
}

/// An unstructured grid: 2-D points, cells over them, arrays on points and cells, and
/// string arrays for the whole grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Grid {
    pub points: Vec<[f64; 2]>,
    pub cells: Vec<Cell>,
    pub point_data: Vec<DataArray>,
    pub cell_data: Vec<DataArray>,
    pub field_data: Vec<FieldStrings>,
}

/// How data array bodies are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// Inline base64 of `[u64 byte count][little-endian values]` (compact, exact).
    #[default]
    Binary,
    /// Space-separated text, shortest round-trip decimals (readable, larger). VTK's text
    /// reader does not parse `nan`/`inf`: use [`Encoding::Binary`] for data that may hold
    /// non-finite values.
    Ascii,
}

/// Writes `grid` to `path` as a VTK XML unstructured grid, base64 binary.
pub fn write_vtu(path: &Path, grid: &Grid) -> io::Result<()> {
    write_vtu_with(path, grid, Encoding::Binary)
}

/// Writes `grid` to `path` with the chosen encoding. The grid is checked first (indices in
/// range, point counts per cell kind, array lengths, names); nothing is written if it is
/// invalid.
pub fn write_vtu_with(path: &Path, grid: &Grid, encoding: Encoding) -> io::Result<()> {
    validate(grid)?;
    let mut w = BufWriter::new(File::create(path)?);
    write_valid_grid(&mut w, grid, encoding)?;
    w.flush()
}

/// Writes `grid` as VTK XML to any writer (see [`write_vtu_with`]).
pub fn write_grid<W: Write>(w: &mut W, grid: &Grid, encoding: Encoding) -> io::Result<()> {
    validate(grid)?;
    write_valid_grid(w, grid, encoding)
}

fn write_valid_grid<W: Write>(w: &mut W, grid: &Grid, encoding: Encoding) -> io::Result<()> {
    let n_points = grid.points.len();
    let n_cells = grid.cells.len();
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    if !grid.field_data.is_empty() {
        writeln!(w, "    <FieldData>")?;
        for a in &grid.field_data {
            write_strings(w, a, encoding)?;
        }
        writeln!(w, "    </FieldData>")?;
    }
    writeln!(
        w,
        r#"    <Piece NumberOfPoints="{n_points}" NumberOfCells="{n_cells}">"#
    )?;

    writeln!(w, "      <PointData>")?;
    for a in &grid.point_data {
        write_data_array(w, a, encoding)?;
    }
    writeln!(w, "      </PointData>")?;
    writeln!(w, "      <CellData>")?;
    for a in &grid.cell_data {
        write_data_array(w, a, encoding)?;
    }
    writeln!(w, "      </CellData>")?;

    writeln!(w, "      <Points>")?;
    let mut xyz = grid.points.iter().flat_map(|p| [p[0], p[1], 0.0]);
    write_raw_array(
        w,
        "Points",
        "Float64",
        3,
        &[],
        encoding,
        Raw::F64(&mut xyz),
        3 * n_points,
    )?;
    writeln!(w, "      </Points>")?;

    writeln!(w, "      <Cells>")?;
    let n_conn: usize = grid.cells.iter().map(|c| c.points.len()).sum();
    let mut conn = grid
        .cells
        .iter()
        .flat_map(|c| c.points.iter().map(|&i| i as i64));
    write_raw_array(
        w,
        "connectivity",
        "Int64",
        1,
        &[],
        encoding,
        Raw::I64(&mut conn),
        n_conn,
    )?;
    let mut offsets = grid.cells.iter().scan(0i64, |end, c| {
        *end += c.points.len() as i64;
        Some(*end)
    });
    write_raw_array(
        w,
        "offsets",
        "Int64",
        1,
        &[],
        encoding,
        Raw::I64(&mut offsets),
        n_cells,
    )?;
    let mut types = grid.cells.iter().map(|c| c.kind.vtk_type());
    write_raw_array(
        w,
        "types",
        "UInt8",
        1,
        &[],
        encoding,
        Raw::U8(&mut types),
        n_cells,
    )?;
    writeln!(w, "      </Cells>")?;

    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    Ok(())
}

fn validate(grid: &Grid) -> io::Result<()> {
    let n_points = grid.points.len();
    for (k, p) in grid.points.iter().enumerate() {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(invalid(format!("point {k} has a non-finite coordinate")));
        }
    }
    for (k, c) in grid.cells.iter().enumerate() {
        if !c.kind.accepts(c.points.len()) {
            return Err(invalid(format!(
                "cell {k} ({:?}) has {} points",
                c.kind,
                c.points.len()
            )));
        }
        if let Some(&i) = c.points.iter().find(|&&i| i >= n_points) {
            return Err(invalid(format!(
                "cell {k} refers to point {i}, the grid has {n_points} points"
            )));
        }
    }
    check_arrays("point", &grid.point_data, n_points)?;
    check_arrays("cell", &grid.cell_data, grid.cells.len())?;
    for (k, a) in grid.field_data.iter().enumerate() {
        if a.name.is_empty() {
            return Err(invalid(format!("field array {k} has no name")));
        }
        if grid.field_data[..k].iter().any(|b| b.name == a.name) {
            return Err(invalid(format!("field array `{}` appears twice", a.name)));
        }
        if a.values.iter().any(|v| v.contains('\0')) {
            return Err(invalid(format!(
                "field array `{}` has a string with a NUL character",
                a.name
            )));
        }
    }
    Ok(())
}

fn check_arrays(place: &str, arrays: &[DataArray], n_tuples: usize) -> io::Result<()> {
    for (k, a) in arrays.iter().enumerate() {
        if a.name.is_empty() {
            return Err(invalid(format!("{place} array {k} has no name")));
        }
        if arrays[..k].iter().any(|b| b.name == a.name) {
            return Err(invalid(format!("{place} array `{}` appears twice", a.name)));
        }
        if !(1..=9).contains(&a.components) {
            return Err(invalid(format!(
                "{place} array `{}` has {} components (1 to 9 allowed)",
                a.name, a.components
            )));
        }
        if a.vector2 && (a.components != 2 || !matches!(a.values, Values::Float64(_))) {
            return Err(invalid(format!(
                "{place} array `{}` is flagged as a 2-D vector but is not 2-component Float64",
                a.name
            )));
        }
        if !a.component_names.is_empty() && a.component_names.len() != a.components {
            return Err(invalid(format!(
                "{place} array `{}` has {} component names for {} components",
                a.name,
                a.component_names.len(),
                a.components
            )));
        }
        if a.values.len() != n_tuples * a.components {
            return Err(invalid(format!(
                "{place} array `{}` has {} values, expected {} ({} tuples × {} components)",
                a.name,
                a.values.len(),
                n_tuples * a.components,
                n_tuples,
                a.components
            )));
        }
    }
    Ok(())
}

/// A [`FieldStrings`] as NUL-terminated UTF-8 bytes in a `UInt8` field array (module doc).
fn write_strings<W: Write>(w: &mut W, a: &FieldStrings, encoding: Encoding) -> io::Result<()> {
    let mut bytes = Vec::new();
    for v in &a.values {
        bytes.extend_from_slice(v.as_bytes());
        bytes.push(0);
    }
    let format = match encoding {
        Encoding::Binary => "binary",
        Encoding::Ascii => "ascii",
    };
    write!(
        w,
        r#"      <DataArray type="UInt8" Name="{}" NumberOfComponents="1" NumberOfTuples="{}" format="{format}">"#,
        escape(&a.name),
        bytes.len()
    )?;
    match encoding {
        Encoding::Binary => {
            let mut raw = Vec::with_capacity(8 + bytes.len());
            raw.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
            raw.extend_from_slice(&bytes);
            w.write_all(
                base64::engine::general_purpose::STANDARD
                    .encode(&raw)
                    .as_bytes(),
            )?;
        }
        Encoding::Ascii => {
            let text: Vec<String> = bytes.iter().map(|b| b.to_string()).collect();
            w.write_all(text.join(" ").as_bytes())?;
        }
    }
    writeln!(w, "</DataArray>")
}

fn write_data_array<W: Write>(w: &mut W, a: &DataArray, encoding: Encoding) -> io::Result<()> {
    let names: Vec<&str> = a.component_names.iter().map(String::as_str).collect();
    match &a.values {
        Values::Float64(v) if a.vector2 => {
            let mut it = v.chunks_exact(2).flat_map(|c| [c[0], c[1], 0.0]);
            let n = v.len() / 2 * 3;
            write_raw_array(
                w,
                &a.name,
                "Float64",
                3,
                &names,
                encoding,
                Raw::F64(&mut it),
                n,
            )
        }
        Values::Float64(v) => {
            let mut it = v.iter().copied();
            write_raw_array(
                w,
                &a.name,
                "Float64",
                a.components,
                &names,
                encoding,
                Raw::F64(&mut it),
                v.len(),
            )
        }
        Values::Int32(v) => {
            let mut it = v.iter().copied();
            write_raw_array(
                w,
                &a.name,
                "Int32",
                a.components,
                &names,
                encoding,
                Raw::I32(&mut it),
                v.len(),
            )
        }
    }
}

/// A stream of values of one VTK type.
enum Raw<'a> {
    F64(&'a mut dyn Iterator<Item = f64>),
    I64(&'a mut dyn Iterator<Item = i64>),
    I32(&'a mut dyn Iterator<Item = i32>),
    U8(&'a mut dyn Iterator<Item = u8>),
}

#[allow(clippy::too_many_arguments)]
fn write_raw_array<W: Write>(
    w: &mut W,
    name: &str,
    vtk_type: &str,
    components: usize,
    component_names: &[&str],
    encoding: Encoding,
    values: Raw<'_>,
    n_values: usize,
) -> io::Result<()> {
    let format = match encoding {
        Encoding::Binary => "binary",
        Encoding::Ascii => "ascii",
    };
    write!(
        w,
        r#"        <DataArray type="{vtk_type}" Name="{}" NumberOfComponents="{components}""#,
        escape(name)
    )?;
    for (i, c) in component_names.iter().enumerate() {
        write!(w, r#" ComponentName{i}="{}""#, escape(c))?;
    }
    write!(w, r#" format="{format}">"#)?;
    match encoding {
        Encoding::Binary => {
            let width = match values {
                Raw::F64(_) | Raw::I64(_) => 8,
                Raw::I32(_) => 4,
                Raw::U8(_) => 1,
            };
            let n_bytes = n_values * width;
            let mut bytes = Vec::with_capacity(8 + n_bytes);
            bytes.extend_from_slice(&(n_bytes as u64).to_le_bytes());
            match values {
                Raw::F64(it) => it.for_each(|v| bytes.extend_from_slice(&v.to_le_bytes())),
                Raw::I64(it) => it.for_each(|v| bytes.extend_from_slice(&v.to_le_bytes())),
                Raw::I32(it) => it.for_each(|v| bytes.extend_from_slice(&v.to_le_bytes())),
                Raw::U8(it) => it.for_each(|v| bytes.push(v)),
            }
            debug_assert_eq!(bytes.len(), 8 + n_bytes);
            w.write_all(
                base64::engine::general_purpose::STANDARD
                    .encode(&bytes)
                    .as_bytes(),
            )?;
        }
        Encoding::Ascii => {
            // Each value is followed by a space (VTK's text reader splits on white space).
            let mut s = String::new();
            match values {
                Raw::F64(it) => it.for_each(|v| {
                    super::history::format_f64(v, &mut s);
                    s.push(' ');
                }),
                Raw::I64(it) => it.for_each(|v| s.push_str(&format!("{v} "))),
                Raw::I32(it) => it.for_each(|v| s.push_str(&format!("{v} "))),
                Raw::U8(it) => it.for_each(|v| s.push_str(&format!("{v} "))),
            }
            s.pop();
            w.write_all(s.as_bytes())?;
        }
    }
    writeln!(w, "</DataArray>")
}

/// Escapes the five XML special characters for use in an attribute value.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// A ParaView collection (`.pvd`) of time frames, rewritten after every addition.
pub struct PvdWriter {
    path: PathBuf,
    frames: Vec<(f64, String)>,
    /// A name per frame (the analysis stage), written as a `name` attribute when not empty.
    names: Vec<String>,
}

impl PvdWriter {
    /// Creates the collection at `path` and writes it (empty) at once.
    pub fn new(path: &Path) -> io::Result<Self> {
        let w = Self {
            path: path.to_path_buf(),
            frames: Vec::new(),
            names: Vec::new(),
        };
        w.rewrite()?;
        Ok(w)
    }

    /// Adds a frame at `time` whose file is `file` (relative to the `.pvd`'s folder, `/` as
    /// separator), then rewrites the collection.
    pub fn add(&mut self, time: f64, file: &str) -> io::Result<()> {
        self.add_named(time, file, "")
    }

    /// As [`Self::add`], with a name for the frame (`name="…"` in the collection; ParaView
    /// ignores it, scripts can read it). An empty name writes no attribute.
    pub fn add_named(&mut self, time: f64, file: &str, name: &str) -> io::Result<()> {
        if !time.is_finite() {
            return Err(invalid(format!("frame time {time} is not finite")));
        }
        if file.is_empty() {
            return Err(invalid("frame file name is empty".to_string()));
        }
        self.frames.push((time, file.to_string()));
        self.names.push(name.to_string());
        self.rewrite()
    }

    /// Reopens the collection at `path` with `frames` (a resumed run: the frames written
    /// up to its checkpoint) and rewrites it.
    pub fn with_frames(
        path: &Path,
        frames: Vec<(f64, String)>,
        mut names: Vec<String>,
    ) -> io::Result<Self> {
        names.resize(frames.len(), String::new());
        let w = Self {
            path: path.to_path_buf(),
            frames,
            names,
        };
        w.rewrite()?;
        Ok(w)
    }

    /// The frames added so far.
    pub fn frames(&self) -> &[(f64, String)] {
        &self.frames
    }

    /// The frames' names (empty: none).
    pub fn frame_names(&self) -> &[String] {
        &self.names
    }

    /// Path of the collection file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn rewrite(&self) -> io::Result<()> {
        let mut s = String::new();
        s.push_str("<?xml version=\"1.0\"?>\n");
        s.push_str("<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
        s.push_str("  <Collection>\n");
        for ((time, file), name) in self.frames.iter().zip(&self.names) {
            s.push_str("    <DataSet timestep=\"");
            super::history::format_f64(*time, &mut s);
            s.push_str("\" group=\"\" part=\"0\" file=\"");
            s.push_str(&escape(file));
            if !name.is_empty() {
                s.push_str("\" name=\"");
                s.push_str(&escape(name));
            }
            s.push_str("\"/>\n");
        }
        s.push_str("  </Collection>\n");
        s.push_str("</VTKFile>\n");
        let mut tmp = self.path.clone().into_os_string();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        {
            let mut f = File::create(&tmp)?;
            f.write_all(s.as_bytes())?;
            f.flush()?;
        }
        std::fs::rename(&tmp, &self.path)
    }
}

/// A `.vtu` file as this module writes it, read back: points (x, y), cells (point indices),
/// and every point, cell and field array by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadGrid {
    pub points: Vec<[f64; 2]>,
    pub cells: Vec<Vec<usize>>,
    /// name → (components, values tuple after tuple).
    pub point_data: std::collections::HashMap<String, (usize, Vec<f64>)>,
    pub cell_data: std::collections::HashMap<String, (usize, Vec<f64>)>,
    /// Field-data string arrays (e.g. `block_names`).
    pub field_strings: std::collections::HashMap<String, Vec<String>>,
}

/// The value of `name="…"` in an XML start tag (unescaped).
fn attribute(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let p = tag.find(&key)? + key.len();
    let end = tag[p..].find('"')? + p;
    Some(
        tag[p..end]
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&"),
    )
}

/// Reads a `.vtu` written by [`write_vtu`] (binary or ASCII; the layout this module writes,
/// not every VTK file). Errors are one line naming the file.
pub fn read_vtu(path: &Path) -> Result<ReadGrid, String> {
    let file = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{file}: cannot read: {e}"))?;
    let bad = |what: &str| format!("{file}: not a .vtu written by nmm ({what})");
    if !text.contains("type=\"UnstructuredGrid\"") {
        return Err(bad("no UnstructuredGrid"));
    }
    let mut g = ReadGrid::default();
    let mut rest = text.as_str();
    let mut section = "";
    let (mut conn, mut offsets): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    while let Some(p) = rest.find('<') {
        rest = &rest[p..];
        let end = rest.find('>').ok_or_else(|| bad("an unterminated tag"))?;
        let tag = &rest[..=end];
        rest = &rest[end + 1..];
        for s in ["FieldData", "PointData", "CellData", "Points", "Cells"] {
            if tag.starts_with(&format!("<{s}>")) || tag.starts_with(&format!("<{s} ")) {
                section = s;
            }
        }
        if !tag.starts_with("<DataArray") {
            continue;
        }
        let close = rest
            .find("</DataArray>")
            .ok_or_else(|| bad("an unterminated DataArray"))?;
        let body = rest[..close].trim();
        rest = &rest[close..];
        let name = attribute(tag, "Name").unwrap_or_default();
        let ty = attribute(tag, "type").unwrap_or_default();
        let comps: usize = attribute(tag, "NumberOfComponents")
            .and_then(|c| c.parse().ok())
            .unwrap_or(1);
        let values: Vec<f64> = if attribute(tag, "format").as_deref() == Some("ascii") {
            body.split_whitespace()
                .map(|t| t.parse::<f64>().map_err(|_| bad("a number")))
                .collect::<Result<_, _>>()?
        } else {
            let bytes = base64::engine::general_purpose::STANDARD
                .decode(body)
                .map_err(|_| bad("base64"))?;
            if bytes.len() < 8 {
                return Err(bad("a short array"));
            }
            let n = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
            let raw = bytes.get(8..8 + n).ok_or_else(|| bad("a short array"))?;
            match ty.as_str() {
                "Float64" => raw
                    .chunks_exact(8)
                    .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                    .collect(),
                "Int64" => raw
                    .chunks_exact(8)
                    .map(|c| i64::from_le_bytes(c.try_into().unwrap()) as f64)
                    .collect(),
                "Int32" => raw
                    .chunks_exact(4)
                    .map(|c| i32::from_le_bytes(c.try_into().unwrap()) as f64)
                    .collect(),
                "UInt8" => raw.iter().map(|&b| b as f64).collect(),
                other => return Err(bad(&format!("array type {other}"))),
            }
        };
        match section {
            "FieldData" => {
                let bytes: Vec<u8> = values.iter().map(|&v| v as u8).collect();
                let mut names: Vec<String> = bytes
                    .split(|&b| b == 0)
                    .map(|s| String::from_utf8_lossy(s).into_owned())
                    .collect();
                names.pop();
                g.field_strings.insert(name, names);
            }
            "PointData" => {
                g.point_data.insert(name, (comps, values));
            }
            "CellData" => {
                g.cell_data.insert(name, (comps, values));
            }
            "Points" => {
                g.points = values.chunks_exact(3).map(|c| [c[0], c[1]]).collect();
            }
            "Cells" => match name.as_str() {
                "connectivity" => conn = values,
                "offsets" => offsets = values,
                _ => {}
            },
            _ => {}
        }
    }
    let mut start = 0usize;
    for &o in &offsets {
        let o = o as usize;
        if o < start || o > conn.len() {
            return Err(bad("cell offsets"));
        }
        let cell: Vec<usize> = conn[start..o].iter().map(|&i| i as usize).collect();
        if cell.iter().any(|&i| i >= g.points.len()) {
            return Err(bad("a cell's point index"));
        }
        g.cells.push(cell);
        start = o;
    }
    Ok(g)
}

/// The frames `(time, file)` of a `.pvd` collection written by [`PvdWriter`].
pub fn read_pvd(path: &Path) -> Result<Vec<(f64, String)>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let mut out = Vec::new();
    for tag in text.split('<').filter(|t| t.starts_with("DataSet ")) {
        let time = attribute(tag, "timestep")
            .and_then(|t| t.parse::<f64>().ok())
            .ok_or_else(|| format!("{}: a DataSet without a timestep", path.display()))?;
        let file = attribute(tag, "file")
            .ok_or_else(|| format!("{}: a DataSet without a file", path.display()))?;
        out.push((time, file));
    }
    Ok(out)
}
