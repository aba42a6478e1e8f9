//! Bonded joints that break (`[[interface]] tensile_strength`, `residual_friction_angle`;
//! `nmm::contact::bonded`).
//!
//! * The law alone: each branch (elastic in compression and in tension, shear yield,
//!   tension cut-off, corner, broken) against its closed form, its tangent against central
//!   finite differences, the branches continuous where they meet, the commit that breaks.
//! * A block hanging from a bonded joint under its weight W: it holds at W = 0.99 T L and
//!   falls at W = 1.01 T L (the threshold within 1%), then falls freely (Δv = −g Δt).
//! * A direct shear of a bonded joint peaks at c + σ_n tan φ (within 0.5%) and drops to
//!   σ_n tan φ_r (within 0.5%).
//! * An interface with `cohesion` and no `tensile_strength` keeps the analysis' law.

use nmm::contact::bonded::{self, corner, Bond, BondState, Bonded, TENSION};
use nmm::contact::friction::{ContactStatus, FrictionParams, LawResponse, ShearHistory};
use nmm::contact::law::{Branch, FrictionLaw, IterationContext, LawId};
use nmm::simulation::{monitor_values, Simulation};

const TAN35: f64 = 0.700_207_538_209_709_9;
const TAN25: f64 = 0.466_307_658_154_998_6;

/// c = 200 kN/m, T = 50 kN/m (below the apex c / tan φ = 286 kN/m), φ = 35°, φ_r = 25°.
const P: FrictionParams = FrictionParams {
    pn: 1.0e10,
    ps: 2.0e9,
    tan_phi: TAN35,
    cohesion: 2.0e5,
    dashpot: 0.0,
    gn0: 0.0,
    own: [5.0e4, TAN25, 0.0, 0.0],
};

fn intact(ge: f64) -> BondState {
    BondState {
        shear: ShearHistory {
            ge,
            status: ContactStatus::Stick,
            tn: -1e5,
            slide_sign: 0.0,
        },
        bond: Bond::Intact,
    }
}

fn broken(ge: f64) -> BondState {
    BondState {
        bond: Bond::Broken,
        ..intact(ge)
    }
}

fn close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * b.abs().max(1.0),
        "{what}: {a} vs closed form {b}"
    );
}

/// The five branches at points inside each (g_N, Δg_S), with the committed elastic gap
/// g_S^e|ₙ = 1e-5: (name, state, g_N, Δg_S, branch).
fn branch_points() -> Vec<(&'static str, BondState, f64, f64, Branch)> {
    vec![
        (
            "elastic, compression",
            intact(1e-5),
            -1e-5,
            2e-5,
            Branch::Stick,
        ),
        ("elastic, tension", intact(1e-5), 3e-6, 2e-5, Branch::Stick),
        ("shear yield", intact(1e-5), -1e-5, 2e-4, Branch::Slide(1)),
        (
            "shear yield, tension",
            intact(1e-5),
            2e-6,
            -2e-4,
            Branch::Slide(-1),
        ),
        ("tension cut-off", intact(1e-5), 1e-5, 2e-5, TENSION),
        ("corner", intact(1e-5), 1e-5, -2e-4, corner(-1)),
        ("broken, slide", broken(1e-5), -1e-5, 2e-4, Branch::Slide(1)),
        ("broken, stick", broken(1e-5), -1e-5, 1e-6, Branch::Stick),
        ("broken, open", broken(1e-5), 1e-5, 2e-5, Branch::Open),
    ]
}

/// The closed forms of the module docs, written out: (t_N, t_S, Δγ, Δg_N^p, status).
fn closed_form(h: &BondState, gn: f64, dgs: f64) -> (f64, f64, f64, f64, ContactStatus) {
    let (c, t, tp, tpr) = (2.0e5, 5.0e4, TAN35, TAN25);
    let tn = 1.0e10 * gn;
    let trial = 2.0e9 * (h.shear.ge + dgs);
    if h.residual() {
        if gn >= 0.0 {
            return (0.0, 0.0, 0.0, 0.0, ContactStatus::Open);
        }
        let s = -tn * tpr;
        return if trial.abs() < s {
            (tn, trial, 0.0, 0.0, ContactStatus::Stick)
        } else {
            let ts = trial.signum() * s;
            (tn, ts, (trial - ts) / 2.0e9, 0.0, ContactStatus::Slide)
        };
    }
    let (n, opening) = if tn > t {
        (t, (tn - t) / 1.0e10)
    } else {
        (tn, 0.0)
    };
    let s = c - n * tp;
    if trial.abs() < s {
        let status = ContactStatus::Stick;
        (n, trial, 0.0, opening, status)
    } else {
        let ts = trial.signum() * s;
        (n, ts, (trial - ts) / 2.0e9, opening, ContactStatus::Slide)
    }
}

