//! The shaken two-block slope against the Newmark (1965) rigid sliding-block reference,
//! for two slope angles and two input motions, with return mapping.
//!
//! Final slip within 5% (measured +1.2% … +2.8%: the elastic block on its soft shear
//! spring, p_S = 10 MN/m, creeps by partial slip at the record's peaks before the whole
//! joint yields, which a rigid block cannot: ~1.5e-4 m per case, 0.2–2% of the slip, plus
//! the spring's dynamic overshoot).
//!
//! Onset of sliding, defined without reference to the comparison (issue 19): the first
//! step at whose end the whole joint slides (`ShakenSlope::onset`), against the first
//! time the reference slips: within 0.03 s (measured 0.004–0.011 s), except on the
//! steady 2 Hz record on θ = 35°: its peak at 0.375 s reaches 0.98 of the rigid block's
//! yield acceleration g tan(φ − θ), and the elastic block's whole joint yields there
//! (0.379 s), one cycle before the rigid block (0.791 s). A real difference between the
//! two models (the onset time jumps by a cycle when a peak lies that close to the yield
//! level; the elastic block on its shear spring overshoots the record by a few per cent),
//! listed and asserted here, not hidden by a threshold
//!   (the former onset, slip above 1 mm, had its threshold raised from 2e-4 m until the
//!   comparison passed).

use nmm::verify::cases::{median, shaken_slope, RAMPED_5HZ, STEADY_2HZ};

#[test]
fn shaken_slope_matches_newmark_with_return_mapping() {
    for theta in [30.0, 35.0] {
        for (name, motion) in [("ramped 5 Hz", RAMPED_5HZ), ("steady 2 Hz", STEADY_2HZ)] {
            let r = shaken_slope(theta, &motion, "return-mapping").unwrap();
            let c = shaken_slope(theta, &motion, "conventional").unwrap();
            let (t, t_ref) = (r.onset.unwrap(), r.onset_reference.unwrap());
            // the base acceleration pushing the block downslope (the plane dips toward +x)
            let a_onset = -r.history.iter().find(|h| h.0 == t).unwrap().1;
            let ratio = a_onset / r.yield_acceleration;
            eprintln!(
                "θ = {theta}°, {name}: a_y = {:.3} m/s²; Newmark onset {t_ref} s, final slip {:.5} m; \
                 return mapping onset {t} s at {ratio:.4} a_y, final {:.5} m ({:+.2}%), median iterations {}; \
                 conventional onset {:?} s, final {:.5} m ({:+.2}%)",
                r.yield_acceleration,
                r.final_reference,
                r.final_slip,
                (r.final_slip / r.final_reference - 1.0) * 100.0,
                median(&r.iterations),
                c.onset,
                c.final_slip,
                (c.final_slip / c.final_reference - 1.0) * 100.0
            );
            if (theta, name) == (35.0, "steady 2 Hz") {
                // the documented early onset (module comment): a cycle early, at a peak
                // just below a_y
                assert!((0.95..1.0).contains(&ratio), "early onset at {ratio} a_y");
                assert!(
                    t_ref - t > 0.3,
                    "onset {t} vs {t_ref}: no longer early, update the comment"
                );
            } else {
                assert!((t - t_ref).abs() <= 0.03, "onset {t} vs {t_ref}");
            }
            assert!(
                ((r.final_slip - r.final_reference) / r.final_reference).abs() < 0.05,
                "{} vs {}",
                r.final_slip,
                r.final_reference
            );
        }
    }
}
