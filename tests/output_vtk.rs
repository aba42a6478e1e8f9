//! VTK writers: the `.vtu` is re-parsed as XML (quick-xml), its counts, offsets and types are
//! checked and every base64 body is decoded back to the numbers given; `.pvd` collections are
//! re-parsed after every frame.

use base64::Engine;
use nmm::output::vtk::{write_vtu_with, Encoding};
use nmm::output::{write_vtu, Cell, DataArray, FieldStrings, Grid, PvdWriter};
use quick_xml::events::Event;
use std::collections::HashMap;
use std::path::Path;

/// A minimal DOM: enough to walk a VTK file.
#[derive(Debug, Default)]
struct Node {
    name: String,
    attrs: HashMap<String, String>,
    text: String,
    children: Vec<Node>,
}

impl Node {
    fn child(&self, name: &str) -> &Node {
        self.children
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("<{}> has no <{name}>", self.name))
    }
    fn all(&self, name: &str) -> Vec<&Node> {
        self.children.iter().filter(|c| c.name == name).collect()
    }
    fn attr(&self, key: &str) -> &str {
        self.attrs
            .get(key)
            .unwrap_or_else(|| panic!("<{}> has no attribute {key}", self.name))
    }
    fn array(&self, name: &str) -> &Node {
        self.all("DataArray")
            .into_iter()
            .find(|a| a.attr("Name") == name)
            .unwrap_or_else(|| panic!("no DataArray {name}"))
    }
}

