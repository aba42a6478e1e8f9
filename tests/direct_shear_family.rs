//! The direct shear test over σn ∈ {0.5, 1, 2, 4} MPa × φ ∈ {15, 25, 30, 40}° with the
//! joint on a mesh line, 10⁻³ h from one and between two (`[cover] origin`): no Δt cut, at
//! most 8 linear solves in any step and a median of at most 3 over the family, and the shear
//! stress within 0.1% of σn tan φ at every step where the whole joint slides (the
//! strength is the closed form; 0.1% is the tolerance). The conventional rule still
//! overshoots the strength on the same tests.

use nmm::verify::cases::{direct_shear_on, median, JointOnMesh};

const SIGMAS: [f64; 4] = [0.5e6, 1.0e6, 2.0e6, 4.0e6];
const PHIS: [f64; 4] = [15.0, 25.0, 30.0, 40.0];

#[test]
fn return_mapping_family_converges_fast_and_slides_at_the_strength() {
    for place in [JointOnMesh::On, JointOnMesh::Near, JointOnMesh::Between] {
        let mut solves = Vec::new();
        let (mut cuts, mut worst, mut sliding_steps) = (0, 0.0f64, 0);
        for sn in SIGMAS {
            for phi in PHIS {
                let h = direct_shear_on(sn, phi, "return-mapping", place.origin()).unwrap();
                let strength = sn * phi.to_radians().tan();
                for s in &h {
                    solves.push(s.iterations);
                    cuts += s.cuts;
                    assert!(
                        s.iterations <= 8,
                        "{place:?} σn {sn} φ {phi}: {} solves in a step",
                        s.iterations
                    );
                    if s.sliding {
                        sliding_steps += 1;
                        let e = (s.tau / strength - 1.0).abs();
                        worst = worst.max(e);
                        assert!(
                            e < 1e-3,
                            "{place:?} σn {sn} φ {phi}: τ {} vs {strength}",
                            s.tau
                        );
                    }
                }
            }
        }
        eprintln!(
            "{place:?}: median {} max {} solves per step, {cuts} cuts, worst sliding error {worst:.1e} over {sliding_steps} sliding steps",
            median(&solves),
            solves.iter().max().unwrap()
        );
        assert_eq!(cuts, 0, "{place:?}");
        assert!(
            median(&solves) <= 3,
            "{place:?}: median {}",
            median(&solves)
        );
        assert!(
            sliding_steps > 20,
            "{place:?}: too few sliding steps to check"
        );
    }
}

#[test]
fn conventional_rule_still_overshoots_the_strength() {
    for place in [JointOnMesh::On, JointOnMesh::Between] {
        for (sn, phi) in [(1.0e6, 30.0), (0.5e6, 15.0), (2.0e6, 25.0)] {
            let h = direct_shear_on(sn, phi, "conventional", place.origin()).unwrap();
            let strength = sn * f64::tan(phi.to_radians());
            let peak = h.iter().map(|s| s.tau / strength).fold(0.0, f64::max);
            eprintln!("{place:?} σn {sn} φ {phi}: conventional peak τ/strength {peak:.3}");
            assert!(peak > 1.01, "{place:?} σn {sn} φ {phi}: peak {peak}");
        }
    }
}