#[test]
fn each_branch_is_its_closed_form() {
    for (name, h, gn, dgs, branch) in branch_points() {
        let r = bonded::bonded(&P, &h, gn, dgs);
        let (tn, ts, slip, opening, status) = closed_form(&h, gn, dgs);
        eprintln!(
            "{name:24} t_N {:>10.1} t_S {:>10.1} Δγ {:.3e} Δg_N^p {:.3e} {:?}",
            r.tn, r.ts, r.slip, r.opening, r.status
        );
        assert_eq!(r.status, status, "{name}");
        close(r.tn, tn, 1e-14, name);
        close(r.ts, ts, 1e-14, name);
        close(r.slip, slip, 1e-9, name);
        close(r.opening, opening, 1e-12, name);
        // the elastic gap is what the shear force stretches
        close(r.ge * P.ps, r.ts, 1e-12, name);
        // the law's branch, and its response through the trait is the pure function
        let s = h.to_state();
        assert_eq!(Bonded.branch(&P, &s, gn, dgs), branch, "{name}");
        assert_eq!(Bonded.response(&P, &s, gn, dgs), r, "{name}");
        // on the yield surfaces: never above the strength
        if !h.residual() {
            assert!(r.tn <= 5.0e4 * (1.0 + 1e-15), "{name}");
            assert!(
                r.ts.abs() <= (2.0e5 - r.tn * TAN35) * (1.0 + 1e-15),
                "{name}"
            );
        }
    }
    // the tension cut-off: t_N = T while the shear spring stays elastic
    let r = bonded::bonded(&P, &intact(1e-5), 1e-5, 2e-5);
    assert_eq!((r.tn, r.slip), (5.0e4, 0.0));
    close(r.ts, 6.0e4, 1e-15, "tension: elastic shear");
    close(r.opening, 5.0e-6, 1e-15, "tension: opening");
    // the corner: t_N = T, t_S = −(c − T tan φ)
    let r = bonded::bonded(&P, &intact(1e-5), 1e-5, -2e-4);
    close(r.ts, -(2.0e5 - 5.0e4 * TAN35), 1e-15, "corner");
}

/// Central finite differences of (t_N, t_S) in (g_N, Δg_S) against the branch's tangent,
/// at every branch point (steps of 1e-9 of the gaps: each point is far from its branch's
/// boundaries).
#[test]
fn the_tangent_of_every_branch_matches_finite_differences() {
    let mut checked = std::collections::BTreeSet::new();
    for (name, h, gn, dgs, branch) in branch_points() {
        let r = bonded::bonded(&P, &h, gn, dgs);
        let (eg, es) = (1e-9 * gn.abs(), 1e-9 * dgs.abs());
        let f = |g: f64, d: f64| {
            let q = bonded::bonded(&P, &h, g, d);
            assert_eq!(bonded_branch(&h, g, d), branch, "{name}: left its branch");
            (q.tn, q.ts)
        };
        let ((a1, b1), (a0, b0)) = (f(gn + eg, dgs), f(gn - eg, dgs));
        let ((c1, d1), (c0, d0)) = (f(gn, dgs + es), f(gn, dgs - es));
        let fd = [
            (a1 - a0) / (2.0 * eg),
            (c1 - c0) / (2.0 * es),
            (b1 - b0) / (2.0 * eg),
            (d1 - d0) / (2.0 * es),
        ];
        let an = [r.dtn_dgn, r.dtn_dgs, r.dts_dgn, r.dts_dgs];
        for (k, (x, y)) in fd.iter().zip(an).enumerate() {
            assert!(
                (x - y).abs() <= 1e-6 * P.pn,
                "{name}: ∂ #{k}: finite differences {x} vs tangent {y}"
            );
        }
        eprintln!("{name:24} tangent {an:?}");
        checked.insert(format!("{branch:?}"));
    }
    // the shear-yield tangent is the unsymmetric consistent one, −s p_N tan φ
    let r = bonded::bonded(&P, &intact(1e-5), -1e-5, 2e-4);
    assert_eq!(r.dts_dgn, -P.pn * TAN35);
    assert_eq!(r.dtn_dgs, 0.0);
    // tension and corner carry no normal stiffness
    assert_eq!(bonded::bonded(&P, &intact(1e-5), 1e-5, 2e-5).dtn_dgn, 0.0);
    assert_eq!(checked.len(), 6, "{checked:?}");
}

