//! Friction laws on their own: step sequences of one contact, compared with
//! closed forms. `return_mapping` never exceeds the Coulomb strength; the
//! conventional rule overshoots it in the step where sliding starts.

use nmm::contact::friction::{
    commit_conventional, commit_return_mapping, conventional, return_mapping, ContactStatus,
    FrictionParams, LawResponse, ShearHistory,
};

/// The two Coulomb rules of `nmm::contact::friction`.
#[derive(Clone, Copy)]
enum FrictionAlgorithm {
    ReturnMapping,
    Conventional,
}

fn evaluate(
    alg: FrictionAlgorithm,
    p: &FrictionParams,
    h: &ShearHistory,
    gn: f64,
    dgs: f64,
) -> LawResponse {
    match alg {
        FrictionAlgorithm::ReturnMapping => return_mapping(p, h, gn, dgs),
        FrictionAlgorithm::Conventional => conventional(p, h, gn, dgs),
    }
}

fn commit(
    alg: FrictionAlgorithm,
    p: &FrictionParams,
    h: &ShearHistory,
    r: &LawResponse,
) -> ShearHistory {
    match alg {
        FrictionAlgorithm::ReturnMapping => commit_return_mapping(p, h, r),
        FrictionAlgorithm::Conventional => commit_conventional(p, h, r),
    }
}

/// The direct-shear numbers of the paper: 1 MPa on 1 m, penalty 100 GN/m, φ = 30°.
fn direct_shear_params() -> FrictionParams {
    FrictionParams {
        pn: 1.0e11,
        ps: 1.0e11,
        tan_phi: 30f64.to_radians().tan(),
        cohesion: 0.0,
        dashpot: 0.0,
        gn0: 0.0,
        own: [0.0; 4],
    }
}

const GN: f64 = -1.0e-5; // t_N = −1 MN/m
/// Shear stiffness of the block in series with the contact (G A / H), N/m.
const KB: f64 = 1.0e10;

/// Shear through an elastic block in series with the contact: the top of the
/// block is moved by `du` per step; per step solve `k_b (U − G_n − d) = t_S(d)`
/// for the contact increment `d` by Newton with the law's tangent.
fn shear_through_block(alg: FrictionAlgorithm, steps: usize, du: f64) -> Vec<(LawResponse, f64)> {
    let p = direct_shear_params();
    let kb = KB;
    let mut h = ShearHistory::default();
    let (mut u, mut g_total) = (0.0, 0.0);
    let mut out = Vec::new();
    for _ in 0..steps {
        u += du;
        let mut d = 0.0;
        let mut r = evaluate(alg, &p, &h, GN, d);
        for _ in 0..50 {
            let res = r.ts - kb * (u - g_total - d);
            if res.abs() <= 1e-9 * p.strength(r.tn) {
                break;
            }
            d -= res / (r.dts_dgs + kb);
            r = evaluate(alg, &p, &h, GN, d);
        }
        assert!(
            (r.ts - kb * (u - g_total - d)).abs() <= 1e-6 * p.strength(r.tn),
            "step did not converge"
        );
        g_total += d;
        out.push((r, p.strength(r.tn)));
        h = commit(alg, &p, &h, &r);
    }
    out
}

#[test]
fn monotonic_shear_return_mapping_never_exceeds_strength() {
    // 0.06 mm per step up to 0.3 mm, as in the paper.
    let rm = shear_through_block(FrictionAlgorithm::ReturnMapping, 5, 6.0e-5);
    let s = 1.0e6 * 30f64.to_radians().tan();
    for (r, strength) in &rm {
        assert!((strength - s).abs() < 1e-6 * s);
        assert!(
            r.ts <= strength * (1.0 + 1e-12),
            "return mapping exceeded the strength: {} > {}",
            r.ts,
            strength
        );
    }
    // Elastic first step: springs in series, k_b p_S/(k_b + p_S) du = 545 kN/m < S.
    let p = direct_shear_params();
    assert_eq!(rm[0].0.status, ContactStatus::Stick);
    let series = KB * p.ps / (KB + p.ps) * 6.0e-5;
    assert!((rm[0].0.ts - series).abs() < 1e-6 * series);
    let sliding: Vec<_> = rm
        .iter()
        .filter(|(r, _)| r.status == ContactStatus::Slide)
        .collect();
    assert!(!sliding.is_empty());
    for (r, strength) in sliding {
        assert!((r.ts - strength).abs() <= 1e-9 * strength);
    }
}