fn parse(path: &Path) -> Node {
    let xml = std::fs::read_to_string(path).unwrap();
    let mut reader = quick_xml::Reader::from_str(&xml);
    let mut stack = vec![Node::default()];
    let start = |e: &quick_xml::events::BytesStart| {
        let mut n = Node {
            name: String::from_utf8(e.name().as_ref().to_vec()).unwrap(),
            ..Node::default()
        };
        for a in e.attributes() {
            let a = a.unwrap();
            n.attrs.insert(
                String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                a.unescape_value().unwrap().into_owned(),
            );
        }
        n
    };
    loop {
        match reader.read_event().unwrap() {
            Event::Start(e) => stack.push(start(&e)),
            Event::Empty(e) => stack.last_mut().unwrap().children.push(start(&e)),
            Event::End(_) => {
                let n = stack.pop().unwrap();
                stack.last_mut().unwrap().children.push(n);
            }
            Event::Text(t) => stack
                .last_mut()
                .unwrap()
                .text
                .push_str(&t.decode().unwrap()),
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(stack.len(), 1, "unbalanced XML");
    let mut doc = stack.pop().unwrap();
    assert_eq!(doc.children.len(), 1, "one root element");
    doc.children.pop().unwrap()
}

/// Decodes an inline binary body: u64 byte count, then the raw little-endian bytes.
fn decode(node: &Node) -> Vec<u8> {
    assert_eq!(node.attr("format"), "binary");
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(node.text.trim())
        .unwrap();
    assert!(bytes.len() >= 8);
    let n = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
    assert_eq!(n, bytes.len() - 8, "header byte count");
    bytes[8..].to_vec()
}

fn f64s(node: &Node) -> Vec<f64> {
    assert_eq!(node.attr("type"), "Float64");
    decode(node)
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn i64s(node: &Node) -> Vec<i64> {
    assert_eq!(node.attr("type"), "Int64");
    decode(node)
        .chunks_exact(8)
        .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn i32s(node: &Node) -> Vec<i32> {
    assert_eq!(node.attr("type"), "Int32");
    decode(node)
        .chunks_exact(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn sample_grid() -> Grid {
    // A unit square block (points 0..4) and a contact point 4 on a line 1-4.
    Grid {
        points: vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [1.5, 0.1 + 0.2],
        ],
        cells: vec![
            Cell::polygon(vec![0, 1, 2, 3]),
            Cell::line(1, 4),
            Cell::vertex(4),
        ],
        point_data: vec![
            DataArray::vector2(
                "displacement",
                vec![
                    0.0, 0.0, 1e-3, 0.0, 1e-3, -2e-3, 0.0, -2e-3, 1e-300, -5e-324,
                ],
            ),
            DataArray::scalars("temperature", vec![1.0, 2.0, 3.0, 4.0, f64::NAN]),
        ],
        cell_data: vec![
            DataArray::named_components(
                "stress",
                &["sxx", "syy", "sxy"],
                vec![-1e5, -2e5, 3e3, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0],
            ),
            DataArray::int32("block", vec![0, -1, i32::MAX]),
            DataArray::int32("state", vec![0, 1, 2]),
        ],
        field_data: vec![],
    }
}

#[test]
fn binary_vtu_decodes_to_the_grid() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("blocks_000000.vtu");
    let grid = sample_grid();
    write_vtu(&path, &grid).unwrap();

    let root = parse(&path);
    assert_eq!(root.name, "VTKFile");
    assert_eq!(root.attr("type"), "UnstructuredGrid");
    assert_eq!(root.attr("byte_order"), "LittleEndian");
    assert_eq!(root.attr("header_type"), "UInt64");
    let piece = root.child("UnstructuredGrid").child("Piece");
    assert_eq!(piece.attr("NumberOfPoints"), "5");
    assert_eq!(piece.attr("NumberOfCells"), "3");

    let points = piece.child("Points").child("DataArray");
    assert_eq!(points.attr("NumberOfComponents"), "3");
    let xyz = f64s(points);
    let expected: Vec<f64> = grid.points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
    assert_eq!(xyz, expected);

    let cells = piece.child("Cells");
    assert_eq!(i64s(cells.array("connectivity")), [0, 1, 2, 3, 1, 4, 4]);
    assert_eq!(i64s(cells.array("offsets")), [4, 6, 7]);
    let types = cells.array("types");
    assert_eq!(types.attr("type"), "UInt8");
    assert_eq!(decode(types), [7, 3, 1]);

    let pd = piece.child("PointData");
    let disp = pd.array("displacement");
    assert_eq!(disp.attr("NumberOfComponents"), "3");
    let d = f64s(disp);
    assert_eq!(d.len(), 15);
    let nmm::output::Values::Float64(given) = &grid.point_data[0].values else {
        panic!("displacement is Float64")
    };
    for k in 0..5 {
        assert_eq!(d[3 * k].to_bits(), given[2 * k].to_bits());
        assert_eq!(d[3 * k + 1].to_bits(), given[2 * k + 1].to_bits());
        assert_eq!(d[3 * k + 2], 0.0, "z component of a 2-D vector");
    }
    assert_eq!(d[13].to_bits(), (-5e-324f64).to_bits());
    let temp = f64s(pd.array("temperature"));
    assert_eq!(temp[..4], [1.0, 2.0, 3.0, 4.0]);
    assert!(temp[4].is_nan(), "binary keeps NaN as is");

    let cd = piece.child("CellData");
    let stress = cd.array("stress");
    assert_eq!(stress.attr("NumberOfComponents"), "3");
    assert_eq!(stress.attr("ComponentName0"), "sxx");
    assert_eq!(stress.attr("ComponentName2"), "sxy");
    assert_eq!(
        f64s(stress),
        [-1e5, -2e5, 3e3, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0]
    );
    assert_eq!(i32s(cd.array("block")), [0, -1, i32::MAX]);
    assert_eq!(i32s(cd.array("state")), [0, 1, 2]);
}

#[test]
fn ascii_vtu_reads_back_the_same_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.vtu");
    let mut grid = sample_grid();
    grid.point_data.pop(); // the NaN column: ASCII readers of VTK do not parse "nan"
    write_vtu_with(&path, &grid, Encoding::Ascii).unwrap();
    let root = parse(&path);
    let piece = root.child("UnstructuredGrid").child("Piece");
    let nums = |n: &Node| -> Vec<f64> {
        assert_eq!(n.attr("format"), "ascii");
        n.text
            .split_whitespace()
            .map(|s| s.parse().unwrap())
            .collect()
    };
    let xyz = nums(piece.child("Points").child("DataArray"));
    assert_eq!(xyz[13].to_bits(), (0.1f64 + 0.2).to_bits());
    assert_eq!(nums(piece.child("Cells").array("offsets")), [4.0, 6.0, 7.0]);
    assert_eq!(nums(piece.child("Cells").array("types")), [7.0, 3.0, 1.0]);
    let d = nums(piece.child("PointData").array("displacement"));
    assert_eq!(d[12], 1e-300);
    assert_eq!(d[13].to_bits(), (-5e-324f64).to_bits());
    assert_eq!(
        nums(piece.child("CellData").array("block")),
        [0.0, -1.0, i32::MAX as f64]
    );
}

#[test]
fn empty_grid_is_a_valid_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("contacts_000000.vtu");
    let grid = Grid {
        cell_data: vec![
            DataArray::vector2("force", vec![]),
            DataArray::int32("state", vec![]),
        ],
        ..Grid::default()
    };
    write_vtu(&path, &grid).unwrap();
    let root = parse(&path);
    let piece = root.child("UnstructuredGrid").child("Piece");
    assert_eq!(piece.attr("NumberOfPoints"), "0");
    assert_eq!(piece.attr("NumberOfCells"), "0");
    assert!(f64s(piece.child("Points").child("DataArray")).is_empty());
    for name in ["connectivity", "offsets"] {
        assert!(i64s(piece.child("Cells").array(name)).is_empty());
    }
    assert!(decode(piece.child("Cells").array("types")).is_empty());
    assert!(f64s(piece.child("CellData").array("force")).is_empty());
    assert!(i32s(piece.child("CellData").array("state")).is_empty());
}

/// Field data: the names as NUL-terminated UTF-8 bytes in one UInt8 array before the
/// piece, in both encodings; a NUL inside a name or a repeated array name is refused.
#[test]
fn field_strings_are_nul_terminated_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let names = vec![
        "base".to_string(),
        "sl,\"ider\" é".to_string(),
        String::new(),
    ];
    let mut grid = sample_grid();
    grid.field_data
        .push(FieldStrings::new("block_names", names.clone()));
    let want: Vec<u8> = names.iter().flat_map(|n| n.bytes().chain([0])).collect();
    for encoding in [Encoding::Binary, Encoding::Ascii] {
        let path = dir.path().join(format!("{encoding:?}.vtu"));
        write_vtu_with(&path, &grid, encoding).unwrap();
        let root = parse(&path);
        let ug = root
            .child("UnstructuredGrid")
            .child("FieldData")
            .array("block_names");
        assert_eq!(ug.attr("type"), "UInt8");
        assert_eq!(ug.attr("NumberOfTuples"), want.len().to_string());
        let bytes = match encoding {
            Encoding::Binary => decode(ug),
            Encoding::Ascii => ug
                .text
                .split_whitespace()
                .map(|t| t.parse::<u8>().unwrap())
                .collect(),
        };
        assert_eq!(bytes, want, "{encoding:?}");
        let back: Vec<String> = String::from_utf8(bytes)
            .unwrap()
            .split('\0')
            .map(str::to_string)
            .collect();
        assert_eq!(back[..3], names[..], "{encoding:?}");
    }
    let mut bad = grid.clone();
    bad.field_data[0].values.push("a\0b".into());
    assert!(write_vtu(&dir.path().join("bad.vtu"), &bad).is_err());
    let mut twice = grid.clone();
    twice
        .field_data
        .push(FieldStrings::new("block_names", vec![]));
    assert!(write_vtu(&dir.path().join("twice.vtu"), &twice).is_err());
}

#[test]
fn names_with_xml_characters_are_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("n.vtu");
    let grid = Grid {
        points: vec![[0.0, 0.0]],
        cells: vec![Cell::vertex(0)],
        point_data: vec![DataArray::scalars("a<b & \"c\"", vec![1.0])],
        cell_data: vec![],
        field_data: vec![],
    };
    write_vtu(&path, &grid).unwrap();
    let piece = parse(&path);
    let pd = piece
        .child("UnstructuredGrid")
        .child("Piece")
        .child("PointData");
    assert_eq!(f64s(pd.array("a<b & \"c\"")), [1.0]);
}

