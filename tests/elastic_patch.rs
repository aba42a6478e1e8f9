//! Patch tests: a block not aligned with the mathematical mesh reproduces a uniform
//! stress state and the linear displacement field.
//!
//! Tolerance 1e-8 relative: the exact field lies in the approximation space (constant
//! covers × linear weights reproduce linear fields), so only round-off and the static
//! mode's inertia term (2ρ/Δt²)·u — about 1e-12 relative with Δt = 1000 s — separate
//! the result from the exact one.

use nmm::verify::cases::{cut_cell_patch, patch, roller_patch};

#[test]
fn rotated_blocks_reproduce_uniform_stress_and_linear_displacement() {
    for (angle, h) in [
        (0.0, 0.17),
        (13.0, 0.1),
        (37.0, 0.23),
        (61.0, 0.07),
        (90.0, 0.13),
    ] {
        let e = patch(angle, h, [0.0123, 0.0456]).unwrap();
        eprintln!(
            "patch angle {angle}° h {h}: stress error {:.2e}, displacement error {:.2e}",
            e.stress, e.displacement
        );
        assert!(e.stress < 1e-8, "angle {angle} h {h}: {e:?}");
        assert!(e.displacement < 1e-8, "angle {angle} h {h}: {e:?}");
    }
}

/// Rollers imposed by edge penalty: the stress is exact, the displacement is the linear
/// field shifted by the penalty stretch σ/p of the loaded roller (p = 1e6 E/h), which
/// the case subtracts; what is left must be round-off.
#[test]
fn roller_patch_with_penalty_constraints() {
    let res: Vec<_> = [(0.09, 1e6), (0.05, 1e6), (0.09, 1e4), (0.09, 1e2)]
        .iter()
        .map(|&(h, factor)| {
            let (stress, disp) = roller_patch(h, factor).unwrap();
            eprintln!("roller patch h {h} penalty factor {factor:e}: stress error {stress:.2e}, displacement error {disp:.2e}");
            (h, stress, disp)
        })
        .collect();
    for (h, stress, disp) in res {
        assert!(stress < 1e-8 && disp < 1e-8, "h {h}: {stress:e} {disp:e}");
    }
}

/// Cut cells: block edges δ = 1e-12 h … 1e-3 h past (or short of) mesh lines leave
/// manifold elements of area down to ~1e-12 h² and covers whose support is that small.
/// Slivers thinner than `MIN_PIECE_WIDTH` h = 1e-5 h are dropped by the discretisation
/// (their geometry is known only to round-off): the block then misses a strip of width δh
/// along that edge, which changes the stress by O(δ) — measured 3.2 δ. Thicker slivers are
/// kept and the patch is exact to 1e-8. Asserted: error < 1e-8 + 4|δ| where dropped, < 1e-8
/// where kept, and no failure of the solve anywhere.
#[test]
fn cut_cells_neither_break_the_solve_nor_spoil_accuracy() {
    for delta in [1e-12, 1e-9, 1e-6, 1e-4, 1e-3, -1e-9, -1e-6, -1e-3] {
        let (stress, disp) = cut_cell_patch(0.1, delta).unwrap();
        eprintln!(
            "cut cells δ = {delta:e} h: stress error {stress:.2e}, displacement error {disp:.2e}"
        );
        let bound = if delta.abs() < nmm::cover::MIN_PIECE_WIDTH {
            1e-8 + 4.0 * delta.abs()
        } else {
            1e-8
        };
        assert!(
            stress < bound && disp < bound,
            "δ = {delta:e}: {stress:e} {disp:e}"
        );
    }
}
