//! Paper 003's SINS / odometer run (scenario 003): the IMU mounted with
//! the scenario's misalignment to the vehicle, odometer-only aiding, and a
//! choice of odometer fault processing.

use kestrel::nalgebra::SMatrix;
use kestrel::nav::engine::LooselyCoupled;
use kestrel::nav::measurement::{GnssAntenna, Odometer};
use kestrel::nav::nalgebra::{SVector, Vector3};
use kestrel::nav::odometer::{FuzzyOdometer, InsOdometer16, MaxThreshold, ScaleFactorProcess};
use kestrel::nav::{NavError, Strapdown};
use kestrel::sim::OdometerSensor;
use kestrel::Ekf;
use kestrel_app::scenario::scenario_003;

/// IMU rate, Hz (the paper's 200 Hz does not matter at this accuracy).
pub const RATE: f64 = 100.0;

/// How odometer updates are processed.
pub enum Processing {
    /// Every reading is used as is.
    Plain,
    /// The max-threshold baseline.
    Threshold(MaxThreshold<f64>),
    /// The fuzzy adaptive gain with the windowed R.
    Fuzzy(Box<FuzzyOdometer<f64, 20>>),
}

/// What a run gives.
pub struct DrRun {
    /// Distance travelled, m.
    pub distance: f64,
    /// Position error (3D, m) every 10 s, with its time.
    pub errors: Vec<(f64, f64)>,
    /// Largest position error, m.
    pub worst: f64,
    /// Final scale-factor estimate and its σ, and the truth's.
    pub scale: (f64, f64, f64),
    /// Updates rejected (isolated or judged unusable).
    pub rejected: usize,
    /// Readings the simulation marked faulty.
    pub faulty: usize,
    /// Faulty readings whose update was rejected.
    pub rejected_faulty: usize,
}

impl DrRun {
    /// The position error at `t` (the sample at or before it).
    pub fn error_at(&self, t: f64) -> f64 {
        self.errors
            .iter()
            .rev()
            .find(|e| e.0 <= t + 1e-6)
            .unwrap()
            .1
    }
}

/// Runs scenario 003 (with its odometer faults if `faults`) on its own
/// seed.
pub fn run_003(faults: bool, processing: Processing) -> DrRun {
    run_003_seed(scenario_003().seed, faults, processing)
}

/// Runs scenario 003 (with its odometer faults if `faults`) with sensor
/// noise from `seed`.
pub fn run_003_seed(seed: u64, faults: bool, mut processing: Processing) -> DrRun {
    let sc = scenario_003();
    let mut odo_config = sc.odometer.clone().unwrap();
    if !faults {
        odo_config.faults.clear();
    }
    let earth = sc.earth;
    let mut odo_sensor = OdometerSensor::new(odo_config, earth, seed);
    let mut imu_sensor = sc.imu_sensor(seed);
    // The filter knows the calibrated mounting of the IMU on the vehicle.
    let [pitch, yaw] = sc.filter.odometer_mounting;
    let odometer = Odometer::new(0.1, 0.1).with_mounting(pitch, yaw);

    let traj = sc.trajectory().unwrap();
    let start = traj.initial_state();
    let system = InsOdometer16::new(sc.filter.imu_model, ScaleFactorProcess::as_published());
    let std = sc.filter.p0.std_vector(sc.filter.error_model);
    let p0 =
        SMatrix::<f64, 16, 16>::from_diagonal(&SVector::from_iterator(std.iter().map(|s| s * s)));
    let mut engine = LooselyCoupled::new(
        Strapdown::new(earth, sc.initial_state(&start)),
        Ekf::<f64, 16>::new(SVector::zeros(), p0).unwrap(),
        system,
        GnssAntenna::new(Vector3::zeros()),
        0.1,
    );

    let mut stream = traj.stream(RATE).unwrap();
    let (mut distance, mut worst, mut last) = (0.0, 0.0f64, start);
    let mut errors = Vec::new();
    let (mut rejected, mut faulty, mut rejected_faulty) = (0, 0, 0);
    let mut k = 0u64;
    while let Some((truth, exact)) = stream.next() {
        engine.imu(&imu_sensor.corrupt(&exact)).unwrap();
        distance += earth.ned_offset(&last.pos, &truth.pos).norm();
        last = truth;
        if let Some(r) = odo_sensor.sample(&truth, stream.motion()) {
            faulty += r.faulty as usize;
            let reading = r.value;
            let m = engine.odometer_measurement(&odometer, &reading);
            let was_rejected = match &mut processing {
                Processing::Plain => engine.apply(&m).unwrap().rejected,
                Processing::Threshold(t) => engine.apply_with(&m, t).unwrap().rejected,
                Processing::Fuzzy(f) => {
                    let scale = engine.corrections().odometer_scale;
                    let adapter = f.prepare(&engine.ins_context(reading.time), &reading, scale);
                    engine.apply_with(&m, adapter).unwrap().rejected
                }
            };
            rejected += was_rejected as usize;
            rejected_faulty += (was_rejected && r.faulty) as usize;
        }
        k += 1;
        let err = NavError::between(&earth, engine.solution(), &truth)
            .dr
            .norm();
        worst = worst.max(err);
        if k.is_multiple_of(10 * RATE as u64) {
            errors.push((truth.time, err));
        }
    }
    DrRun {
        distance,
        errors,
        worst,
        scale: (
            engine.corrections().odometer_scale,
            engine.std_devs()[15],
            0.005 + odo_sensor.scale_markov(),
        ),
        rejected,
        faulty,
        rejected_faulty,
    }
}
