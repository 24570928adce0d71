//! An IMU that corrupts exact increments with its true errors.

use nalgebra::Vector3;

use super::imu_errors::ImuErrors;
use super::markov::GaussMarkov3;
use super::rng::{normal3, sensor_rng, SensorStream, SimRng};
use kestrel_nav::imu::ImuIncrement;

/// Applies [`ImuErrors`] to exact increments, drawing noise from its own
/// seeded generator (stream [`SensorStream::Imu`]).
///
/// White noise of density `N` integrates over an interval `Δt` to a
/// standard deviation `N √Δt` per increment, so the noise statistics do not
/// depend on the sampling rate. The Markov drifts start in their steady
/// state and are integrated over each interval by the trapezoid rule.
///
/// ```
/// use kestrel_nav::{ImuIncrement, nalgebra::Vector3};
/// use kestrel_sim::{ImuErrors, ImuSensor};
/// let mut e = ImuErrors::perfect();
/// e.gyro_bias = Vector3::new(1e-3, 0.0, 0.0);
/// let mut imu = ImuSensor::new(e, 42);
/// let exact = ImuIncrement { time: 0.01, dt: 0.01, dtheta: Vector3::zeros(), dvel: Vector3::zeros() };
/// assert!((imu.corrupt(&exact).dtheta.x - 1e-5).abs() < 1e-18);
/// ```
#[derive(Clone, Debug)]
pub struct ImuSensor {
    errors: ImuErrors,
    rng: SimRng,
    gyro_markov: GaussMarkov3,
    accel_markov: GaussMarkov3,
}

impl ImuSensor {
    /// A sensor with the errors `errors`, noise from the seed `seed`.
    ///
    /// ```
    /// use kestrel_sim::{ImuErrors, ImuSensor};
    /// let s = ImuSensor::new(ImuErrors::perfect(), 1);
    /// assert_eq!(s.errors(), &ImuErrors::perfect());
    /// ```
    pub fn new(errors: ImuErrors, seed: u64) -> Self {
        let mut rng = sensor_rng(seed, SensorStream::Imu);
        let gyro_markov =
            GaussMarkov3::new(&errors.gyro_markov_sigma, &errors.gyro_markov_tau, &mut rng);
        let accel_markov = GaussMarkov3::new(
            &errors.accel_markov_sigma,
            &errors.accel_markov_tau,
            &mut rng,
        );
        Self {
            errors,
            rng,
            gyro_markov,
            accel_markov,
        }
    }

    /// The true errors.
    ///
    /// ```
    /// use kestrel_sim::{ImuErrors, ImuSensor};
    /// assert_eq!(ImuSensor::new(ImuErrors::perfect(), 0).errors().accel_scale.x, 0.0);
    /// ```
    pub fn errors(&self) -> &ImuErrors {
        &self.errors
    }

    /// The current Markov drifts: gyro (rad/s) and accelerometer (m/s²).
    ///
    /// ```
    /// use kestrel_sim::{ImuErrors, ImuSensor};
    /// let (g, a) = ImuSensor::new(ImuErrors::perfect(), 0).markov();
    /// assert_eq!(g.norm() + a.norm(), 0.0);
    /// ```
    pub fn markov(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.gyro_markov.value(), self.accel_markov.value())
    }

    /// The total gyro (rad/s) and accelerometer (m/s²) biases now:
    /// constant plus Markov, what an estimator of the biases should find.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{ImuErrors, ImuSensor};
    /// let mut e = ImuErrors::perfect();
    /// e.accel_bias = Vector3::new(0.0, 0.0, 1e-3);
    /// assert_eq!(ImuSensor::new(e, 0).biases().1.z, 1e-3);
    /// ```
    pub fn biases(&self) -> (Vector3<f64>, Vector3<f64>) {
        (
            self.errors.gyro_bias + self.gyro_markov.value(),
            self.errors.accel_bias + self.accel_markov.value(),
        )
    }

    /// The measured increment for the exact increment `exact`.
    ///
    /// ```
    /// use kestrel_nav::{ImuIncrement, nalgebra::Vector3};
    /// use kestrel_sim::{ImuErrors, ImuSensor};
    /// let mut e = ImuErrors::perfect();
    /// e.accel_scale = Vector3::repeat(0.01);
    /// let exact = ImuIncrement { time: 1.0, dt: 0.005, dtheta: Vector3::zeros(), dvel: Vector3::new(0.0, 0.0, -0.049) };
    /// let m = ImuSensor::new(e, 3).corrupt(&exact);
    /// assert!((m.dvel.z + 0.049 * 1.01).abs() < 1e-15);
    /// ```
    pub fn corrupt(&mut self, exact: &ImuIncrement) -> ImuIncrement {
        let dt = exact.dt.max(0.0);
        let e = &self.errors;
        let sq = dt.sqrt();
        let mg = self.gyro_markov.step(dt, &mut self.rng);
        let ma = self.accel_markov.step(dt, &mut self.rng);
        let ng = normal3(&mut self.rng);
        let na = normal3(&mut self.rng);
        let dtheta = exact.dtheta
            + e.gyro_scale.component_mul(&exact.dtheta)
            + (e.gyro_bias + mg) * dt
            + e.gyro_arw.component_mul(&ng) * sq;
        let dvel = exact.dvel
            + e.accel_scale.component_mul(&exact.dvel)
            + (e.accel_bias + ma) * dt
            + e.accel_vrw.component_mul(&na) * sq;
        ImuIncrement {
            time: exact.time,
            dt: exact.dt,
            dtheta,
            dvel,
        }
    }
}