#[test]
fn invalid_grids_are_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(&str, Grid)> = vec![
        (
            "index out of range",
            Grid {
                points: vec![[0.0, 0.0], [1.0, 0.0]],
                cells: vec![Cell::line(0, 2)],
                ..Grid::default()
            },
        ),
        (
            "polygon with two points",
            Grid {
                points: vec![[0.0, 0.0], [1.0, 0.0]],
                cells: vec![Cell::polygon(vec![0, 1])],
                ..Grid::default()
            },
        ),
        ("array too short", {
            let mut g = sample_grid();
            g.point_data.push(DataArray::scalars("short", vec![1.0; 4]));
            g
        }),
        ("duplicate name", {
            let mut g = sample_grid();
            g.cell_data.push(DataArray::int32("state", vec![0; 3]));
            g
        }),
        ("component names do not match", {
            let mut g = sample_grid();
            g.cell_data[0].component_names.pop();
            g
        }),
        ("non-finite point", {
            let mut g = sample_grid();
            g.points[2][1] = f64::INFINITY;
            g
        }),
    ];
    for (what, grid) in cases {
        let path = dir.path().join("bad.vtu");
        let e = write_vtu(&path, &grid).expect_err(what);
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput, "{what}: {e}");
        assert!(!path.exists(), "{what}: file written");
    }
}

