//! `kestrel simulate`: a scenario's truth and sensor data in the open GINS
//! text formats, with a matching `kestrel process` configuration.

mod process_config;

use std::path::{Path, PathBuf};

use crate::experiment::{RunOptions, Simulation};
use crate::scenario::{by_name, Scenario};

use crate::transaction::{Begin, Cancel, Provenance, Transaction};
use crate::{Error, InputError};
use kestrel_io::gins::{GnssWriter, ImuRecord, ImuWriter, NavWriter};

pub use process_config::process_config;

/// What to simulate and where to write it.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulateOptions {
    /// A built-in scenario (000, 001, 002, 003, 004) or a scenario file
    /// (.toml): see [`scenario`].
    pub scenario: String,
    /// Random seed of the sensor noise (`None`: the scenario's).
    pub seed: Option<u64>,
    /// Simulate only the first seconds of the trajectory.
    pub duration: Option<f64>,
    /// IMU rate in Hz (`None`: the scenario's).
    pub imu_rate: Option<f64>,
    /// Output directory (created if missing).
    pub out: PathBuf,
    /// Also replace an imu.txt, gnss.txt, truth.nav or process.toml that
    /// no earlier kestrel run into the folder wrote (without it they are
    /// refused; an earlier run's files are always replaced, exactly the set
    /// its manifest lists).
    pub force: bool,
}

/// What `simulate` wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulateReport {
    /// IMU samples written.
    pub samples: usize,
    /// GNSS fixes written.
    pub fixes: usize,
    /// Whether the IMU file has the odometer column.
    pub odometer: bool,
    /// The files: imu.txt, gnss.txt, truth.nav, process.toml.
    pub files: Vec<PathBuf>,
}

/// The I/O error mapping for `p`.
fn io(p: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::io(p, e)
}

/// The scenario named by `arg`: a built-in name or a scenario file.
///
/// # Errors
/// [`Error`] for an unknown name or a bad file.
pub fn scenario(arg: &str) -> Result<Scenario, Error> {
    if let Some(s) = by_name(arg) {
        return Ok(s);
    }
    let path = Path::new(arg);
    if path.extension().is_some_and(|e| e == "toml") {
        return crate::config::scenario::load(path);
    }
    Err(Error::Failed(format!(
        "unknown scenario `{arg}`: expected 000, 001, 002, 003, 004 or a .toml file"
    )))
}

/// Writes the files of `args` and says what it wrote.
///
/// # Errors
/// [`Error`]: unknown scenario, invalid options, unwritable files.
///
/// ```
/// use kestrel_app::simulate::{simulate, SimulateOptions};
/// let dir = std::env::temp_dir().join(format!("kestrel-doc-simulate-{}", std::process::id()));
/// let r = simulate(&SimulateOptions { scenario: "003".into(), seed: None, duration: Some(2.0),
///     imu_rate: None, out: dir.clone(), force: true }).unwrap();
/// assert_eq!((r.samples, r.fixes, r.odometer), (400, 0, true));
/// let imu = std::fs::read_to_string(dir.join("imu.txt")).unwrap();
/// assert_eq!(imu.lines().last().unwrap().split(' ').count(), 8);
/// assert!(kestrel_app::simulate::scenario("999").is_err());
/// ```
pub fn simulate(args: &SimulateOptions) -> Result<SimulateReport, Error> {
    simulate_with(args, &Cancel::default(), &[])
}

/// As [`simulate`], stopped by `cancel` (then [`Error::Cancelled`], and
/// nothing written) and recording `command` in the manifest.
///
/// # Errors
/// As [`simulate`], and [`Error::Cancelled`].
pub fn simulate_with(
    args: &SimulateOptions,
    cancel: &Cancel,
    command: &[String],
) -> Result<SimulateReport, Error> {
    let sc = scenario(&args.scenario)?;
    let seed = args.seed.unwrap_or(sc.seed);
    let mut options = RunOptions::default();
    if let Some(d) = args.duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::Failed(format!(
                "--duration must be a positive number of seconds, found {d}"
            )));
        }
        options = options.with_duration(d);
    }
    if let Some(r) = args.imu_rate {
        options = options.with_imu_rate(r);
    }
    let sim = Simulation::new(&sc, seed, &options)
        .map_err(|e| Error::Failed(format!("scenario {}: {e}", sc.name)))?;
    let out = &args.out;
    let mut begin = Begin::command(command.iter().cloned());
    begin.force = args.force;
    if Path::new(&args.scenario)
        .extension()
        .is_some_and(|e| e == "toml")
    {
        begin = begin.input("scenario", &args.scenario);
    }
    let mut tx = Transaction::begin(out, begin)?;
    let paths = [
        tx.path("imu.txt")?,
        tx.path("gnss.txt")?,
        tx.path("truth.nav")?,
        tx.path("process.toml")?,
    ];
    let [imu_path, gnss_path, truth_path, config_path] = &paths;
    let has_odometer = sc.odometer.is_some();
    let head = format!(
        "kestrel simulate {} seed {seed}: {}",
        sc.name, sc.description
    );

    let mut imu = ImuWriter::create(imu_path)?;
    imu.comment(&head).map_err(io(imu_path))?;
    imu.comment(if has_odometer {
        "sow dθx dθy dθz (rad) dvx dvy dvz (m/s) odometer speed (m/s, the latest reading)"
    } else {
        "sow dθx dθy dθz (rad) dvx dvy dvz (m/s)"
    })
    .map_err(io(imu_path))?;
    let mut gnss = GnssWriter::create(gnss_path)?;
    gnss.comment(&head).map_err(io(gnss_path))?;
    gnss.comment("sow lat lon (deg) h (m) σN σE σD (m) [vN vE vD σvN σvE σvD (m/s)]")
        .map_err(io(gnss_path))?;
    let mut truth = NavWriter::create(truth_path)?;
    truth.comment(&head).map_err(io(truth_path))?;
    truth
        .comment("week sow lat lon (deg) h (m) vN vE vD (m/s) roll pitch yaw (deg)")
        .map_err(io(truth_path))?;

    let start_truth = sim.initial_truth();
    truth.write(0, &start_truth).map_err(io(truth_path))?;
    let (mut samples, mut fixes, mut speed) = (0, 0, 0.0);
    for s in sim {
        if let Some(o) = &s.odometer {
            speed = o.value.speed;
        }
        if let Some(g) = &s.gnss {
            gnss.write(&g.value).map_err(io(gnss_path))?;
            fixes += 1;
        }
        let rec = ImuRecord {
            time: s.imu.time,
            dtheta: s.imu.dtheta,
            dvel: s.imu.dvel,
            odometer: has_odometer.then_some(speed),
            line: 0,
        };
        imu.write(&rec).map_err(io(imu_path))?;
        truth.write(0, &s.truth).map_err(io(truth_path))?;
        samples += 1;
    }
    imu.into_inner().map_err(io(imu_path))?;
    gnss.into_inner().map_err(io(gnss_path))?;
    truth.into_inner().map_err(io(truth_path))?;
    cancel.check()?;
    let kind = sc
        .filters
        .first()
        .copied()
        .unwrap_or(crate::scenario::FilterKind::Standard);
    let text = process_config(&sc, &sc.initial_state(&start_truth), &kind);
    std::fs::write(config_path, text).map_err(io(config_path))?;
    if samples == 0 {
        return Err(InputError::file(out, "the simulation produced no IMU sample").into());
    }
    let files = tx.commit(Provenance {
        seeds: vec![seed],
        ..Provenance::default()
    })?;
    Ok(SimulateReport {
        samples,
        fixes,
        odometer: has_odometer,
        files,
    })
}
