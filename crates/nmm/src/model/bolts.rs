//! `[[bolt]]` tables: rock bolts, read and checked (the law they follow is in
//! [`crate::bolt`]).
//!
//! ```toml
//! [[bolt]]
//! name = "b1"
//! points = [[x1, y1], [x2, y2]]    # its two anchors: material points, in one block or two
//! stiffness = 1.0e8                # axial, N/m
//! capacity = 2.0e5                 # yield force, N
//! pretension = 0.0                 # optional, N (0 ≤ pretension ≤ capacity)
//! stage = "support"                # optional: installed at the start of this stage
//! ```
//!
//! Each anchor lies in the first block (in file order, after cutting) whose polygon holds
//! it, inside or on its boundary, as a point monitor's does.

use super::lines::Doc;
use super::reader::{array, array_of_tables, fmt_num, fmt_point, number, point, string, Fields, R};
use super::{Block, Bolt, Stage};
use crate::geometry::polygon::{point_in_polygon, Location};

/// The keys of a `[[bolt]]` table.
const KEYS: &[&str] = &[
    "name",
    "points",
    "stiffness",
    "capacity",
    "pretension",
    "stage",
];

fn positive(f: &Fields, key: &str) -> R<f64> {
    let x = f.req(key, number)?;
    // `!(x > 0)`: a NaN fails too (the reader refuses them already)
    if x.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(f.err(key, format!("must be positive, got {}", fmt_num(x))));
    }
    Ok(x)
}

/// Every `[[bolt]]` of the model, in file order: names unique, both anchors inside a block
/// and apart, stiffness and capacity positive, 0 ≤ pretension ≤ capacity, the stage one
/// of the model's.
pub(super) fn bolts(root: &Doc, blocks: &[Block], stages: &[Stage], tol: f64) -> R<Vec<Bolt>> {
    let mut out: Vec<Bolt> = Vec::new();
    for (k, t) in array_of_tables(root, "bolt")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[bolt]] #{}", k + 1), t, "bolt", Some(k));
        let name = f.name("name")?;
        f.set_place(format!("[[bolt]] {name:?}"));
        f.deny_unknown(KEYS)?;
        if name.chars().any(|c| c == ',' || c == '"' || c.is_control()) {
            return Err(f.err(
                "name",
                "must not contain commas, quotes or control characters (it names history.csv columns)",
            ));
        }
        if let Some(j) = out.iter().position(|b| b.name == name) {
            return Err(f.err(
                "name",
                format!("duplicate bolt name (also [[bolt]] #{})", j + 1),
            ));
        }
        let pts = f.req("points", array)?;
        if pts.len() != 2 {
            return Err(f.err(
                "points",
                format!(
                    "expected its two anchors [[x1, y1], [x2, y2]], got {} items",
                    pts.len()
                ),
            ));
        }
        let mut points = [[0.0; 2]; 2];
        let mut owners = [0; 2];
        for (i, v) in pts.iter().enumerate() {
            let p = point(v).map_err(|e| f.err("points", format!("point {}: {e}", i + 1)))?;
            owners[i] = blocks
                .iter()
                .position(|b| point_in_polygon(&b.vertices, p, tol) != Location::Outside)
                .ok_or_else(|| {
                    f.err(
                        "points",
                        format!(
                            "point {} {} is not inside any block (an anchor is a material point of a block)",
                            i + 1,
                            fmt_point(p)
                        ),
                    )
                })?;
            points[i] = p;
        }
        if crate::geometry::dist(points[0], points[1]) <= tol {
            return Err(f.err(
                "points",
                format!(
                    "the two anchors coincide at {}: a bolt needs a length",
                    fmt_point(points[0])
                ),
            ));
        }
        let stiffness = positive(&f, "stiffness")?;
        let capacity = positive(&f, "capacity")?;
        let pretension = f.opt("pretension", number)?.unwrap_or(0.0);
        if pretension < 0.0 {
            return Err(f.err(
                "pretension",
                format!(
                    "must be zero or positive (a tensile force), got {}",
                    fmt_num(pretension)
                ),
            ));
        }
        if pretension > capacity {
            return Err(f.err(
                "pretension",
                format!(
                    "{} is above the capacity {}: the bolt would yield at installation",
                    fmt_num(pretension),
                    fmt_num(capacity)
                ),
            ));
        }
        let stage = match f.opt("stage", string)? {
            None => None,
            Some(s) => Some(stages.iter().position(|st| st.name == s).ok_or_else(|| {
                let known: Vec<String> = stages.iter().map(|st| format!("{:?}", st.name)).collect();
                f.err(
                    "stage",
                    if known.is_empty() {
                        format!("unknown stage {s:?} (the model has no [[stage]])")
                    } else {
                        format!("unknown stage {s:?} (stages: {})", known.join(", "))
                    },
                )
            })?),
        };
        out.push(Bolt {
            name,
            points,
            blocks: owners,
            stiffness,
            capacity,
            pretension,
            stage,
        });
    }
    Ok(out)
}
