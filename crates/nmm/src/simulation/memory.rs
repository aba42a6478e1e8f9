//! Memory: an estimate of what a model's run needs, made from the model alone (before the
//! covers are built), and the memory the process may use; a model that cannot fit is
//! refused with one line before any large allocation.
//!
//! **Estimate.** The mathematical mesh has squares of side h over the box of all blocks; a
//! block of area A and perimeter P has about A/h² + P/h + 4 physical covers (a cover per mesh
//! node whose star meets it: the block dilated by about ¾ h), A/h² + ¾ P/h + 2, each with
//! two unknowns unless the block is fixed. (Blocks whose edges lie on mesh lines, as the
//! walls' bricks at h = 0.2 m, have fewer: 12 unknowns per brick against 17 estimated.) The run's peak
//! resident memory grows with the unknowns as the sparse factor does (2-D, nested dissection:
//! n log n), measured on the running-bond walls of `generate::wall` (one contact per brick
//! vertex, the factor, GMRES's Krylov basis, the contact tangents):
//!
//! | wall | unknowns | peak RSS | estimate |
//! |---|---|---|---|
//! | 30×30 | 10,800 (15,300 estimated) | 101 MB | EST30 |
//! | 40×40 | 19,200 (27,200 estimated) | 193 MB | EST40 |
//! | 50×50 | 30,000 (42,500 estimated) | 300 MB | EST50 |
//!
//! i.e. [`BYTES_PER_UNKNOWN`] × n × (1 + log₂(n / 10⁴) / 10) plus [`BASE_BYTES`], plus the
//! mesh itself ([`BYTES_PER_MESH_SQUARE`] per square of the box). The estimate is meant to be
//! close, not padded: it refuses only models whose run could not fit.
//!
//! **First-order covers** (`[cover] order = 1`): three times the unknowns per cover, less
//! the six per block removed for linear dependence, and [`ORDER_1_BYTES_FACTOR`] times the
//! bytes per unknown (an element couples 18 unknowns, a contact 36: the 20×20 wall at
//! h = 0.2 m peaked at 289 MB with 12,000 unknowns, 24 kB each, against 51 MB with 4,800 at
//! order 0, 10.6 kB each).
//!
//! **Limit.** The smallest of the memory available on the machine (`MemAvailable`), the
//! process's cgroup limit less what the cgroup uses (v2 `memory.max`, v1
//! `memory.limit_in_bytes`) and its address-space limit (`RLIMIT_AS`, from
//! `/proc/self/limits`). Where none can be read (not Linux), there is no limit.

use crate::geometry::moments::polygon_area;
use crate::model::Model;

/// Peak resident bytes per unknown of a run (see the module docs).
pub const BYTES_PER_UNKNOWN: f64 = 6_500.0;

/// Bytes per unknown at order 1 relative to order 0 (module docs).
pub const ORDER_1_BYTES_FACTOR: f64 = 2.3;
/// Resident bytes of the program itself.
pub const BASE_BYTES: f64 = 12.0e6;
/// Bytes per square of the mathematical mesh (its nodes and triangles).
pub const BYTES_PER_MESH_SQUARE: f64 = 64.0;

/// What a model's run is expected to need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Unknowns (two per physical cover of a movable block).
    pub unknowns: f64,
    /// Squares of the mathematical mesh.
    pub mesh_squares: f64,
    /// Peak resident memory of the run (bytes).
    pub bytes: f64,
}