fn frames(path: &Path) -> Vec<(String, String)> {
    let root = parse(path);
    assert_eq!(root.attr("type"), "Collection");
    root.child("Collection")
        .all("DataSet")
        .iter()
        .map(|d| (d.attr("timestep").to_string(), d.attr("file").to_string()))
        .collect()
}

#[test]
fn pvd_is_valid_after_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("blocks.pvd");
    let mut pvd = PvdWriter::new(&path).unwrap();
    assert!(frames(&path).is_empty(), "valid empty collection at once");
    let times = [0.0, 0.1 + 0.2, 1e-7, 12.5];
    for (k, t) in times.iter().enumerate() {
        let name = nmm::output::frame_file_name("blocks", k * 10);
        write_vtu(&dir.path().join(&name), &sample_grid()).unwrap();
        pvd.add(*t, &name).unwrap();
        let f = frames(&path);
        assert_eq!(f.len(), k + 1);
        assert_eq!(f[k].0.parse::<f64>().unwrap().to_bits(), t.to_bits());
        assert_eq!(f[k].1, name);
        assert!(dir.path().join(&f[k].1).exists());
    }
    assert_eq!(frames(&path)[3].1, "blocks_000030.vtu");
    assert!(pvd.add(f64::NAN, "x.vtu").is_err());
    assert_eq!(
        frames(&path).len(),
        4,
        "a refused frame leaves the file as it was"
    );
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(names.is_empty(), "{names:?}");
}

