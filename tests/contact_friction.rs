//! Verification of contact and friction: the paper's direct shear test with both
//! algorithms, a block sliding on an incline, a stack and a wall settling under
//! gravity, and Newton's convergence.

use nmm::verify::cases::{
    direct_shear, incline, jointed_incline, median, settle, stack_blocks, wall_blocks, wall_courses,
};

const CASES: [(f64, f64); 3] = [(1.0e6, 30.0), (0.5e6, 20.0), (2.0e6, 15.0)];

/// With return mapping the joint's shear stress is σn tan φ (±0.1%) at every step in
/// which the joint slides (all closed contacts sliding; the first 0.06 mm step is partly
/// taken up by the elastic shortening of the upper block), and never above it by more
/// than 0.1% at any step.
#[test]
fn direct_shear_return_mapping_stays_at_the_strength() {
    for (sigma_n, phi) in CASES {
        let strength = sigma_n * phi.to_radians().tan();
        let h = direct_shear(sigma_n, phi, "return-mapping").unwrap();
        for (i, s) in h.iter().enumerate() {
            eprintln!(
                "return mapping σn={sigma_n} φ={phi} step {}: τ = {:.6e} ({:+.4}%), σn = {:.6e}, sliding {}, {} iterations",
                i + 1,
                s.tau,
                (s.tau / strength - 1.0) * 100.0,
                s.sigma_n,
                s.sliding,
                s.iterations
            );
            // the joint carries the applied normal stress (static mode: inertia 2M/Δt²·Δu ~ 1e-8)
            assert!(
                (s.sigma_n - sigma_n).abs() < 1e-6 * sigma_n,
                "step {}: σn {}",
                i + 1,
                s.sigma_n
            );
            assert!(
                s.tau <= strength * 1.001,
                "step {}: τ = {} above {strength}",
                i + 1,
                s.tau
            );
            if s.sliding {
                assert!(
                    ((s.tau - strength) / strength).abs() < 1e-3,
                    "step {}: τ = {}, strength {strength}",
                    i + 1,
                    s.tau
                );
            }
        }
        assert!(
            h.iter().filter(|s| s.sliding).count() >= 3,
            "the joint must slide in most steps"
        );
    }
}

/// With the conventional rule the step in which the joint starts sliding carries the
/// elastic shear force, above the strength.
#[test]
fn direct_shear_conventional_overshoots_the_strength() {
    for (sigma_n, phi) in CASES {
        let strength = sigma_n * phi.to_radians().tan();
        let h = direct_shear(sigma_n, phi, "conventional").unwrap();
        let taus: Vec<f64> = h.iter().map(|s| s.tau / strength).collect();
        eprintln!("conventional σn={sigma_n} φ={phi}: τ/strength per step {taus:?}");
        assert!(taus.iter().any(|&t| t > 1.001), "{taus:?}");
    }
}

/// θ = 30°, φ = 20°: slip ½ g (sin θ − cos θ tan φ) t² within 2% after 1 s.
#[test]
fn block_slides_down_incline_as_closed_form() {
    let (slip, exact, its) = incline(30.0, 20.0, 1e-3, 1000).unwrap();
    eprintln!(
        "incline: slip {slip:.6} vs {exact:.6} ({:+.3}%), median iterations {}",
        (slip / exact - 1.0) * 100.0,
        median(&its)
    );
    assert!(((slip - exact) / exact).abs() < 0.02, "{slip} vs {exact}");
    assert!(median(&its) <= 4);
}

/// The elastic offset of a block resting on a plane dipping θ (simple shear under its own
/// weight, ρ g sin θ at depth d: u(y) = ρ g sin θ / G (H y − y²/2) at height y of a layer
/// of thickness H) at height `y` of a layer `h` thick; G = E/(2(1 + ν)), E = 1 GPa, ν = 0.25,
/// ρ = 2000 kg/m³ as in `incline` and `jointed_incline`.
fn shear_offset(theta: f64, h: f64, y: f64) -> f64 {
    let g_mod = 1.0e9 / 2.5;
    2000.0 * 9.81 * theta.to_radians().sin() / g_mod * (h * y - 0.5 * y * y)
}

/// Joint shear spring offset: shear force over ε L, ε = 2 p_S / s̄ (p_S = 1 GN/m, s̄ the
/// boundary segment, about the cover size `h_cover`).
fn joint_offset(theta: f64, weight: f64, length: f64, h_cover: f64) -> f64 {
    weight * theta.to_radians().sin() / (2.0 * 1.0e9 / h_cover * length)
}

