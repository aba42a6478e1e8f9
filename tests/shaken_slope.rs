//! The shaken two-block slope against the Newmark (1965) rigid sliding-block reference,
//! for two slope angles and two input motions. Tolerances (from the issue): final slip
//! within 5%, onset of sliding within 0.03 s, with return mapping. The conventional
//! rule's deviation is printed for the record.

use nmm::verify::cases::{median, shaken_slope, RAMPED_5HZ, STEADY_2HZ};

#[test]
fn shaken_slope_matches_newmark_with_return_mapping() {
    for theta in [30.0, 35.0] {
        for (name, motion) in [("ramped 5 Hz", RAMPED_5HZ), ("steady 2 Hz", STEADY_2HZ)] {
            let r = shaken_slope(theta, &motion, "return-mapping").unwrap();
            let c = shaken_slope(theta, &motion, "conventional").unwrap();
            eprintln!(
                "θ = {theta}°, {name}: a_y = {:.3} m/s²; Newmark onset {:?} s, final slip {:.5} m; \
                 return mapping onset {:?} s, final {:.5} m ({:+.2}%), median iterations {}; \
                 conventional onset {:?} s, final {:.5} m ({:+.2}%)",
                r.yield_acceleration,
                r.onset_reference,
                r.final_reference,
                r.onset,
                r.final_slip,
                (r.final_slip / r.final_reference - 1.0) * 100.0,
                median(&r.iterations),
                c.onset,
                c.final_slip,
                (c.final_slip / c.final_reference - 1.0) * 100.0
            );
            let (t, t_ref) = (r.onset.unwrap(), r.onset_reference.unwrap());
            assert!((t - t_ref).abs() <= 0.03, "onset {t} vs {t_ref}");
            assert!(
                ((r.final_slip - r.final_reference) / r.final_reference).abs() < 0.05,
                "{} vs {}",
                r.final_slip,
                r.final_reference
            );
        }
    }
}
