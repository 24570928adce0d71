//! A filter failure in the user's terms: when, at which input line, and in
//! words which state or measurement component went non-finite or lost
//! positive definiteness.

use crate::scenario::ErrorModelKind;
use kestrel::{FilterError, Quantity};

/// What was being done when the filter failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// The mechanisation and covariance propagation of an IMU sample.
    Imu,
    /// A GNSS update with `M` rows (3: position, 6: position and velocity).
    Gnss(usize),
    /// An odometer update (speed and the two non-holonomic constraints).
    Odometer,
    /// A zero-velocity update at standstill.
    ZeroVelocity,
    /// A zero-angular-rate update at standstill.
    ZeroAngularRate,
    /// A non-holonomic update without an odometer.
    NonHolonomic,
}

const NED: [&str; 3] = ["north", "east", "down"];
const XYZ: [&str; 3] = ["x", "y", "z"];

/// The name of component `i` of the error state of `model`, e.g.
/// "velocity error east (state 4)" for `Ins15`.
pub(crate) fn state_component(model: ErrorModelKind, i: usize) -> String {
    let (block, k) = (i / 3, i % 3);
    let name = match (model, block) {
        (_, 0) => format!("attitude error {}", NED[k]),
        (_, 1) => format!("velocity error {}", NED[k]),
        (_, 2) => format!("position error {}", NED[k]),
        (ErrorModelKind::Ins18, 3) => format!("constant gyro bias {}", XYZ[k]),
        (ErrorModelKind::Ins18, 4) => format!("Gauss-Markov gyro bias {}", XYZ[k]),
        (ErrorModelKind::Ins18, 5) => format!("accelerometer bias {}", XYZ[k]),
        (_, 3) => format!("gyro bias {}", XYZ[k]),
        (_, 4) => format!("accelerometer bias {}", XYZ[k]),
        (ErrorModelKind::Odometer16 { .. }, 5) if k == 0 => "odometer scale factor".to_owned(),
        (ErrorModelKind::Ins21 { .. }, 5) => format!("gyro scale factor {}", XYZ[k]),
        (ErrorModelKind::Ins21 { .. }, 6) => format!("accelerometer scale factor {}", XYZ[k]),
        _ => format!("state {i}"),
    };
    format!("{name} (state {i})")
}

/// The name of component `i` of the measurement of `step`.
fn measurement_component(step: Step, i: usize) -> String {
    let name = match step {
        Step::Gnss(_) if i < 3 => format!("GNSS position {}", NED[i]),
        Step::Gnss(_) if i < 6 => format!("GNSS velocity {}", NED[i - 3]),
        Step::Odometer => [
            "odometer forward speed",
            "lateral velocity (non-holonomic)",
            "vertical velocity (non-holonomic)",
        ]
        .get(i)
        .map_or_else(|| format!("row {i}"), |s| (*s).to_owned()),
        Step::ZeroVelocity if i < 3 => format!("zero velocity {}", NED[i]),
        Step::ZeroAngularRate if i < 3 => format!("zero angular rate {}", XYZ[i]),
        Step::NonHolonomic if i < 2 => ["lateral velocity", "vertical velocity"][i].to_owned(),
        _ => format!("row {i}"),
    };
    format!("{name} (row {i})")
}

/// Whether rows of `q` index the error state (else the measurement).
fn indexes_state(q: Quantity) -> bool {
    !matches!(
        q,
        Quantity::Measurement
            | Quantity::MeasurementNoise
            | Quantity::PredictedMeasurement
            | Quantity::MeasurementJacobian
            | Quantity::InnovationCovariance
    )
}

/// `error` with the component its index points at named in words.
pub(crate) fn describe(error: &FilterError, model: ErrorModelKind, step: Step) -> String {
    let name = |q: Quantity, i: usize| {
        if indexes_state(q) {
            state_component(model, i)
        } else {
            measurement_component(step, i)
        }
    };
    let component = match *error {
        FilterError::NonFinite { what, row, .. } | FilterError::NotSymmetric { what, row, .. } => {
            Some(name(what, row))
        }
        FilterError::NotPositiveDefinite { what, index } => Some(name(what, index)),
        FilterError::DowndateFailed { index, .. } => Some(state_component(model, index)),
        _ => None,
    };
    match component {
        Some(c) => format!("{error}: {c}"),
        None => error.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_are_named_in_words() {
        let e = FilterError::NonFinite {
            what: Quantity::PropagatedState,
            row: 4,
            col: 0,
        };
        assert_eq!(
            describe(&e, ErrorModelKind::Ins15, Step::Imu),
            "propagated state f(x, dt) has a non-finite value at index 4: velocity error east (state 4)"
        );
        let e = FilterError::NotPositiveDefinite {
            what: Quantity::InnovationCovariance,
            index: 5,
        };
        assert!(describe(&e, ErrorModelKind::Ins15, Step::Gnss(6))
            .ends_with(": GNSS velocity down (row 5)"));
        assert_eq!(
            state_component(ErrorModelKind::Odometer16 { scale_tau: 1.0 }, 15),
            "odometer scale factor (state 15)"
        );
        assert_eq!(
            state_component(ErrorModelKind::Ins18, 13),
            "Gauss-Markov gyro bias y (state 13)"
        );
        assert!(describe(
            &FilterError::NegativeTimeStep,
            ErrorModelKind::Ins15,
            Step::Imu
        )
        .starts_with("time step dt is negative"));
    }
}