#[test]
fn monotonic_shear_conventional_overshoots_then_pulls_back() {
    let conv = shear_through_block(FrictionAlgorithm::Conventional, 5, 6.0e-5);
    let rm = shear_through_block(FrictionAlgorithm::ReturnMapping, 5, 6.0e-5);
    // Find the first step where the conventional force exceeds the strength.
    let first = conv
        .iter()
        .position(|(r, s)| r.ts > *s * (1.0 + 1e-6))
        .expect("the conventional rule must overshoot");
    let (r, s) = conv[first];
    assert_eq!(r.status, ContactStatus::Stick);
    // The overshoot is the elastic force of the two springs in series after two steps.
    assert_eq!(first, 1);
    assert!(
        r.ts > rm[first].0.ts,
        "conventional {} vs return mapping {}",
        r.ts,
        rm[first].0.ts
    );
    let series = KB * 1.0e11 / (KB + 1.0e11) * 2.0 * 6.0e-5;
    assert!(
        (r.ts - series).abs() < 1e-6 * series,
        "elastic force {} vs {series}",
        r.ts
    );
    // Next step: sliding at the strength of the committed normal force.
    let (r2, s2) = conv[first + 1];
    assert_eq!(r2.status, ContactStatus::Slide);
    assert!((r2.ts - s2).abs() <= 1e-9 * s);
    println!(
        "overshoot at step {}: conventional {:.1} N/m, strength {:.1} N/m ({:.1} %)",
        first + 1,
        r.ts,
        s,
        100.0 * (r.ts / s - 1.0)
    );
}

#[test]
fn load_reversal_slide_stick_slide_other_way() {
    let p = direct_shear_params();
    let s = p.strength(p.pn * GN);
    let mut h = ShearHistory::default();
    let mut log = Vec::new();
    // 3 steps forward, 5 steps back, increments imposed directly on the contact.
    for dgs in [4e-6, 4e-6, 4e-6, -2e-6, -2e-6, -2e-6, -2e-6, -2e-6, -2e-6] {
        let r = return_mapping(&p, &h, GN, dgs);
        h = commit(FrictionAlgorithm::ReturnMapping, &p, &h, &r);
        log.push((r.status, r.ts));
    }
    use ContactStatus::*;
    // Forward: trial 4e5 < S (stick), then 8e5 > S (slide), slide.
    assert_eq!(log[0].0, Stick);
    assert_eq!(log[1].0, Slide);
    assert_eq!(log[2].0, Slide);
    assert!((log[2].1 - s).abs() < 1e-9 * s);
    // Reverse: elastic unloading from +S: S − 2e5, S − 4e5, ... then slide at −S.
    assert_eq!(log[3].0, Stick);
    assert!((log[3].1 - (s - 2e5)).abs() < 1e-6 * s);
    assert_eq!(log[4].0, Stick);
    let first_back_slide = log
        .iter()
        .position(|(st, ts)| *st == Slide && *ts < 0.0)
        .expect("must slide back");
    // |S − k·2e5| ≥ S first at k = 6 (2S/2e5 = 5.77): step index 3 + 5 = 8.
    assert_eq!(first_back_slide, 8);
    assert!((log[8].1 + s).abs() < 1e-9 * s);

    // The conventional rule reverses the same way, but only after its one-step lags:
    // sliding starts a step late, and the reversal is seen at the end of the step.
    let mut h = ShearHistory::default();
    let mut conv = Vec::new();
    for dgs in [4e-6, 4e-6, 4e-6, -2e-6, -2e-6] {
        let r = conventional(&p, &h, GN, dgs);
        h = commit(FrictionAlgorithm::Conventional, &p, &h, &r);
        conv.push((r.status, r.ts));
    }
    assert_eq!(conv[1].0, Stick); // 8e5 > S: overshoot, switched at commit
    assert!(conv[1].1 > s);
    assert_eq!(conv[2].0, Slide);
    assert!((conv[2].1 - s).abs() < 1e-9 * s);
    assert_eq!(conv[3].0, Slide); // mode frozen within the step: still the friction force
    assert!((conv[3].1 - s).abs() < 1e-9 * s);
    assert_eq!(conv[4].0, Stick); // reversal seen at commit: elastic from g_S^e = S/p_S
    assert!((conv[4].1 - (s - 2e5)).abs() < 1e-6 * s);
}