/// The conventions of docs/outputs.md on a real run (issue 19): a 0.5 m × 0.25 m block on a
/// fixed base under gravity tilted 30° (an incline without rotating the mesh), φ = 20°, so
/// it slides in +x; plane strain, ν = 0.25; dynamic, 300 steps of 1 ms, frames at 0 and 300.
/// - contacts: `force_on_vertex_block` = −(t_N n + t_S t) with |t_N| = `normal_force`,
///   t_S = `shear_force` and t the edge block's counter-clockwise direction (−n_y, n_x);
///   `normal` points toward the vertex block; every closed contact is sliding (state 2);
///   the forces on the block (its vertex contacts' plus the opposite of its edge
///   contacts') add up to the base's reaction: N = m g cos θ up, friction tan φ N against
///   the slip (−x);
/// - blocks: `szz` = ν(`sxx` + `syy`) per cell (plane strain), tension positive: the
///   block's mean stress from equilibrium (∫σ_ij dA = ∮ x_i t_j ds + ∫ x_i (b_j − ρa_j) dA,
///   y measured from the joint): σyy = −ρ g cos θ H/2, τxy = +ρ g cos θ tan φ H/2.
///
/// Tolerance 1e-3 on the sums and means: what is left after 300 steps of the contacts'
/// oscillation on the penalty springs, damped by the scheme, and the slider's deformed
/// geometry (strain ~1e-6) in the means (measured 3e-5).
#[test]
fn a_real_run_writes_the_documented_signs_and_stress() {
    let (theta, phi, rho, nu) = (30f64.to_radians(), 20f64.to_radians(), 2500.0, 0.25);
    let (s, c) = theta.sin_cos();
    let g = 9.81;
    let model = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 300\noutput_every = 300\ngravity = [{}, {}]\n\
         [cover]\nsize = 0.0625\n\
         [[material]]\nname = \"rock\"\ndensity = {rho}\nyoung = 1.0e9\npoisson = {nu}\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nfixed = true\nvertices = [[0.0, 0.0], [3.0, 0.0], [3.0, 0.5], [0.0, 0.5]]\n\
         [[block]]\nname = \"slider\"\nmaterial = \"rock\"\nvertices = [[0.5, 0.5], [1.0, 0.5], [1.0, 0.75], [0.5, 0.75]]\n\
         [[interface]]\nfriction_angle = 20.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e9\n",
        g * s,
        -g * c
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (h, w) = (0.25, 0.5);
    let m = rho * h * w;
    let n_force = m * g * c;

    // contacts
    let root = parse(&out.join("vtk/contacts_000300.vtu"));
    let cd = root
        .child("UnstructuredGrid")
        .child("Piece")
        .child("CellData");
    let normal = f64s(cd.array("normal"));
    let force = f64s(cd.array("force_on_vertex_block"));
    let tn = f64s(cd.array("normal_force"));
    let ts = f64s(cd.array("shear_force"));
    let state = i32s(cd.array("state"));
    let blocks = f64s(cd.array("blocks"));
    let (mut fx, mut fy, mut closed) = (0.0, 0.0, 0);
    for k in 0..state.len() {
        let nv = [normal[3 * k], normal[3 * k + 1]];
        let f = [force[3 * k], force[3 * k + 1]];
        let t = [-nv[1], nv[0]];
        let scale = n_force;
        assert!(
            (f[0] * nv[0] + f[1] * nv[1] - tn[k]).abs() < 1e-9 * scale,
            "contact {k}: F·n vs |t_N|"
        );
        assert!(
            (f[0] * t[0] + f[1] * t[1] + ts[k]).abs() < 1e-9 * scale,
            "contact {k}: F·t vs −t_S"
        );
        let (vb, eb) = (blocks[2 * k] as usize, blocks[2 * k + 1] as usize);
        // the normal points from the edge block toward the vertex block: up when the
        // base's top is the edge (a slider's edge is turned by its strain, ~1e-6)
        let up = if eb == 0 { 1.0 } else { -1.0 };
        assert!(
            (nv[1] - up).abs() < 1e-8 && nv[0].abs() < 1e-4,
            "contact {k}: normal {nv:?}, blocks {vb}/{eb}"
        );
        if tn[k] > 0.0 {
            closed += 1;
            assert_eq!(state[k], 2, "contact {k} closed but not sliding");
        }
        let sign = if vb == 1 { 1.0 } else { -1.0 };
        fx += sign * f[0];
        fy += sign * f[1];
    }
    eprintln!(
        "contacts: {closed} closed; force on the slider ({fx:.3}, {fy:.3}) N/m, expected ({:.3}, {n_force:.3})",
        -phi.tan() * n_force
    );
    assert!(closed >= 4, "{closed} closed contacts");
    assert!((fy / n_force - 1.0).abs() < 1e-3, "{fy} vs {n_force}");
    assert!(
        (fx / (-phi.tan() * n_force) - 1.0).abs() < 1e-3,
        "{fx} vs friction against the slip"
    );

    // blocks
    let root = parse(&out.join("vtk/blocks_000300.vtu"));
    let piece = root.child("UnstructuredGrid").child("Piece");
    let pts = f64s(piece.child("Points").array("Points"));
    let conn = i64s(piece.child("Cells").array("connectivity"));
    let offs = i64s(piece.child("Cells").array("offsets"));
    let cd = piece.child("CellData");
    let stress = f64s(cd.array("stress"));
    let block = i32s(cd.array("block"));
    let (mut area, mut syy, mut txy) = (0.0, 0.0, 0.0);
    let mut start = 0usize;
    for (k, &end) in offs.iter().enumerate() {
        let v: Vec<[f64; 2]> = conn[start..end as usize]
            .iter()
            .map(|&i| [pts[3 * i as usize], pts[3 * i as usize + 1]])
            .collect();
        start = end as usize;
        let st = &stress[4 * k..4 * k + 4];
        let scale = st.iter().fold(1.0f64, |a, x| a.max(x.abs()));
        assert!(
            (st[3] - nu * (st[0] + st[1])).abs() < 1e-9 * scale,
            "cell {k}: szz {st:?}"
        );
        if block[k] != 1 {
            continue;
        }
        let a: f64 = (0..v.len())
            .map(|i| {
                let (p, q) = (v[i], v[(i + 1) % v.len()]);
                0.5 * (p[0] * q[1] - q[0] * p[1])
            })
            .sum();
        area += a;
        syy += a * st[1];
        txy += a * st[2];
    }
    let (syy, txy) = (syy / area, txy / area);
    let (want_syy, want_txy) = (-rho * g * c * h / 2.0, rho * g * c * phi.tan() * h / 2.0);
    eprintln!("slider: area {area:.6}, mean σyy {syy:.2} Pa (expected {want_syy:.2}), τxy {txy:.2} Pa (expected {want_txy:.2})");
    assert!((area / (h * w) - 1.0).abs() < 1e-3, "{area}");
    assert!(
        (syy / want_syy - 1.0).abs() < 1e-3,
        "σyy {syy} vs {want_syy}"
    );
    assert!(
        (txy / want_txy - 1.0).abs() < 1e-3,
        "τxy {txy} vs {want_txy}"
    );
}

