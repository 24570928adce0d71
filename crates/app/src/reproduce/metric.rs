//! The figures a table reports per filter, read from a run's summary.

use crate::experiment::{PositionAxes, RunSummary};

/// One figure of merit of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// RMS position error along axis 0, 1 or 2 of the scenario's
    /// [`PositionAxes`], metres.
    Position(usize),
    /// RMS horizontal position error, metres.
    Horizontal,
    /// RMS velocity error along north (0), east (1), down (2), m/s.
    Velocity(usize),
    /// RMS attitude error about north (0), east (1), down (2), degrees.
    Attitude(usize),
    /// Largest position error norm of the run, metres.
    MaxPosition,
}

impl Metric {
    /// The metrics every table reports, in column order: the position
    /// metrics (the first [`POSITION_METRICS`](Self::POSITION_METRICS)),
    /// then velocity and attitude.
    pub const ALL: [Metric; 11] = [
        Metric::Position(0),
        Metric::Position(1),
        Metric::Position(2),
        Metric::Horizontal,
        Metric::MaxPosition,
        Metric::Velocity(0),
        Metric::Velocity(1),
        Metric::Velocity(2),
        Metric::Attitude(0),
        Metric::Attitude(1),
        Metric::Attitude(2),
    ];

    /// How many of [`ALL`](Self::ALL) are position metrics.
    pub const POSITION_METRICS: usize = 5;

    /// The value of this metric in `summary`.
    ///
    /// ```
    /// use kestrel_app::reproduce::Metric;
    /// use kestrel_app::experiment::{run, RunOptions};
    /// let s = kestrel_app::scenario::by_name("002").unwrap();
    /// let r = run(&s, &s.filters[0], 1, &RunOptions::default().with_duration(5.0)).unwrap();
    /// assert_eq!(Metric::Horizontal.value(&r.summary), r.summary.horizontal_rms());
    /// ```
    pub fn value(&self, summary: &RunSummary) -> f64 {
        match *self {
            Self::Position(i) => summary.rms_position[i],
            Self::Horizontal => summary.horizontal_rms(),
            Self::Velocity(i) => summary.rms_velocity[i],
            Self::Attitude(i) => summary.rms_attitude[i].to_degrees(),
            Self::MaxPosition => summary.max_position,
        }
    }

    /// A column name with its unit, e.g. `pos_east_m`.
    ///
    /// ```
    /// use kestrel_app::reproduce::Metric;
    /// use kestrel_app::experiment::PositionAxes;
    /// assert_eq!(Metric::Position(2).name(PositionAxes::EastNorthUp), "pos_up_m");
    /// assert_eq!(Metric::Velocity(1).name(PositionAxes::EastNorthUp), "vel_east_mps");
    /// ```
    pub fn name(&self, axes: PositionAxes) -> String {
        const NED: [&str; 3] = ["north", "east", "down"];
        const ENU: [&str; 3] = ["east", "north", "up"];
        let pos = match axes {
            PositionAxes::NorthEastDown => NED,
            PositionAxes::EastNorthUp => ENU,
        };
        match *self {
            Self::Position(i) => format!("pos_{}_m", pos[i]),
            Self::Horizontal => "pos_horizontal_m".into(),
            Self::Velocity(i) => format!("vel_{}_mps", NED[i]),
            Self::Attitude(i) => format!("att_{}_deg", NED[i]),
            Self::MaxPosition => "pos_max_m".into(),
        }
    }

    /// A short column heading for printed tables, e.g. `pE m`.
    pub fn heading(&self, axes: PositionAxes) -> String {
        const NED: [&str; 3] = ["N", "E", "D"];
        const ENU: [&str; 3] = ["E", "N", "U"];
        let pos = match axes {
            PositionAxes::NorthEastDown => NED,
            PositionAxes::EastNorthUp => ENU,
        };
        match *self {
            Self::Position(i) => format!("p{} m", pos[i]),
            Self::Horizontal => "pH m".into(),
            Self::Velocity(i) => format!("v{} m/s", NED[i]),
            Self::Attitude(i) => format!("φ{} deg", NED[i]),
            Self::MaxPosition => "max|p| m".into(),
        }
    }
}