/// Two unknowns x = (g_N, Δg_S) loaded through a coupled elastic frame `K`:
/// `R(x) = t(x) + K x − f = 0`. The slide branch is linear in x, so Newton
/// with the consistent tangent ends in a couple of iterations; dropping the
/// unsymmetric term ∂t_S/∂g_N slows it to linear convergence.
fn newton_iterations(p: &FrictionParams, drop_coupling: bool) -> (usize, [f64; 2]) {
    let k = [[2.0e9, 1.0e9], [1.0e9, 2.0e9]];
    let h = ShearHistory::default();
    // Solution chosen in the slide regime: g_N = −1e-5, Δg_S = 1e-3.
    let xs = [-1.0e-5, 1.0e-3];
    let rs = return_mapping(p, &h, xs[0], xs[1]);
    assert_eq!(rs.status, ContactStatus::Slide);
    let f = [
        rs.tn + k[0][0] * xs[0] + k[0][1] * xs[1],
        rs.ts + k[1][0] * xs[0] + k[1][1] * xs[1],
    ];
    let mut x = [-1.0e-6, 0.0];
    for it in 0..200 {
        let r = return_mapping(p, &h, x[0], x[1]);
        let res = [
            r.tn + k[0][0] * x[0] + k[0][1] * x[1] - f[0],
            r.ts + k[1][0] * x[0] + k[1][1] * x[1] - f[1],
        ];
        if res[0].hypot(res[1]) <= 1e-10 * f[0].hypot(f[1]) {
            return (it, x);
        }
        let dts_dgn = if drop_coupling { 0.0 } else { r.dts_dgn };
        let j = [
            [r.dtn_dgn + k[0][0], r.dtn_dgs + k[0][1]],
            [dts_dgn + k[1][0], r.dts_dgs + k[1][1]],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        x[0] -= (j[1][1] * res[0] - j[0][1] * res[1]) / det;
        x[1] -= (-j[1][0] * res[0] + j[0][0] * res[1]) / det;
    }
    (usize::MAX, x)
}

#[test]
fn newton_with_consistent_tangent_converges_in_few_iterations() {
    let p = FrictionParams {
        pn: 1.0e11,
        ps: 1.0e9,
        tan_phi: 0.6,
        cohesion: 0.0,
        dashpot: 0.0,
        gn0: 0.0,
        own: [0.0; 4],
    };
    let (it_consistent, x) = newton_iterations(&p, false);
    let (it_dropped, _) = newton_iterations(&p, true);
    assert!(
        it_consistent <= 4,
        "consistent tangent took {it_consistent} iterations"
    );
    assert!((x[0] + 1.0e-5).abs() < 1e-12 && (x[1] - 1.0e-3).abs() < 1e-10);
    assert!(
        it_dropped > it_consistent + 2,
        "dropped coupling: {it_dropped} vs {it_consistent}"
    );
    println!("Newton iterations: consistent {it_consistent}, without dts/dgn {it_dropped}");
}

/// The return mapping at every point of a grid of (g_N, Δg_S) and committed states,
/// against the closed form written out here (trial t_S = p_S (g_S^e|ₙ + Δg_S); stick below
/// S = |p_N g_N| tan φ + c, else t_S = sgn(trial) S with slip (trial − t_S)/p_S), and its
/// tangent against central differences of the forces (relative 1e-6: the differences'
/// round-off at a step of 1e-7 of the gaps, away from the stick/slide boundary). The
/// response depends on the committed state and the current gaps only (it is evaluated at
/// every Newton iterate from the committed state), so a grid of states covers it.
/// (Replaces a check that called the pure function twice and compared the results.)
#[test]
fn return_mapping_matches_the_closed_form_and_its_tangent() {
    let p = FrictionParams {
        pn: 1.0e10,
        ps: 2.0e9,
        tan_phi: 35f64.to_radians().tan(),
        cohesion: 5.0e3,
        dashpot: 0.0,
        gn0: 0.0,
        own: [0.0; 4],
    };
    let mut n = [0usize; 3];
    for ge0 in [-4e-6, 0.0, 1e-6, 3e-6] {
        for status in [ContactStatus::Stick, ContactStatus::Slide] {
            let h = ShearHistory {
                ge: ge0,
                status,
                tn: -2e4,
                slide_sign: if status == ContactStatus::Slide {
                    1.0
                } else {
                    0.0
                },
            };
            for gn in [1e-7, -1e-7, -1e-6, -3e-6] {
                for dgs in [-2e-5, -3e-6, -1e-7, 0.0, 1e-7, 2e-6, 5e-6, 1e-4] {
                    let r = return_mapping(&p, &h, gn, dgs);
                    if gn >= 0.0 {
                        n[0] += 1;
                        assert_eq!((r.tn, r.ts, r.status), (0.0, 0.0, ContactStatus::Open));
                        continue;
                    }
                    let tn = p.pn * gn;
                    let strength = -tn * p.tan_phi + p.cohesion;
                    let trial = p.ps * (ge0 + dgs);
                    let (ts, slip, status) = if trial.abs() < strength {
                        (trial, 0.0, ContactStatus::Stick)
                    } else {
                        let ts = trial.signum() * strength;
                        (ts, (trial - ts) / p.ps, ContactStatus::Slide)
                    };
                    n[if status == ContactStatus::Stick { 1 } else { 2 }] += 1;
                    let what = format!("ge {ge0}, {status:?}, gn {gn}, dgs {dgs}: {r:?}");
                    assert_eq!(r.status, status, "{what}");
                    assert!((r.tn - tn).abs() <= 1e-12 * tn.abs(), "{what}");
                    assert!((r.ts - ts).abs() <= 1e-9 * strength, "{what}");
                    assert!((r.slip - slip).abs() <= 1e-9 * strength / p.ps, "{what}");
                    assert!((r.ge * p.ps - ts).abs() <= 1e-9 * strength, "{what}");
                    assert!(r.ts.abs() <= strength * (1.0 + 1e-12), "{what}");
                    // the tangent against central differences, away from the boundary
                    if (trial.abs() - strength).abs() > 0.01 * strength {
                        let (eg, es) = (1e-7 * gn.abs(), 1e-7 * gn.abs());
                        let f = |g: f64, d: f64| {
                            let q = return_mapping(&p, &h, g, d);
                            (q.tn, q.ts)
                        };
                        let (a, b) = (f(gn + eg, dgs), f(gn - eg, dgs));
                        let (c, d) = (f(gn, dgs + es), f(gn, dgs - es));
                        let fd = [
                            (a.0 - b.0) / (2.0 * eg),
                            (c.0 - d.0) / (2.0 * es),
                            (a.1 - b.1) / (2.0 * eg),
                            (c.1 - d.1) / (2.0 * es),
                        ];
                        let an = [r.dtn_dgn, r.dtn_dgs, r.dts_dgn, r.dts_dgs];
                        for k in 0..4 {
                            assert!(
                                (fd[k] - an[k]).abs() <= 1e-6 * p.pn,
                                "{what}: tangent {k}: {} vs differences {}",
                                an[k],
                                fd[k]
                            );
                        }
                    }
                }
            }
        }
    }
    // the grid reaches the three branches
    assert!(n.iter().all(|&k| k >= 8), "{n:?}");
}
