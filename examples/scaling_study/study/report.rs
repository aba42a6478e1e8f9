//! The study's report: a Markdown table per model family with the fitted growth exponents,
//! and one JSON object per row (and per fit).

use super::{Case, Config, Family, Row};
use serde_json::{json, Value};

/// Least-squares slope and r² of log y against log x, over the points with x, y > 0 (at least
/// two distinct x).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit {
    pub exponent: f64,
    pub r2: f64,
    pub points: usize,
    pub x_range: (f64, f64),
}

pub fn fit_loglog(points: &[(f64, f64)]) -> Option<Fit> {
    let kept: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .collect();
    let p: Vec<(f64, f64)> = kept.iter().map(|(x, y)| (x.ln(), y.ln())).collect();
    let n = p.len() as f64;
    if p.len() < 2 {
        return None;
    }
    let mx = p.iter().map(|q| q.0).sum::<f64>() / n;
    let my = p.iter().map(|q| q.1).sum::<f64>() / n;
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    let syy: f64 = p.iter().map(|q| (q.1 - my).powi(2)).sum();
    if sxx.is_nan() || sxx <= 0.0 {
        return None;
    }
    let b = sxy / sxx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    let xs = kept.iter().map(|q| q.0);
    Some(Fit {
        exponent: b,
        r2,
        points: p.len(),
        x_range: (
            xs.clone().fold(f64::INFINITY, f64::min),
            xs.fold(0.0, f64::max),
        ),
    })
}

/// Rows of `family` that enter the fit (the configured size range, status ok).
fn fit_rows<'a>(cfg: &Config, rows: &'a [Row], family: Family) -> Vec<&'a Row> {
    rows.iter()
        .filter(|r| r.case.family() == family && r.status == "ok")
        .filter(|r| match r.case {
            Case::Wall { nx, ny } => {
                let (lo, hi) = cfg.wall_fit;
                (lo..=hi).contains(&nx) && (lo..=hi).contains(&ny)
            }
            Case::Slope { .. } => {
                let (lo, hi) = cfg.slope_fit;
                (lo..=hi).contains(&r.blocks)
            }
        })
        .collect()
}

/// The fits of one family: per-step cost and peak memory of nmm against unknowns, and the
/// peer's per-step cost against the same unknowns.
pub struct Fits {
    pub per_step: Option<Fit>,
    pub memory: Option<Fit>,
    pub peer_per_step: Option<Fit>,
    /// The fit range, as labels.
    pub range: Option<(String, String)>,
}

pub fn fits(cfg: &Config, rows: &[Row], family: Family) -> Fits {
    let r = fit_rows(cfg, rows, family);
    let pts = |f: &dyn Fn(&Row) -> Option<f64>| -> Vec<(f64, f64)> {
        r.iter()
            .filter_map(|row| Some((row.unknowns()?, f(row)?)))
            .collect()
    };
    Fits {
        per_step: fit_loglog(&pts(&|r| r.per_step_ms)),
        memory: fit_loglog(&pts(&|r| r.peak_mb.or(r.peak_summary_mb))),
        peer_per_step: fit_loglog(&pts(&|r| {
            r.peer
                .as_ref()
                .filter(|p| p.status == "ok")
                .and_then(|p| p.per_step_ms)
        })),
        range: match (r.first(), r.last()) {
            (Some(a), Some(b)) => Some((a.case.label(), b.case.label())),
            _ => None,
        },
    }
}

const DASH: &str = "—";

/// A number with thousands separators.
fn int(x: f64) -> String {
    let s = format!("{:.0}", x.abs());
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    if x < 0.0 {
        format!("-{out}")
    } else {
        out
    }
}

/// About three significant digits.
fn sig(x: f64) -> String {
    let a = x.abs();
    if a >= 1000.0 {
        int(x)
    } else if a >= 100.0 {
        format!("{x:.0}")
    } else if a >= 10.0 {
        format!("{x:.1}")
    } else if a >= 1.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.3}")
    }
}

/// A count or a median of counts (whole or half).
fn count(x: f64) -> String {
    if x.fract() == 0.0 {
        int(x)
    } else {
        format!("{x:.1}")
    }
}

fn opt(x: Option<f64>, f: fn(f64) -> String) -> String {
    x.map(f).unwrap_or_else(|| DASH.into())
}

fn describe_fit(what: &str, f: &Option<Fit>) -> String {
    match f {
        Some(f) => format!(
            "{what} ∝ n^{:.2} (r² = {:.3}, {} sizes, n = {} … {})",
            f.exponent,
            f.r2,
            f.points,
            int(f.x_range.0),
            int(f.x_range.1)
        ),
        None => format!("{what}: too few sizes to fit"),
    }
}

