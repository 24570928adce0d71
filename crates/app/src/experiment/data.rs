//! The simulated data of a run: truth, corrupted IMU increments and the
//! aiding sensors, all from the seed and the truth only.

use super::error::RunError;
use super::options::RunOptions;
use crate::scenario::Scenario;
use kestrel::nav::imu::ImuIncrement;
use kestrel::nav::measurement::{AttitudeFix, GnssFix, OdometerReading};
use kestrel::nav::state::NavState;
use kestrel::sim::{AttitudeSensor, GnssSensor, ImuSensor, ImuStream, OdometerSensor, Simulated};

/// One IMU sample of a simulation and the sensor readings due at it.
///
/// ```
/// use kestrel_app::experiment::{RunOptions, Simulation};
/// let s = kestrel_app::scenario::by_name("003").unwrap();
/// let first = Simulation::new(&s, 3, &RunOptions::default()).unwrap().next().unwrap();
/// assert_eq!(first.truth.time, first.imu.time);
/// assert!(first.gnss.is_none() && first.attitude.is_none());
/// ```
#[derive(Clone, Copy, Debug)]
pub struct SensorSample {
    /// The true state at the end of the increment.
    pub truth: NavState,
    /// The IMU increment as the (erroneous) IMU delivers it.
    pub imu: ImuIncrement,
    /// The GNSS fix due at this sample, if any.
    pub gnss: Option<Simulated<GnssFix>>,
    /// The attitude reference reading due at this sample, if any.
    pub attitude: Option<AttitudeFix>,
    /// The odometer reading due at this sample, if any.
    pub odometer: Option<Simulated<OdometerReading>>,
    /// The odometer's true scale-factor error (constant plus Markov part,
    /// ratio) with its reading, for judging a filter's estimate.
    pub odometer_scale: Option<f64>,
}

/// The sensor data of a scenario for a seed, sample by sample.
///
/// Each sensor draws from its own seeded stream and from the truth, so the
/// data does not depend on who consumes it: every filter of a run sees the
/// same samples for the same seed.
///
/// ```
/// use kestrel_app::experiment::{RunOptions, Simulation};
/// let s = kestrel_app::scenario::by_name("000").unwrap();
/// let opts = RunOptions::default().with_duration(2.0);
/// let a: Vec<_> = Simulation::new(&s, 7, &opts).unwrap().collect();
/// let b: Vec<_> = Simulation::new(&s, 7, &opts).unwrap().collect();
/// assert_eq!(a.len(), 400); // 2 s at 200 Hz
/// assert!(a.iter().zip(&b).all(|(x, y)| x.imu == y.imu && x.gnss == y.gnss));
/// assert_eq!(a.iter().filter(|x| x.gnss.is_some()).count(), 20); // 10 Hz GNSS
/// ```
#[derive(Debug)]
pub struct Simulation {
    stream: ImuStream,
    start: NavState,
    end: f64,
    imu: ImuSensor,
    gnss: Option<GnssSensor>,
    attitude: Option<AttitudeSensor>,
    odometer: Option<OdometerSensor>,
}

/// The most IMU samples a simulated run may have (duration × IMU rate):
/// about 28 hours at 200 Hz. Longer runs are refused before any work, so a
/// mistyped duration or rate cannot run or write for days.
///
/// ```
/// use kestrel_app::experiment::{RunError, RunOptions, Simulation, MAX_IMU_SAMPLES};
/// let s = kestrel_app::scenario::by_name("002").unwrap();
/// let opts = RunOptions::default().with_imu_rate(1e9);
/// let e = Simulation::new(&s, 1, &opts).unwrap_err();
/// assert!(matches!(e, RunError::TooLong { .. }));
/// assert!(e.to_string().contains(&format!("more than the limit of {MAX_IMU_SAMPLES}")));
/// ```
pub const MAX_IMU_SAMPLES: u64 = 20_000_000;

impl Simulation {
    /// The simulation of `scenario` with noise from `seed`, limited to
    /// `options.duration` and at `options.imu_rate` if given.
    ///
    /// # Errors
    /// [`RunError::Trajectory`] for an invalid trajectory or rate.
    pub fn new(scenario: &Scenario, seed: u64, options: &RunOptions) -> Result<Self, RunError> {
        let traj = scenario.trajectory()?;
        let start = traj.initial_state();
        let end = options
            .duration
            .map_or(traj.duration(), |d| d.min(traj.duration()));
        let rate = options.imu_rate.unwrap_or(scenario.imu_rate);
        let samples = end * rate;
        if samples.is_nan() || samples > MAX_IMU_SAMPLES as f64 {
            return Err(RunError::TooLong {
                duration: end,
                rate,
            });
        }
        Ok(Self {
            stream: traj.into_stream(rate)?,
            start,
            end: start.time + end,
            imu: scenario.imu_sensor(seed),
            gnss: scenario.gnss_sensor(seed),
            attitude: scenario.attitude_sensor(seed),
            odometer: scenario.odometer_sensor(seed),
        })
    }