/// φ = 35° > θ = 30°: the block stays where its elastic offset puts it. Estimate: the
/// slider's simple shear at its centroid (0.25 m layer, y = 0.125) 5.7e-7 m + the joint's
/// shear spring 7.7e-8 m = 6.5e-7 m (measured 1.2e-6: the free ends carry no shear, which
/// simple shear ignores); tolerance 4 × the estimate. A block that slides even at
/// φ − 1° moves centimetres.
#[test]
fn block_holds_on_incline_when_friction_exceeds_slope() {
    let (slip, _, its) = incline(30.0, 35.0, 1e-3, 1000).unwrap();
    let estimate =
        shear_offset(30.0, 0.25, 0.125) + joint_offset(30.0, 2000.0 * 9.81 * 0.125, 0.5, 0.0625);
    eprintln!(
        "incline φ > θ: slip {slip:.3e} m (elastic estimate {estimate:.3e}), median iterations {}",
        median(&its)
    );
    assert!(
        slip.abs() < 4.0 * estimate,
        "{slip} vs the elastic offset {estimate}"
    );
}

/// A block cut by one persistent joint dipping θ = 30° (φ = 20° on the joint, 60° by
/// default): the upper piece slides on the joint face at ½ g (sin θ − cos θ tan φ) t²
/// within 2% after 1 s; the faces the joint made take the joint's interface.
#[test]
fn piece_slides_on_the_joint_that_cut_it_as_closed_form() {
    let (slip, exact, its) = jointed_incline(30.0, 20.0, 1e-3, 1000).unwrap();
    eprintln!(
        "jointed incline: slip {slip:.6} vs {exact:.6} ({:+.3}%), median iterations {}",
        (slip / exact - 1.0) * 100.0,
        median(&its)
    );
    assert!(((slip - exact) / exact).abs() < 0.02, "{slip} vs {exact}");
}

/// φ = 35° > θ = 30° on the joint: the upper piece stays where its elastic offset puts
/// it. Estimate: the lower piece's simple shear under both pieces (0.5 m layer, at
/// y = 0.25) 2.3e-6 m + the upper piece's at its centroid 5.7e-7 m + the joint's spring
/// 1.5e-7 m = 3.0e-6 m (measured 5.3e-6); tolerance 4 × the estimate.
#[test]
fn piece_holds_on_the_joint_when_friction_exceeds_its_dip() {
    let (slip, _, _) = jointed_incline(30.0, 35.0, 1e-3, 1000).unwrap();
    let estimate = shear_offset(30.0, 0.5, 0.25)
        + shear_offset(30.0, 0.25, 0.125)
        + joint_offset(30.0, 2000.0 * 9.81 * 0.625, 2.5, 0.125);
    eprintln!("jointed incline φ > θ: slip {slip:.3e} m (elastic estimate {estimate:.3e})");
    assert!(
        slip.abs() < 4.0 * estimate,
        "{slip} vs the elastic offset {estimate}"
    );
}

fn check_settled(label: &str, blocks: &[(f64, f64, f64, f64)]) {
    let s = settle(blocks, 200).unwrap();
    let rel = (s.base_force - s.weight).abs() / s.weight;
    eprintln!(
        "{label}: base force {:.9e} vs weight {:.9e} (rel {rel:.2e}), max |v| {:.2e} m/s, max penetration {:.2e} m, median iterations {}",
        s.base_force,
        s.weight,
        s.max_velocity,
        s.max_penetration,
        median(&s.iterations)
    );
    assert!(rel < 1e-6, "{label}: {} vs {}", s.base_force, s.weight);
    assert!(s.max_velocity < 1e-6, "{label}: {}", s.max_velocity);
    // no single contact carries more than the whole weight: penetration ≤ W / p_N
    assert!(
        s.max_penetration <= s.weight / 1.0e10,
        "{label}: {}",
        s.max_penetration
    );
    assert!(median(&s.iterations) <= 4, "{label}");
}

#[test]
fn stack_of_blocks_settles_to_rest() {
    check_settled("stack", &stack_blocks());
}

#[test]
fn masonry_wall_settles_to_rest() {
    check_settled("wall", &wall_blocks());
}

/// A taller wall (eight courses, 36 bricks) whose joints all just touch at
/// the start. Before the closed-contact predictor (`ContactSet::evaluate`), the first
/// Newton direction was a free fall and from six courses up step 1 did not converge
/// even after six halvings of Δt.
#[test]
fn tall_wall_with_touching_joints_settles() {
    check_settled("eight-course wall", &wall_courses(8));
}

/// Direct shear with return mapping: the tangent is unsymmetric while contacts slide.
/// Newton finds the active set in a few iterations, and once found the residual drops
/// to round-off in one more (the law is piecewise linear in the gaps): the last ratio of
/// successive residuals is below 1e-3, unless the residual before the last was already at
/// round-off (below 1e-13 of the first: with the whole tangent's LU as the preconditioner
/// step 3 went 8.1e10 → 6.6e-4 → 1.2e-5, where 1.2e-5 is 1.5e-16 of 8.1e10).
#[test]
fn newton_converges_fast_when_contacts_slide() {
    for (step, s) in direct_shear(1.0e6, 30.0, "return-mapping")
        .unwrap()
        .iter()
        .enumerate()
    {
        let r = &s.residuals;
        eprintln!("step {}: residuals {r:?}", step + 1);
        let k = r.len() - 1;
        assert!(r[k] < 1e-8 * r[0], "{r:?}");
        if k >= 2 {
            assert!(r[k] / r[k - 1] < 1e-3 || r[k - 1] < 1e-13 * r[0], "{r:?}");
        }
    }
}