fn bonded_branch(h: &BondState, gn: f64, dgs: f64) -> Branch {
    Bonded.branch(&P, &h.to_state(), gn, dgs)
}

/// Each branch's affine continuation (`on_branch`) is exactly affine with its tangent, and
/// the branches meet continuously: across each boundary the forces jump by no more than
/// the stiffness times the step across.
#[test]
fn branches_are_affine_and_meet_continuously() {
    let h = intact(1e-5);
    let s = h.to_state();
    for b in [
        Branch::Stick,
        Branch::Slide(1),
        Branch::Slide(-1),
        TENSION,
        corner(1),
        corner(-1),
    ] {
        let (gn, dgs) = (2e-6, 3e-5);
        let r = Bonded.on_branch(&P, &s, gn, dgs, b);
        for (dn, ds) in [(1e-7, 0.0), (0.0, 1e-5), (-2e-6, 3e-5), (5e-6, -1e-4)] {
            let q = Bonded.on_branch(&P, &s, gn + dn, dgs + ds, b);
            let tn = r.tn + r.dtn_dgn * dn + r.dtn_dgs * ds;
            let ts = r.ts + r.dts_dgn * dn + r.dts_dgs * ds;
            assert!((q.tn - tn).abs() <= 1e-9 * tn.abs().max(1.0), "{b:?}");
            assert!((q.ts - ts).abs() <= 1e-9 * ts.abs().max(1.0), "{b:?}");
        }
    }
    // boundaries: t_N^tr = T (g_N = 5e-6) at several shear gaps; |t_S^tr| = S at several
    // normal gaps
    let d = 1e-12;
    let jump = |a: LawResponse, b: LawResponse| (a.tn - b.tn).abs().max((a.ts - b.ts).abs());
    let mut crossings = 0;
    for dgs in [-2e-4, -5e-5, 0.0, 2e-5, 2e-4] {
        let (a, b) = (
            bonded::bonded(&P, &h, 5e-6 - d, dgs),
            bonded::bonded(&P, &h, 5e-6 + d, dgs),
        );
        assert!(jump(a, b) <= 2.0 * P.pn * d, "t_N = T at Δg_S {dgs}");
        crossings +=
            usize::from(bonded_branch(&h, 5e-6 - d, dgs) != bonded_branch(&h, 5e-6 + d, dgs));
    }
    for gn in [-2e-5, -1e-6, 2e-6, 1e-5] {
        let tn = (P.pn * gn).min(5.0e4);
        let strength = 2.0e5 - tn * TAN35;
        for sgn in [1.0, -1.0] {
            let at = sgn * strength / P.ps - 1e-5;
            let (a, b) = (
                bonded::bonded(&P, &h, gn, at - d),
                bonded::bonded(&P, &h, gn, at + d),
            );
            assert!(jump(a, b) <= 2.0 * P.ps * d, "|t_S| = S at g_N {gn}");
            crossings +=
                usize::from(bonded_branch(&h, gn, at - d) != bonded_branch(&h, gn, at + d));
        }
    }
    assert_eq!(crossings, 5 + 8, "every probe crosses a boundary");
}