    /// The true initial state.
    ///
    /// ```
    /// # use kestrel_app::experiment::{RunOptions, Simulation};
    /// let s = kestrel_app::scenario::by_name("003").unwrap();
    /// let sim = Simulation::new(&s, 1, &RunOptions::default()).unwrap();
    /// assert_eq!(sim.initial_truth().time, 0.0);
    /// ```
    pub fn initial_truth(&self) -> NavState {
        self.start
    }
}

impl Iterator for Simulation {
    type Item = SensorSample;

    fn next(&mut self) -> Option<SensorSample> {
        let (truth, exact) = self.stream.next()?;
        // Half a microsecond absorbs the rounding of sample times.
        if truth.time > self.end + 5e-7 {
            return None;
        }
        let motion = *self.stream.motion();
        let (odometer, odometer_scale) = match self.odometer.as_mut() {
            Some(o) => {
                let reading = o.sample(&truth, &motion);
                let scale = reading
                    .is_some()
                    .then(|| o.config().scale_error + o.scale_markov());
                (reading, scale)
            }
            None => (None, None),
        };
        Some(SensorSample {
            truth,
            imu: self.imu.corrupt(&exact),
            gnss: self
                .gnss
                .as_mut()
                .and_then(|g| g.sample(&truth, &motion.omega_nb)),
            attitude: self.attitude.as_mut().and_then(|a| a.sample(&truth)),
            odometer,
            odometer_scale,
        })
    }
}

/// A fingerprint of the bits of the data a filter consumes: FNV-1a taken a
/// 64-bit word at a time, with a rotation so the high bits of one word
/// reach the low bits of the next step.
///
/// Each step (xor with the word, multiplication by an odd constant,
/// rotation) is a bijection of the state, so two streams that differ in
/// exactly one word always get different fingerprints. A word at a time
/// instead of FNV's byte at a time: the byte loop was a chain of eight
/// dependent multiplications per value, about 6 % of a run's time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Digest(u64);

impl Default for Digest {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Digest {
    fn word(&mut self, w: u64) {
        self.0 = (self.0 ^ w)
            .wrapping_mul(0x0000_0100_0000_01b3)
            .rotate_left(29);
    }

    fn values(&mut self, v: &[f64]) {
        v.iter().for_each(|x| self.word(x.to_bits()));
    }

    /// Adds the IMU increment and the aiding readings of `s`.
    pub(crate) fn add(&mut self, s: &SensorSample) {
        let i = &s.imu;
        self.values(&[i.time, i.dt]);
        self.values(i.dtheta.as_slice());
        self.values(i.dvel.as_slice());
        if let Some(g) = &s.gnss {
            let f = &g.value;
            self.values(&[f.time, f.pos.lat, f.pos.lon, f.pos.h]);
            if let Some(v) = &f.vel {
                self.values(v.as_slice());
            }
        }
        if let Some(a) = &s.attitude {
            self.values(&[a.time]);
            self.values(a.att.coords.as_slice());
        }
        if let Some(o) = &s.odometer {
            self.values(&[o.value.time, o.value.speed]);
        }
    }

    pub(crate) fn value(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::Digest;

    fn digest(v: &[f64]) -> u64 {
        let mut d = Digest::default();
        d.values(v);
        d.value()
    }

    #[test]
    fn any_single_changed_value_or_bit_changes_the_fingerprint() {
        let base = [1.0, -2.5, 3.25e-7, 0.0, 9.80665, 1e300];
        let reference = digest(&base);
        for i in 0..base.len() {
            for bit in [0, 1, 31, 52, 62, 63] {
                let mut v = base;
                v[i] = f64::from_bits(v[i].to_bits() ^ (1 << bit));
                assert_ne!(digest(&v), reference, "value {i}, bit {bit}");
            }
        }
    }

    #[test]
    fn order_and_length_matter() {
        assert_ne!(digest(&[1.0, 2.0]), digest(&[2.0, 1.0]));
        assert_ne!(digest(&[0.0]), digest(&[0.0, 0.0]));
        assert_eq!(digest(&[1.0, 2.0]), digest(&[1.0, 2.0]));
    }
}
