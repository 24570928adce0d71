//! The estimation side of a scenario: error-state model, measurements,
//! initial errors and covariance, measurement noise.

use kestrel::nalgebra::Vector3;

use kestrel::nav::imu_spec::ImuSpec;

/// The error-state model a scenario's filters use (state order as in the
/// crate's error models).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ErrorModelKind {
    /// 15 states: φ (NED, rad), δv (NED, m/s), δr (NED, m), gyro bias
    /// (rad/s), accelerometer bias (m/s²).
    Ins15,
    /// 18 states: φ, δv, δr, gyro constant drift ε_c, gyro first-order
    /// Markov drift ε_r, accelerometer bias ∇.
    Ins18,
    /// 16 states: the 15 plus the odometer scale-factor error (first-order
    /// Markov with correlation time `scale_tau`, s).
    Odometer16 {
        /// Correlation time of the scale-factor error, s.
        scale_tau: f64,
    },
    /// 21 states: the 15 plus gyro and accelerometer scale-factor errors
    /// (random constants for an infinite `scale_tau`, else first-order
    /// Markov).
    Ins21 {
        /// Correlation time of the scale-factor errors, s.
        scale_tau: f64,
    },
}

impl ErrorModelKind {
    /// Number of states.
    ///
    /// ```
    /// use kestrel_app::scenario::ErrorModelKind;
    /// assert_eq!(ErrorModelKind::Odometer16 { scale_tau: 3600.0 }.dimension(), 16);
    /// ```
    pub fn dimension(&self) -> usize {
        match self {
            Self::Ins15 => 15,
            Self::Ins18 => 18,
            Self::Odometer16 { .. } => 16,
            Self::Ins21 { .. } => 21,
        }
    }
}

/// What a scenario's filters measure (in files by the names
/// [`name`](Self::name) gives).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MeasurementKind {
    /// GNSS position and velocity (m = 6).
    GnssPositionVelocity,
    /// Attitude, velocity and position (m = 9; attitude from an attitude
    /// reference, position and velocity from GNSS).
    AttitudeVelocityPosition,
    /// Velocity matching with the odometer speed mapped to NED (m = 3).
    OdometerVelocity,
}

impl MeasurementKind {
    /// The name files use.
    ///
    /// ```
    /// use kestrel_app::scenario::MeasurementKind;
    /// assert_eq!(MeasurementKind::OdometerVelocity.name(), "odometer-velocity");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Self::GnssPositionVelocity => "gnss-position-velocity",
            Self::AttitudeVelocityPosition => "attitude-velocity-position",
            Self::OdometerVelocity => "odometer-velocity",
        }
    }
}

/// The errors of the filter's initial navigation state (truth plus these
/// is where the filter starts).
///
/// ```
/// use kestrel_app::scenario::InitialErrors;
/// assert_eq!(InitialErrors::none().position.norm(), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialErrors {
    /// Attitude error φ (NED, rad): `C_b^n(initial) = (I − [φ×]) C_b^n(true)`.
    pub attitude: kestrel::nalgebra::Vector3<f64>,
    /// Velocity error (NED, m/s), initial − true.
    pub velocity: kestrel::nalgebra::Vector3<f64>,
    /// Position error (NED, m), from the true to the initial position.
    pub position: kestrel::nalgebra::Vector3<f64>,
}

impl InitialErrors {
    /// No error.
    ///
    /// ```
    /// assert_eq!(kestrel_app::scenario::InitialErrors::none().attitude.norm(), 0.0);
    /// ```
    pub fn none() -> Self {
        Self {
            attitude: Vector3::zeros(),
            velocity: Vector3::zeros(),
            position: Vector3::zeros(),
        }
    }
}

/// The initial covariance as standard deviations per state block (P0 is
/// diagonal in every paper).
///
/// ```
/// use kestrel_app::scenario::{ErrorModelKind, InitialUncertainty};
/// let p = InitialUncertainty::default();
/// assert_eq!(p.std_vector(ErrorModelKind::Ins18).len(), 18);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InitialUncertainty {
    /// Attitude error σ north, east, down, rad.
    pub attitude: Vector3<f64>,
    /// Velocity error σ north, east, down, m/s.
    pub velocity: Vector3<f64>,
    /// Position error σ north, east, down, m.
    pub position: Vector3<f64>,
    /// Gyro bias σ (the constant drift ε_c of the 18-state model), rad/s.
    pub gyro_bias: Vector3<f64>,
    /// Gyro Markov drift σ ε_r (18-state model only), rad/s.
    pub gyro_markov: Vector3<f64>,
    /// Accelerometer bias σ, m/s².
    pub accel_bias: Vector3<f64>,
    /// Odometer scale-factor error σ (16-state model only), ratio.
    pub odometer_scale: f64,
    /// Gyro scale-factor error σ (21-state model only), ratio.
    pub gyro_scale: Vector3<f64>,
    /// Accelerometer scale-factor error σ (21-state model only), ratio.
    pub accel_scale: Vector3<f64>,
}

