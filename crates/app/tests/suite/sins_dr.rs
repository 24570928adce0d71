//! SINS / odometer dead reckoning without faults (paper 003's set-up): a
//! navigation-grade IMU aided only by the odometer (forward speed with the
//! non-holonomic constraint, 16-state filter with the scale factor) keeps
//! the position error below 0.1 % of the distance travelled over 1 h.
//!
//! The trajectory, sensor errors, initial errors (misalignment 1′, 1′,
//! 10′), P0 and R are those of the built-in scenario 003 with its odometer
//! faults removed. The IMU is mounted with the scenario's misalignment to
//! the vehicle (pitch 0.2°, yaw −0.3°): the simulated vehicle moves along
//! its own x axis, the truth and the increments are the IMU body's, the
//! odometer reads the vehicle's forward speed, and the filter knows the
//! mounting angles.

use crate::odometer_run::{run_003, Processing};

#[test]
fn dead_reckoning_error_below_a_thousandth_of_distance() {
    let run = run_003(false, Processing::Plain);
    let (k, sd, truth) = run.scale;
    let last = run.errors.last().unwrap().1;
    eprintln!(
        "{:.0} m travelled: final position error {last:.2} m ({:.4} %), worst {:.2} m ({:.4} %); \
         scale {k:.5} ± {sd:.5} (truth {truth:.5})",
        run.distance,
        100.0 * last / run.distance,
        run.worst,
        100.0 * run.worst / run.distance,
    );
    assert!(run.distance > 60e3, "the drive is about 70 km");
    assert_eq!(run.rejected, 0);
    assert!(
        run.worst < 1e-3 * run.distance,
        "worst position error {:.1} m",
        run.worst
    );
    // The scale factor is estimated: within 3σ of the truth (0.5 % constant
    // plus the odometer's Markov part now), σ a fifth of the prior.
    assert!(
        (k - truth).abs() < 3.0 * sd,
        "scale {k} vs {truth} (σ {sd})"
    );
    assert!(sd < 0.2 * 0.005, "scale factor not estimated: σ {sd}");
}