#[test]
fn a_contact_breaks_on_any_yield_branch_and_for_good() {
    let law = LawId::by_name("bonded").unwrap().law();
    for (name, h, gn, dgs, branch) in branch_points() {
        let s = h.to_state();
        let r = law.response(&P, &s, gn, dgs);
        let c = BondState::from_state(&law.commit(&P, &s, &r));
        let yielded = matches!(branch, Branch::Slide(_) | Branch::Limit(..));
        let breaks = h.bond == Bond::Broken || yielded;
        assert_eq!(c.bond == Bond::Broken, breaks, "{name}");
        assert_eq!(law.lasting(&law.commit(&P, &s, &r)), breaks, "{name}");
        assert_eq!(law.bond(&law.commit(&P, &s, &r)), Some(!breaks), "{name}");
        if yielded && h.bond == Bond::Intact {
            // the residual law starts from the peak force's elastic gap
            close(c.shear.ge, r.ts / P.ps, 1e-15, name);
            let next = bonded::bonded(&P, &c, -1e-5, 0.0);
            if gn < 0.0 {
                close(next.ts.abs(), 1e5 * TAN25, 1e-12, "the residual strength");
            }
        }
    }
    // intact in the elastic domain stays intact; a broken contact never bonds again
    let s = intact(0.0).to_state();
    let r = law.response(&P, &s, -1e-5, 1e-5);
    assert_eq!(law.bond(&law.commit(&P, &s, &r)), Some(true));
    let b = broken(0.0).to_state();
    let r = law.response(&P, &b, -1e-5, 1e-9);
    assert_eq!(r.status, ContactStatus::Stick);
    assert_eq!(law.bond(&law.commit(&P, &b, &r)), Some(false));
    // bonds form between faces touching at the start only; the others never had one
    // (residual friction, not counted as broken, not kept)
    assert_eq!(law.bond(&law.new_state(true, true)), Some(true));
    for (touching, at_start) in [(false, true), (true, false), (false, false)] {
        let n = law.new_state(touching, at_start);
        assert_eq!(law.bond(&n), None);
        assert!(!law.lasting(&n));
        let r = law.response(&P, &n, -1e-5, 2e-4);
        close(r.ts, 1e5 * TAN25, 1e-12, "never bonded: residual friction");
        assert_eq!(law.bond(&law.commit(&P, &n, &r)), None);
    }
    // the state's words round-trip and are checked
    let st = broken(-3e-6).to_state();
    assert_eq!(BondState::from_state(&st), broken(-3e-6));
    assert!(law.valid_state(&st));
    let mut bad = st;
    bad.0[4] = 3;
    assert!(!law.valid_state(&bad));
    // the spring forces at a step's start: an intact bond holds tension
    assert_eq!(
        law.start_forces(&P, &intact(1e-5).to_state(), 2e-6),
        (2e4, 2e4)
    );
    assert_eq!(
        law.start_forces(&P, &broken(1e-5).to_state(), 2e-6),
        (0.0, 2e4)
    );
}

#[test]
fn a_tensile_strength_above_the_apex_is_cut_at_the_apex() {
    // T = 400 kN/m > c / tan φ = 285.6 kN/m: the bond carries at most the apex tension
    let p = FrictionParams {
        own: [4.0e5, TAN25, 0.0, 0.0],
        ..P
    };
    let apex = 2.0e5 / TAN35;
    assert_eq!(bonded::tensile_force(&p), apex);
    let r = bonded::bonded(&p, &intact(0.0), 1e-4, 1e-9);
    close(r.tn, apex, 1e-15, "apex");
    assert_eq!(r.status, ContactStatus::Slide, "at the apex the corner");
    assert!(
        r.ts.abs() <= 1e-9 * 2.0e5,
        "no shear strength at the apex: {}",
        r.ts
    );
    // without cohesion and tensile strength the bond breaks on any tension
    let p = FrictionParams {
        cohesion: 0.0,
        own: [0.0, TAN25, 0.0, 0.0],
        ..P
    };
    let r = bonded::bonded(&p, &intact(0.0), 1e-7, 0.0);
    assert_eq!((r.tn, r.ts), (0.0, 0.0));
    assert_eq!(
        BondState::from_state(&Bonded.commit(&p, &intact(0.0).to_state(), &r)).bond,
        Bond::Broken
    );
}

/// The semi-smooth rules: an intact contact on a shear limit that would reverse is held
/// elastic in shear for one iterate; a broken one follows the return mapping's rules.
#[test]
fn iteration_rules() {
    let s = intact(0.0).to_state();
    let ctx = |previous| IterationContext {
        previous,
        touching: true,
    };
    assert_eq!(
        Bonded.iteration_branch(&P, &s, -1e-5, -2e-4, ctx(Some(Branch::Slide(1)))),
        Branch::Stick
    );
    assert_eq!(
        Bonded.iteration_branch(&P, &s, 1e-5, -2e-4, ctx(Some(corner(1)))),
        TENSION
    );
    assert_eq!(
        Bonded.iteration_branch(&P, &s, 1e-5, -2e-4, ctx(None)),
        corner(-1)
    );
    // broken and touching: the closed-contact predictor at the first iterate
    let b = BondState::NEVER.to_state();
    assert_eq!(Bonded.branch(&P, &b, 1e-12, 0.0), Branch::Open);
    assert_eq!(
        Bonded.iteration_branch(&P, &b, 1e-12, 0.0, ctx(None)),
        Branch::Stick
    );
}