/// The heading of one family's table.
fn heading(cfg: &Config, family: Family) -> String {
    let mode = match cfg.mode {
        nmm::model::Mode::Dynamic => "dynamic",
        nmm::model::Mode::Static => "static",
    };
    match family {
        Family::Wall => format!(
            "Brick walls (running bond of 0.4 × 0.2 m bricks on a fixed base; cover {} m, {mode}, Δt = {} s)",
            cfg.wall_cover, cfg.dt
        ),
        Family::Slope => format!(
            "Jointed slopes (60° face, joint sets dipping 25° out of and 70° into the slope, 0.5 m apart{}; cover {} m, {mode}, Δt = {} s)",
            if cfg.stagger { ", staggered" } else { "" },
            cfg.slope_cover,
            cfg.dt
        ),
    }
}

/// The Markdown report: one table per family present, with its fits.
pub fn markdown(cfg: &Config, rows: &[Row], header: &str) -> String {
    let mut s = String::new();
    if !header.is_empty() {
        s += header;
        s += "\n\n";
    }
    let (s1, s2) = cfg.steps;
    for family in [Family::Wall, Family::Slope] {
        let fam: Vec<&Row> = rows.iter().filter(|r| r.case.family() == family).collect();
        if fam.is_empty() {
            continue;
        }
        let peer = fam.iter().any(|r| r.peer.is_some());
        s += &format!("### {}\n\n", heading(cfg, family));
        s += &format!(
            "Per step = (T({s2}) − T({s1})) / {}, median of {} repetition(s); stage times differenced the same way (ms per step); iterations, contacts and cuts of the {s2}-step run; peak memory = peak RSS of the {s2}-step process (MB = 10⁶ bytes).\n\n",
            s2 - s1,
            cfg.reps
        );
        let mut cols = vec![
            "size",
            "blocks",
            "unknowns",
            "contacts (max)",
            "iterations/step (median / max)",
            "cuts",
            "assembly",
            "contact",
            "factorisation",
            "solve",
            "ms/step",
            "peak MB",
        ];
        if peer {
            cols.extend(["ntdda ms/step", "nmm / ntdda", "ntdda peak MB"]);
        }
        s += &format!("| {} |\n", cols.join(" | "));
        s += &format!("|{}\n", "---|".repeat(cols.len()));
        for r in &fam {
            let i = &r.info;
            let mut cells = vec![
                r.case.label(),
                int(r.blocks as f64),
                opt(r.unknowns(), int),
                opt(i.contacts_max, int),
                match (i.iterations_median, i.iterations_max) {
                    (None, None) => DASH.into(),
                    (a, b) => format!("{} / {}", opt(a, count), opt(b, int)),
                },
                opt(i.cuts, int),
            ];
            if r.status == "ok" {
                cells.extend(r.stage_ms.iter().map(|x| opt(*x, sig)));
                cells.push(opt(r.per_step_ms, sig));
                cells.push(opt(r.peak_mb.or(r.peak_summary_mb), sig));
            } else {
                cells.extend(std::iter::repeat_n(DASH.to_string(), 5));
                cells.push(format!("{} ({})", DASH, r.status.replace('|', "/")));
            }
            if peer {
                match &r.peer {
                    Some(p) if p.status == "ok" => {
                        cells.push(opt(p.per_step_ms, sig));
                        cells.push(match (r.per_step_ms, p.per_step_ms) {
                            (Some(a), Some(b)) if b > 0.0 => format!("{}×", sig(a / b)),
                            _ => DASH.into(),
                        });
                        cells.push(opt(p.peak_mb, sig));
                    }
                    Some(p) => {
                        cells.push(p.status.clone());
                        cells.push(DASH.into());
                        cells.push(DASH.into());
                    }
                    None => cells.extend([DASH.into(), DASH.into(), DASH.into()]),
                }
            }
            s += &format!("| {} |\n", cells.join(" | "));
        }
        let sources: Vec<&str> = fam
            .iter()
            .map(|r| r.info.source.as_str())
            .filter(|s| *s != "summary.json")
            .collect();
        if !sources.is_empty() {
            s += "\nNo complete `summary.json` for some runs: their figures come from `history.csv` and the summary lines of `nmm run` on stderr where these have them (contacts only from `summary.json`).\n";
        }
        let f = fits(cfg, rows, family);
        s += "\n";
        if let (Some((a, b)), Some(_)) = (&f.range, &f.per_step) {
            s += &format!("Fitted over {a} … {b} (n = unknowns):\n\n");
        }
        s += &format!("- {}\n", describe_fit("nmm per-step cost", &f.per_step));
        s += &format!("- {}\n", describe_fit("nmm peak memory", &f.memory));
        if peer {
            s += &format!(
                "- {}\n",
                describe_fit("ntdda per-step cost", &f.peer_per_step)
            );
        }
        s += "\n";
    }
    s
}