impl InitialUncertainty {
    /// The standard deviations in the state order of `model`; P0 is the
    /// diagonal of their squares.
    ///
    /// ```
    /// use kestrel::nalgebra::Vector3;
    /// use kestrel_app::scenario::{ErrorModelKind, InitialUncertainty};
    /// let p = InitialUncertainty { odometer_scale: 5e-3, position: Vector3::repeat(2.0), ..Default::default() };
    /// let s = p.std_vector(ErrorModelKind::Odometer16 { scale_tau: 3600.0 });
    /// assert_eq!((s[6], s[15]), (2.0, 5e-3));
    /// ```
    pub fn std_vector(&self, model: ErrorModelKind) -> Vec<f64> {
        let mut v: Vec<f64> = [self.attitude, self.velocity, self.position, self.gyro_bias]
            .iter()
            .flat_map(|b| b.iter().copied())
            .collect();
        match model {
            ErrorModelKind::Ins15 => v.extend(self.accel_bias.iter()),
            ErrorModelKind::Ins18 => {
                v.extend(self.gyro_markov.iter());
                v.extend(self.accel_bias.iter());
            }
            ErrorModelKind::Odometer16 { .. } => {
                v.extend(self.accel_bias.iter());
                v.push(self.odometer_scale);
            }
            ErrorModelKind::Ins21 { .. } => {
                v.extend(self.accel_bias.iter());
                v.extend(self.gyro_scale.iter());
                v.extend(self.accel_scale.iter());
            }
        }
        v
    }
}

/// The measurement noise a filter assumes (R as standard deviations; R is
/// diagonal in every paper). Blocks a scenario does not measure are `None`.
///
/// ```
/// use kestrel::nalgebra::Vector3;
/// use kestrel_app::scenario::MeasurementNoise;
/// let r = MeasurementNoise::gnss(Vector3::repeat(5.0), Vector3::repeat(0.3));
/// assert!(r.attitude.is_none() && r.odometer.is_none());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasurementNoise {
    /// Position σ north, east, down, m.
    pub position: Option<Vector3<f64>>,
    /// Velocity σ north, east, down, m/s.
    pub velocity: Option<Vector3<f64>>,
    /// Attitude σ roll, pitch, yaw, rad.
    pub attitude: Option<Vector3<f64>>,
    /// Odometer velocity-matching σ north, east, down, m/s.
    pub odometer: Option<Vector3<f64>>,
}

impl MeasurementNoise {
    /// GNSS position (m) and velocity (m/s) σ, NED.
    ///
    /// ```
    /// use kestrel::nalgebra::Vector3;
    /// use kestrel_app::scenario::MeasurementNoise;
    /// let r = MeasurementNoise::gnss(Vector3::repeat(5.0), Vector3::repeat(0.3));
    /// assert_eq!(r.velocity, Some(Vector3::repeat(0.3)));
    /// ```
    pub fn gnss(position: Vector3<f64>, velocity: Vector3<f64>) -> Self {
        Self {
            position: Some(position),
            velocity: Some(velocity),
            attitude: None,
            odometer: None,
        }
    }
}

/// Everything the filters of a scenario share.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterSetup {
    /// Error-state model.
    pub error_model: ErrorModelKind,
    /// Measurement.
    pub measurement: MeasurementKind,
    /// The IMU errors the filter assumes (its process noise and bias
    /// models), which need not equal the simulated ones.
    pub imu_model: ImuSpec,
    /// Initial covariance.
    pub p0: InitialUncertainty,
    /// Measurement noise (the initial R of adaptive filters).
    pub r: MeasurementNoise,
    /// GNSS lever arm the filter uses (body, m).
    pub lever_arm: Vector3<f64>,
    /// Odometer mounting pitch and yaw the filter uses (calibrated), rad.
    pub odometer_mounting: [f64; 2],
}