#[test]
fn the_model_reads_the_keys_into_the_bonded_law() {
    let law = LawId::by_name("bonded").unwrap();
    assert_eq!(law.keys(), ["tensile_strength", "residual_friction_angle"]);
    let v = law
        .law()
        .interface_values(35.0, 1e5, &[Some(5e4), None])
        .unwrap();
    assert_eq!(v, [5e4, 35.0], "φ_r defaults to φ");
    let v = law
        .law()
        .interface_values(35.0, 1e5, &[None, Some(25.0)])
        .unwrap();
    assert_eq!(v, [0.0, 25.0], "T defaults to 0");
    assert_eq!(
        law.law()
            .interface_values(35.0, 1e5, &[Some(-1.0), None])
            .unwrap_err()
            .0,
        0
    );
    assert_eq!(
        law.law()
            .interface_values(35.0, 1e5, &[None, Some(36.0)])
            .unwrap_err()
            .0,
        1
    );
    let own = law.law().own_constants(&[5e4, 25.0], 0.02);
    assert_eq!(own[0], 5e4 * 0.02);
    close(own[1], TAN25, 1e-15, "tan φ_r");
    assert!(law
        .law()
        .interface_warning(35.0, 1e4, &[5e4, 25.0])
        .is_some());
    assert!(law
        .law()
        .interface_warning(35.0, 1e5, &[5e4, 25.0])
        .is_none());
}

// ------------------------------------------------------------ the whole pipeline

fn simulate(text: &str) -> Simulation {
    Simulation::new(nmm::verify::cases::model(text).unwrap()).unwrap()
}

const RHO: f64 = 2000.0;
const G: f64 = 9.81;

/// A 1 m × 0.5 m block (ν = 0, so that its weight hangs as a uniform pull on its top face)
/// bonded under a fixed roof along L = 1 m, its weight W = ρ g A = 9810 N/m, with the
/// tensile strength `t` (Pa) and a cohesion far above it: a static stage applies the
/// weight, then a dynamic one lets go (free fall if the bond broke). The joint is 100
/// times softer than the block (penalties 1e8 N/m against E = 1e10 Pa) so that the weight
/// pulls every contact alike (to 0.1%); with penalties as stiff as E the block's own
/// stretch under its weight loads the joint's ends 4% more than its middle.
fn hanging_block(t: f64) -> String {
    format!(
        "[analysis]\ngravity = [0.0, -{G}]\n[cover]\nsize = 0.125\n\
         [[material]]\nname = \"rock\"\ndensity = {RHO}\nyoung = 1.0e10\npoisson = 0.0\n\
         [[block]]\nname = \"roof\"\nmaterial = \"rock\"\nvertices = [[0.0, 1.0], [2.0, 1.0], [2.0, 1.5], [0.0, 1.5]]\nfixed = true\n\
         [[block]]\nname = \"hanging\"\nmaterial = \"rock\"\nvertices = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.0], [0.5, 1.0]]\n\
         [[interface]]\nfriction_angle = 30.0\ncohesion = 1.0e6\ntensile_strength = {t}\nnormal_penalty = 1.0e8\nshear_penalty = 1.0e8\n\
         [[monitor]]\nname = \"c\"\npoint = [1.0, 0.75]\n\
         [[monitor]]\nname = \"joint\"\ninterface = [\"hanging\", \"roof\"]\n\
         [[stage]]\nname = \"load\"\nmode = \"static\"\ndt = 1.0\nsteps = 2\n\
         [[stage]]\nname = \"let go\"\nmode = \"dynamic\"\ndt = 0.01\nsteps = 20\n"
    )
}

struct Hang {
    /// uy of the block's centre and the joint's fy at the end of the static stage.
    uy_loaded: f64,
    fy_loaded: f64,
    /// (intact, broken) bonds after the static stage.
    bonds: (usize, usize),
    /// vy at the end of the static stage and at the end, and the time between.
    vy: (f64, f64),
    uy_end: f64,
    duration: f64,
}