/// The estimate of a model's run (module docs), from its blocks and cover size.
pub fn estimate(model: &Model) -> Estimate {
    let h = model.cover_size;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut unknowns = 0.0;
    for b in &model.blocks {
        let v = &b.vertices;
        for p in v {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if b.fixed {
            continue;
        }
        let area = if b.holes.is_empty() {
            polygon_area(v).abs()
        } else {
            b.area()
        };
        let perimeter: f64 = (0..v.len())
            .map(|i| {
                let (p, q) = (v[i], v[(i + 1) % v.len()]);
                (q[0] - p[0]).hypot(q[1] - p[1])
            })
            .sum();
        let covers = area / (h * h) + 0.75 * perimeter / h + 2.0;
        unknowns += if model.cover_order == 0 {
            2.0 * covers
        } else {
            (6.0 * covers - 6.0).max(6.0)
        };
    }
    let mesh_squares = if model.blocks.is_empty() {
        0.0
    } else {
        ((hi[0] - lo[0]) / h + 2.0) * ((hi[1] - lo[1]) / h + 2.0)
    };
    let growth = 1.0 + (unknowns / 1e4).max(1.0).log2() / 10.0;
    let per_unknown = if model.cover_order == 0 {
        BYTES_PER_UNKNOWN
    } else {
        ORDER_1_BYTES_FACTOR * BYTES_PER_UNKNOWN
    };
    let bytes = BASE_BYTES + per_unknown * unknowns * growth + BYTES_PER_MESH_SQUARE * mesh_squares;
    Estimate {
        unknowns,
        mesh_squares,
        bytes,
    }
}

/// The memory this process may use (bytes) and where the limit comes from, if known.
pub fn available() -> Option<(f64, &'static str)> {
    let mut best: Option<(f64, &'static str)> = None;
    let mut take = |v: Option<f64>, what: &'static str| {
        if let Some(v) = v {
            if best.is_none_or(|(b, _)| v < b) {
                best = Some((v, what));
            }
        }
    };
    take(meminfo_available(), "memory available on this machine");
    take(cgroup_room(), "the cgroup's memory limit");
    take(address_space_limit(), "the address-space limit (ulimit -v)");
    best
}

fn read(path: &str) -> Option<String> {
    std::fs::read_to_string(path).ok()
}

fn meminfo_available() -> Option<f64> {
    let s = read("/proc/meminfo")?;
    let line = s.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

fn cgroup_room() -> Option<f64> {
    // v2: the process's own cgroup (the unified hierarchy's "0::/path" line)
    if let Some(cg) = read("/proc/self/cgroup") {
        if let Some(path) = cg.lines().find_map(|l| l.strip_prefix("0::")) {
            let dir = format!("/sys/fs/cgroup{}", path.trim_end());
            if let Some(max) = read(&format!("{dir}/memory.max")) {
                let max = max.trim();
                if max != "max" {
                    let max: f64 = max.parse().ok()?;
                    let used: f64 = read(&format!("{dir}/memory.current"))
                        .and_then(|s| s.trim().parse().ok())
                        .unwrap_or(0.0);
                    return Some((max - used).max(0.0));
                }
                return None;
            }
        }
    }
    // v1
    let max: f64 = read("/sys/fs/cgroup/memory/memory.limit_in_bytes")?
        .trim()
        .parse()
        .ok()?;
    if max >= 1e18 {
        return None; // "no limit" is a huge number in v1
    }
    let used: f64 = read("/sys/fs/cgroup/memory/memory.usage_in_bytes")
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(0.0);
    Some((max - used).max(0.0))
}

fn address_space_limit() -> Option<f64> {
    let s = read("/proc/self/limits")?;
    let line = s.lines().find(|l| l.starts_with("Max address space"))?;
    let soft = line
        .trim_start_matches("Max address space")
        .split_whitespace()
        .next()?;
    soft.parse().ok()
}

/// Bytes as a short human figure: `1.2 GB`, `350 MB`.
pub fn human(bytes: f64) -> String {
    if bytes >= 1e15 {
        format!("{bytes:.1e} bytes")
    } else if bytes >= 1e12 {
        format!("{:.1} TB", bytes / 1e12)
    } else if bytes >= 1e9 {
        format!("{:.1} GB", bytes / 1e9)
    } else {
        format!("{:.0} MB", (bytes / 1e6).max(1.0))
    }
}

/// `Err(one line)` when the model's estimate exceeds the memory the process may use.
pub fn check_fits(model: &Model) -> Result<Estimate, String> {
    let e = estimate(model);
    match available() {
        Some((limit, what)) if e.bytes > limit => Err(format!(
            "the model needs about {} of memory ({:.3e} unknowns at cover size {} m) but the process may use {} ({what}): use a coarser [cover] size or a machine with more memory",
            human(e.bytes),
            e.unknowns,
            model.cover_size,
            human(limit)
        )),
        _ => Ok(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{brick_wall_model, WallOptions};
    use crate::model::parse_model;
    use std::path::Path;

    #[test]
    fn wall_estimates_are_close_to_the_measured_peaks() {
        // (wall, unknowns, measured peak RSS) from the module docs' table
        for (n, unknowns, peak) in [
            (30, 10_800.0, 101e6),
            (40, 19_200.0, 193e6),
            (50, 30_000.0, 300e6),
        ] {
            let m =
                parse_model(&brick_wall_model(&WallOptions::new(n, n)), Path::new(".")).unwrap();
            let e = estimate(&m);
            let ru = e.unknowns / unknowns;
            assert!((1.0..1.6).contains(&ru), "{n}: {e:?}");
            let r = e.bytes / peak;
            eprintln!(
                "{n}×{n}: estimate {:.0} MB, measured {:.0} MB",
                e.bytes / 1e6,
                peak / 1e6
            );
            assert!(
                (0.9..1.5).contains(&r),
                "{n}: estimate {} vs {peak}",
                e.bytes
            );
        }
    }

    #[test]
    fn a_cover_far_too_fine_is_refused_in_one_line() {
        let text = "[analysis]\ndt = 0.01\nsteps = 1\n[cover]\nsize = 1e-4\n\
            [[material]]\nname = \"m\"\ndensity = 2500.0\nyoung = 1e9\npoisson = 0.25\n\
            [[block]]\nname = \"big\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]]\n";
        let m = parse_model(text, Path::new(".")).unwrap();
        let e = estimate(&m);
        assert!(e.bytes > 1e15, "{e:?}");
        if available().is_some() {
            let err = check_fits(&m).unwrap_err();
            assert!(!err.contains('\n'));
            assert!(
                err.contains("needs about") && err.contains("coarser"),
                "{err}"
            );
        }
    }
}