fn fit_json(f: &Option<Fit>) -> Value {
    match f {
        Some(f) => json!({"exponent": f.exponent, "r2": f.r2, "points": f.points,
                          "unknowns_min": f.x_range.0, "unknowns_max": f.x_range.1}),
        None => Value::Null,
    }
}

/// One JSON object per row (`"kind": "row"`), then one per family fit (`"kind": "fit"`).
pub fn json_lines(cfg: &Config, rows: &[Row], version: Option<&str>) -> Vec<Value> {
    let mut out = Vec::new();
    for r in rows {
        let i = &r.info;
        let mut v = json!({
            "kind": "row",
            "family": r.case.family().name(),
            "size": r.case.label(),
            "status": r.status,
            "nmm_version": version,
            "steps": [cfg.steps.0, cfg.steps.1],
            "reps": cfg.reps,
            "dt": cfg.dt,
            "cover": match r.case.family() { Family::Wall => cfg.wall_cover, Family::Slope => cfg.slope_cover },
            "blocks": r.blocks,
            "unknowns": r.unknowns().map(|u| u.round() as u64),
            "physical_covers": r.check.physical_covers,
            "manifold_elements": r.check.manifold_elements,
            "contacts_max": i.contacts_max,
            "contacts_mean": i.contacts_mean,
            "iterations_total": i.iterations_total,
            "iterations_median": i.iterations_median,
            "iterations_max": i.iterations_max,
            "cuts": i.cuts,
            "cover_s": r.cover_s,
            "assembly_ms_per_step": r.stage_ms[0],
            "contact_ms_per_step": r.stage_ms[1],
            "factorisation_ms_per_step": r.stage_ms[2],
            "solve_ms_per_step": r.stage_ms[3],
            "ms_per_step": r.per_step_ms,
            "t_s1_s": r.t1_s,
            "t_s2_s": r.t2_s,
            "peak_memory_mb": r.peak_mb,
            "peak_memory_summary_mb": r.peak_summary_mb,
            "source": i.source,
        });
        match r.case {
            Case::Wall { nx, ny } => {
                v["nx"] = json!(nx);
                v["ny"] = json!(ny);
            }
            Case::Slope { blocks } => v["target_blocks"] = json!(blocks),
        }
        if let Some(p) = &r.peer {
            v["peer"] = json!({
                "status": p.status, "detail": p.detail, "blocks": p.blocks,
                "ms_per_step": p.per_step_ms, "t_s1_s": p.t1_s, "t_s2_s": p.t2_s,
                "peak_memory_mb": p.peak_mb,
            });
        }
        out.push(v);
    }
    for family in [Family::Wall, Family::Slope] {
        if !rows.iter().any(|r| r.case.family() == family) {
            continue;
        }
        let f = fits(cfg, rows, family);
        out.push(json!({
            "kind": "fit",
            "family": family.name(),
            "range": f.range.map(|(a, b)| [a, b]),
            "per_step": fit_json(&f.per_step),
            "peak_memory": fit_json(&f.memory),
            "peer_per_step": fit_json(&f.peer_per_step),
        }));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loglog_fit_recovers_a_power_law() {
        let pts: Vec<(f64, f64)> = [1e3, 4e3, 2e4, 1e5]
            .iter()
            .map(|&n: &f64| (n, 3e-4 * n.powf(1.3)))
            .collect();
        let f = fit_loglog(&pts).unwrap();
        assert!((f.exponent - 1.3).abs() < 1e-12 && (f.r2 - 1.0).abs() < 1e-12);
        assert_eq!((f.points, f.x_range), (4, (1e3, 1e5)));
        // Non-positive costs (noise at small sizes) are left out; one point is no fit.
        assert_eq!(fit_loglog(&[(1e3, -1.0), (1e4, 2.0)]), None);
        assert_eq!(fit_loglog(&[]), None);
    }

    #[test]
    fn numbers_are_formatted() {
        assert_eq!(int(120000.0), "120,000");
        assert_eq!(int(999.0), "999");
        assert_eq!(int(-1234.0), "-1,234");
        assert_eq!(sig(13760.4), "13,760");
        assert_eq!(sig(141.46), "141");
        assert_eq!(sig(18.64), "18.6");
        assert_eq!(sig(1.174), "1.17");
        assert_eq!(sig(0.1234), "0.123");
    }
}