fn hang(t: f64) -> Hang {
    let mut sim = simulate(&hanging_block(t));
    let mut loaded = None;
    while !sim.finished() {
        sim.advance().unwrap();
        let v = monitor_values(&sim);
        if sim.stage_name() == Some("load") && sim.stage_finished() {
            loaded = Some((v[1], v[5], v[3], sim.time, sim.contacts.bond_counts()));
        }
    }
    let (uy_loaded, fy_loaded, vy0, t0, bonds) = loaded.unwrap();
    let v = monitor_values(&sim);
    Hang {
        uy_loaded,
        fy_loaded,
        bonds,
        vy: (vy0, v[3]),
        uy_end: v[1],
        duration: sim.time - t0,
    }
}

#[test]
fn a_block_hangs_below_its_tensile_strength_and_falls_above_it() {
    let w = RHO * G * 0.5;
    let l = 1.0;
    // W = 0.99 T L: the bond holds, the joint carries the weight, nothing moves
    let t_hold = w / (0.99 * l);
    let h = hang(t_hold);
    eprintln!(
        "W = 0.99 T L: uy {:.3e} m after loading, fy {:.2} N/m (W = {w}), bonds {:?}, uy at the end {:.3e} m",
        h.uy_loaded, h.fy_loaded, h.bonds, h.uy_end
    );
    assert_eq!(h.bonds.1, 0, "no bond broke");
    assert!(h.bonds.0 > 0);
    assert!(
        (h.fy_loaded / w - 1.0).abs() < 1e-6,
        "the joint holds the weight"
    );
    assert!(h.uy_loaded.abs() < 1e-5 && h.uy_end.abs() < 1e-5);
    // W = 1.01 T L: every bond breaks in the static stage, then the block falls freely
    let t_fall = w / (1.01 * l);
    let f = hang(t_fall);
    eprintln!(
        "W = 1.01 T L: uy {:.3e} m after loading, bonds {:?}, Δvy {:.6} m/s over {} s (−g Δt = {:.6}), uy at the end {:.4} m",
        f.uy_loaded,
        f.bonds,
        f.vy.1 - f.vy.0,
        f.duration,
        -G * f.duration,
        f.uy_end
    );
    assert_eq!(f.bonds.0, 0, "every bond broke");
    assert_eq!(f.bonds.1, h.bonds.0, "the same contacts, all broken");
    assert!(f.uy_loaded < -1e-3, "the block moved off: {}", f.uy_loaded);
    let dv = f.vy.1 - f.vy.0;
    assert!(
        (dv / (-G * f.duration) - 1.0).abs() < 1e-6,
        "free fall: Δvy {dv} vs −g Δt {}",
        -G * f.duration
    );
}

/// The bonded direct shear: the paper's direct shear with stiff blocks and a soft joint
/// (E = 100 GPa, penalties 1e9 and 1e8 N/m, so that the joint is loaded nearly
/// uniformly: its contacts' normal forces within ±5%), σ_n = 1 MPa, c = 0.1 MPa,
/// T = 50 kPa, φ = 35°, φ_r = 25°, the upper block pushed 15 µm per static step: about
/// 0.3 of the peak per step, so that the step that reaches the peak takes the whole joint
/// past it (a brittle joint loaded unevenly in small steps fails progressively, and its peak
/// is lower by the unevenness). Returns (τ, σ_n) per step (Pa) and the bonds at the end.
fn bonded_direct_shear(extra: &str) -> (Vec<(f64, f64)>, (usize, usize)) {
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 20\n[cover]\nsize = 0.025\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e11\npoisson = 0.0\n\
         [[block]]\nname = \"lower\"\nmaterial = \"rock\"\nvertices = [[0.0, 0.0], [0.2, 0.0], [0.2, 0.1], [0.0, 0.1]]\nfixed = true\n\
         [[block]]\nname = \"upper\"\nmaterial = \"rock\"\nvertices = [[0.05, 0.1], [0.15, 0.1], [0.15, 0.2], [0.05, 0.2]]\n\
         [[interface]]\nfriction_angle = 35.0\ncohesion = 1.0e5\n{extra}normal_penalty = 1.0e9\nshear_penalty = 1.0e8\n\
         [[load]]\nblock = \"upper\"\nedge = [[0.05, 0.2], [0.15, 0.2]]\ntraction = [0.0, -1.0e6]\n\
         [[constraint]]\nblock = \"upper\"\nedge = [[0.05, 0.1], [0.05, 0.2]]\nux = [[0.0, 0.0], [20.0, 3.0e-4]]\n\
         [[monitor]]\nname = \"joint\"\ninterface = [\"upper\", \"lower\"]\n"
    );
    let mut sim = simulate(&text);
    let mut out = Vec::new();
    while !sim.finished() {
        sim.advance().unwrap();
        let v = monitor_values(&sim);
        out.push((-v[0] / 0.1, v[2] / 0.1));
    }
    (out, sim.contacts.bond_counts())
}