/// Only contacts touching at the start of the analysis are locked (stick history, an
/// elastic shear spring from the first step, as DDA's initial contacts). A contact that
/// comes to touch later keeps its open history: under the conventional rule it is then
/// Coulomb-limited while it closes, so its shear force cannot jump as it opens again.
#[test]
fn only_initially_touching_contacts_are_locked() {
    use nmm::contact::friction::ContactStatus;
    use nmm::simulation::Simulation;
    let text = "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = 2\ngravity = [0.0, 0.0]\nfriction = \"conventional\"\n\
        [cover]\nsize = 0.25\n[[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e9\npoisson = 0.25\n\
        [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = [[0.0, -0.5], [2.0, -0.5], [2.0, 0.0], [0.0, 0.0]]\nfixed = true\n\
        [[block]]\nname = \"top\"\nmaterial = \"rock\"\nvertices = [[0.5, 0.0], [1.5, 0.0], [1.5, 0.5], [0.5, 0.5]]\n\
        [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e9\n";
    let mut sim = Simulation::new(nmm::verify::cases::model(text).unwrap()).unwrap();
    // detect on the current geometry: (gap at the start of the step, history) per contact
    let detect = |sim: &mut Simulation| -> Vec<(f64, ContactStatus)> {
        sim.contacts
            .detect(&sim.disc, &sim.model, &sim.u, 1e-3, None);
        let found: Vec<_> = sim
            .contacts
            .contacts
            .iter()
            .map(|c| {
                (
                    c.gn0,
                    nmm::contact::ShearHistory::from_state(&c.history).status,
                )
            })
            .collect();
        assert!(!found.is_empty());
        found
    };
    assert!(detect(&mut sim)
        .iter()
        .all(|&(gn0, status)| gn0.abs() < 1e-12 && status == ContactStatus::Stick));
    // A step with no load: the contacts stay at g_N = 0, i.e. open, and are committed so.
    let du = vec![0.0; sim.n_dofs()];
    sim.contacts.commit(&du);
    assert!(detect(&mut sim)
        .iter()
        .all(|&(_, status)| status == ContactStatus::Open));
}

/// A vertex is found inside a face no deeper than the two blocks' reach allows
/// (`PenetrationReach`: the sum of each block's, at least its floor, at most the search
/// distance); without it, as deep as the search distance. A block whose bottom corners lie
/// 5 cm inside a fixed base: found with a global search of 10 cm, not when the two blocks'
/// reach is 1 cm (they did not move), found again when their reach sums to 6 cm. (The
/// block is moved into the base by its displacement: a model may not overlap.)
#[test]
fn a_vertex_is_found_no_deeper_than_its_blocks_reach() {
    use nmm::contact::set::PenetrationReach;
    use nmm::simulation::Simulation;
    let text = "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = 1\ngravity = [0.0, 0.0]\n\
        [cover]\nsize = 0.25\n[[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e9\npoisson = 0.25\n\
        [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = [[0.0, -0.5], [2.0, -0.5], [2.0, 0.0], [0.0, 0.0]]\nfixed = true\n\
        [[block]]\nname = \"top\"\nmaterial = \"rock\"\nvertices = [[0.5, 0.0], [1.5, 0.0], [1.5, 0.5], [0.5, 0.5]]\n\
        [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e9\n";
    let mut sim = Simulation::new(nmm::verify::cases::model(text).unwrap()).unwrap();
    // the top block 5 cm down, into the base (a translation: every cover's constant term)
    for c in &sim.disc.covers {
        if let Some(d) = c.dof {
            sim.u[d + 1] = -0.05;
        }
    }
    let mut deepest = |blocks: Option<[f64; 2]>| -> Option<f64> {
        let reach = blocks.as_ref().map(|b| PenetrationReach {
            blocks: b,
            floor: 0.01,
        });
        sim.contacts
            .detect(&sim.disc, &sim.model, &sim.u, 0.1, reach);
        sim.contacts
            .contacts
            .iter()
            .map(|c| c.gn0)
            .min_by(f64::total_cmp)
    };
    let global = deepest(None).expect("the corners inside the base");
    assert!((global + 0.05).abs() < 1e-9, "{global}");
    // the two blocks at rest: their reach is the floor, 1 cm
    assert!(deepest(Some([0.0, 0.0])).is_none_or(|g| g > -0.01));
    assert!(deepest(Some([0.0, 0.03])).is_none_or(|g| g > -0.03));
    let both = deepest(Some([0.03, 0.03])).expect("within 6 cm");
    assert!((both + 0.05).abs() < 1e-9, "{both}");
}