/// The bolts' frames (docs/outputs.md, `bolts.pvd`): a block on a fixed base under gravity
/// tilted 30°, φ = 20°, held by a bolt (k = 1e5 N/m) from the block to an abutment of the
/// base, static, 3 steps. `bolts.pvd` lists the frames `blocks.pvd` does (same times,
/// `vtk/bolts_NNNNNN.vtu`); each is one VTK_LINE cell (type 3) between the anchors — at
/// step 0 the points as written, at the end the block's anchor moved along the bolt by the
/// elongation — with `force`, `elongation`, `plastic_elongation`, `installed`, `yielded`,
/// `bolt` and the `bolt_names` field data, and the force is history.csv's `b1.force`.
#[test]
fn bolts_frames_are_line_cells_with_their_forces() {
    let (s, c) = 30f64.to_radians().sin_cos();
    let model = format!(
        "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = 3\noutput_every = 3\ngravity = [{}, {}]\n\
         [cover]\nsize = 0.0625\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nfixed = true\n\
         vertices = [[0.0, 0.0], [3.0, 0.0], [3.0, 0.5], [0.3, 0.5], [0.3, 0.75], [0.0, 0.75]]\n\
         [[block]]\nname = \"slider\"\nmaterial = \"rock\"\nvertices = [[0.5, 0.5], [1.0, 0.5], [1.0, 0.75], [0.5, 0.75]]\n\
         [[interface]]\nfriction_angle = 20.0\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n\
         [[bolt]]\nname = \"b1\"\npoints = [[0.6, 0.625], [0.15, 0.625]]\nstiffness = 1.0e5\ncapacity = 1.0e4\n\
         [[monitor]]\nname = \"b1\"\nbolt = \"b1\"\n",
        9.81 * s,
        -9.81 * c
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bolts = frames(&out.join("bolts.pvd"));
    let blocks = frames(&out.join("blocks.pvd"));
    assert_eq!(bolts.len(), 2);
    for (b, k) in bolts.iter().zip(&blocks) {
        assert_eq!(b.0, k.0);
        assert_eq!(b.1, k.1.replace("blocks_", "bolts_"));
    }
    let hist = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert!(hist.starts_with("step,time,b1.force,b1.elongation,iterations,solves,cuts\n"));
    let last: Vec<f64> = hist
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    for (k, (_, file)) in bolts.iter().enumerate() {
        let root = parse(&out.join(file));
        let piece = root.child("UnstructuredGrid").child("Piece");
        assert_eq!(piece.attr("NumberOfCells"), "1");
        assert_eq!(piece.attr("NumberOfPoints"), "2");
        let cells = piece.child("Cells");
        assert_eq!(i64s(cells.array("connectivity")), [0, 1]);
        assert_eq!(i64s(cells.array("offsets")), [2]);
        let types = decode(cells.array("types"));
        assert_eq!(types, [3u8], "VTK_LINE");
        let pts = f64s(piece.child("Points").array("Points"));
        let cd = piece.child("CellData");
        let force = f64s(cd.array("force"))[0];
        let elongation = f64s(cd.array("elongation"))[0];
        assert_eq!(f64s(cd.array("plastic_elongation")), [0.0]);
        assert_eq!(i32s(cd.array("installed")), [1]);
        assert_eq!(i32s(cd.array("yielded")), [0]);
        assert_eq!(i32s(cd.array("bolt")), [0]);
        let names = decode(
            root.child("UnstructuredGrid")
                .child("FieldData")
                .array("bolt_names"),
        );
        assert_eq!(names, b"b1\0");
        if k == 0 {
            assert_eq!(pts, [0.6, 0.625, 0.0, 0.15, 0.625, 0.0]);
            assert_eq!((force, elongation), (0.0, 0.0));
        } else {
            // the history's figures (written as shortest round-trip decimals)
            assert_eq!((force, elongation), (last[2], last[3]));
            assert!(force > 400.0, "{force}");
            // the block's anchor moved down the slope (+x) by the elongation, the base's not
            assert!(
                (pts[0] - 0.6 - elongation).abs() < 1e-3 * elongation,
                "{pts:?}"
            );
            assert_eq!(&pts[3..5], [0.15, 0.625]);
        }
    }
}
