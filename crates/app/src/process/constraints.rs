//! Pseudo-measurements of a ground vehicle: zero velocity and zero angular
//! rate at detected standstill, and the non-holonomic constraint.

use kestrel::nav::measurement::Odometer;
use kestrel::nav::nalgebra::Vector2;
use kestrel::nav::standstill::StandstillDetector;

use super::schedule::Schedule;
use crate::config::process::{NhcSettings, ZuptSettings};

/// What the constraints did over a run.
///
/// ```
/// let c = kestrel_app::process::ConstraintCounts::default();
/// assert_eq!((c.zero_velocity, c.non_holonomic), (0, 0));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConstraintCounts {
    /// Zero-velocity updates.
    pub zero_velocity: usize,
    /// Zero-angular-rate updates.
    pub zero_angular_rate: usize,
    /// Non-holonomic updates.
    pub non_holonomic: usize,
    /// IMU samples detected standing still.
    pub standstill_samples: usize,
}

/// The configured constraints and their schedules.
pub(crate) struct Constraints {
    pub nhc: Option<(Odometer, f64, Schedule)>,
    pub zupt: Option<(StandstillDetector, ZuptSettings, Schedule)>,
    pub counts: ConstraintCounts,
}

impl Constraints {
    pub(crate) fn new(nhc: Option<NhcSettings>, zupt: Option<ZuptSettings>) -> Self {
        Self {
            nhc: nhc.map(|n| {
                // The odometer model's constraint rows, without a speed row.
                let mut model = Odometer::new(1.0, 1.0)
                    .with_mounting(n.mounting[0], n.mounting[1])
                    .with_lever_arm(n.lever_arm);
                model.nhc_std = Vector2::new(n.std[0], n.std[1]);
                (model, n.rate, Schedule::new())
            }),
            zupt: zupt.map(|z| {
                (
                    StandstillDetector::new(z.window, z.accel_std, z.gyro_std),
                    z,
                    Schedule::new(),
                )
            }),
            counts: ConstraintCounts::default(),
        }
    }
}