#[test]
fn a_bonded_direct_shear_peaks_at_c_plus_sigma_tan_phi_and_drops_to_the_residual() {
    let (c, sn) = (1.0e5, 1.0e6);
    let peak = c + sn * TAN35;
    let residual = sn * TAN25;
    let (h, bonds) =
        bonded_direct_shear("tensile_strength = 5.0e4\nresidual_friction_angle = 25.0\n");
    for (k, (tau, s)) in h.iter().enumerate() {
        eprintln!(
            "step {}: τ {:.1} Pa, σn {:.1} Pa, τ/peak {:.5}",
            k + 1,
            tau,
            s,
            tau / peak
        );
    }
    let (at, max) = h
        .iter()
        .enumerate()
        .fold((0, 0.0), |m, (k, x)| if x.0 > m.1 { (k, x.0) } else { m });
    eprintln!(
        "peak {max:.1} Pa at step {} vs c + σn tan φ = {peak:.1} ({:+.4}%); last {:.1} vs σn tan φr = {residual:.1} ({:+.4}%); bonds {bonds:?}",
        at + 1,
        100.0 * (max / peak - 1.0),
        h.last().unwrap().0,
        100.0 * (h.last().unwrap().0 / residual - 1.0)
    );
    assert!((max / peak - 1.0).abs() < 5e-3, "peak {max} vs {peak}");
    assert!(at > 0, "the joint first loads elastically");
    assert!(h[0].0 < 0.9 * peak);
    // after the peak every step is on the residual line
    for (tau, s) in &h[at + 1..] {
        assert!((tau / residual - 1.0).abs() < 5e-3, "τ {tau} vs {residual}");
        assert!((s / sn - 1.0).abs() < 5e-3, "σn {s}");
    }
    assert!(h.len() - at > 5, "several residual steps");
    assert_eq!(bonds.0, 0, "every bond broke");
    assert!(bonds.1 > 0);

    // the same joint with cohesion only keeps the return mapping's law: it yields at the
    // same peak and stays there (the cohesion is never lost; −0.37%: the share of the
    // lower block's contact that leaves the upper face's end as it slides, ½ × 1/32 of L)
    let (h, bonds) = bonded_direct_shear("");
    assert_eq!(bonds, (0, 0));
    let last = h.last().unwrap().0;
    eprintln!(
        "cohesion only: last τ {last:.1} vs {peak:.1} ({:+.3}%)",
        100.0 * (last / peak - 1.0)
    );
    assert!(
        (last / peak - 1.0).abs() < 5e-3,
        "cohesion kept: {last} vs {peak}"
    );
}

/// The contacts' VTK frame of a bonded model has the `bond` field; summary.json's `bonds`.
#[test]
fn outputs_report_the_bonds() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("hang.toml");
    std::fs::write(&model, hanging_block(9810.0 / 1.01)).unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["bonds"]["intact"], 0);
    assert!(s["bonds"]["broken"].as_u64().unwrap() > 0);
    // the first frame with contacts: the step the bonds broke (they are 0), pulled to T
    let frames = nmm::output::vtk::read_pvd(&out.join("contacts.pvd")).unwrap();
    let g = nmm::output::vtk::read_vtu(&out.join(&frames[0].1)).unwrap();
    let bond = &g.cell_data["bond"].1;
    let tn = &g.cell_data["normal_force"].1;
    assert!(
        !bond.is_empty() && bond.iter().all(|&b| b == 0.0),
        "{bond:?}"
    );
    assert!(tn.iter().all(|&t| t < 0.0), "in tension: {tn:?}");
    // a model without bonded interfaces has no such field
    let plain = hanging_block(1.0).replace("tensile_strength = 1\n", "");
    assert!(!plain.contains("tensile_strength"));
    let sim = simulate(&plain);
    assert!(!nmm::contact::set::uses_bonds(&sim.model));
}
