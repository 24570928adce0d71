//! Before the pass: the inputs checked and opened, the output folder made
//! safe to write, and the job assembled with its result files, comparison
//! with the truth and smoother's record.
//!
//! The order matters: everything that can be refused (a flag without its
//! table, an unreadable input, an output that would replace an input) is
//! refused before the first result file is created.

use kestrel_io::input::Input as In;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use kestrel_io::gins::{last_time, ImuReader, ImuRecord, OdometerReader};
use kestrel_io::input::Tally;

use super::dispatch::GnssLayout;
use super::drift::{gap_threshold, DriftTable};
use super::evaluation::{Evaluation, EvaluationSetup, Truth};
use super::pipeline::{GnssInput, GnssSource, Job};
use super::sink::{Sink, SinkSetup};
use super::smooth::{ForwardRecord, SmoothSetup};
use super::{Inputs, OdometerInput, Progress, Settings};
use crate::progress::Ticker;
use crate::{Error, InputError};

/// Refuses odometer flags the configuration cannot serve: any odometer
/// input needs the `[odometer]` table, and `--odo` outside the GINS layout
/// needs the IMU file's odometer column named.
pub(super) fn check_odometer(inputs: &Inputs, settings: &Settings) -> Result<(), Error> {
    let flag = match inputs.odometer {
        OdometerInput::None => None,
        OdometerInput::ImuColumn => Some("--odo"),
        OdometerInput::File(_) => Some("--odometer"),
    };
    if let (Some(flag), None) = (flag, &settings.odometer) {
        return Err(
            InputError::file(&inputs.config, format!("{flag} needs an [odometer] table"))
                .with_key("odometer")
                .into(),
        );
    }
    if inputs.odometer == OdometerInput::ImuColumn
        && !settings.imu_format.is_gins()
        && settings.imu_format.odometer.is_none()
    {
        return Err(InputError::file(
            &inputs.config,
            "--odo reads the odometer speed from the IMU file: give its column",
        )
        .with_key("imu_file.columns.odometer")
        .into());
    }
    Ok(())
}

/// The run's inputs, each opened once and read by one reader from here to
/// the end of the run (the alignment, the pass, the evaluation and the
/// smoother share the streams); their tallies go into the manifest.
pub(crate) struct Readers {
    pub imu: ImuReader<In>,
    /// IMU records read ahead (by the alignment) and not yet processed.
    pub imu_ahead: VecDeque<ImuRecord>,
    pub gnss: Option<GnssSource>,
    /// What the first fix holds: the GNSS measurement of the filter.
    pub layout: GnssLayout,
    pub truth: Option<Truth>,
    pub odometer: Option<OdometerReader<In>>,
    /// Every input by its flag, with what was read of it.
    pub tallies: Vec<(String, PathBuf, Tally)>,
}

impl Readers {
    /// Opens the files `inputs` names in the formats of `settings`.
    pub(super) fn open(inputs: &Inputs, settings: &Settings) -> Result<Self, Error> {
        let mut tallies = Vec::new();
        let mut open = |flag: &str, path: &Path| -> Result<In, Error> {
            let (reader, tally) = kestrel_io::input::open(path)?;
            tallies.push((flag.to_owned(), path.to_path_buf(), tally));
            Ok(reader)
        };
        let imu = ImuReader::with_format(
            open("--imu", &inputs.imu)?,
            &inputs.imu,
            &settings.imu_format,
            settings.week,
            settings.start.time,
        );
        let (gnss, layout) = match &inputs.gnss {
            None => (None, GnssLayout::None),
            Some(p) => {
                let reader = open("--gnss", p)?;
                let mut g = GnssSource::open(GnssInput::new(
                    reader,
                    p,
                    &settings.gnss_format,
                    settings.week,
                ))?;
                let layout = match g.peek()? {
                    None => GnssLayout::None,
                    Some(f) if f.vel.is_some() => GnssLayout::PositionVelocity,
                    Some(_) => GnssLayout::Position,
                };
                (Some(g), layout)
            }
        };
        let truth = match inputs.truth.as_deref() {
            Some(p) => Some(Truth::new(
                open("--truth", p)?,
                p,
                &settings.truth.format,
                settings.week,
            )),
            None => None,
        };
        let odometer = match &inputs.odometer {
            OdometerInput::File(p) => Some(OdometerReader::new(open("--odometer", p)?, p)),
            _ => None,
        };
        Ok(Self {
            imu,
            imu_ahead: VecDeque::new(),
            gnss,
            layout,
            truth,
            odometer,
            tallies,
        })
    }
}

/// The job of the pass: the readers, the result files (with the
/// comparison with the truth and the progress report) and, with
/// `--smooth`, the smoother's record. Files are created from here on.
pub(super) fn job<'p>(
    inputs: &Inputs,
    settings: &Settings,
    mut readers: Readers,
    dir: &Path,
    progress: &'p mut dyn Progress,
) -> Result<Job<'p>, Error> {
    let gap = readers
        .gnss
        .as_mut()
        .and_then(|g| gnss_gap_threshold(g).transpose())
        .transpose()?;
    let evaluation = match readers.truth.take() {
        Some(truth) => {
            // The smoother compares against the same truth, replayed from
            // what the forward comparison read: the file is read once.
            let truth = if inputs.smooth {
                truth.tee(dir.join(".work-truth"))?
            } else {
                truth
            };
            Some(compare_with(
                inputs,
                settings,
                truth,
                gap,
                dir.join("errors.csv"),
            )?)
        }
        None => None,
    };
    let smoother = if inputs.smooth {
        Some(smoother(inputs, settings, gap, dir)?)
    } else {
        None
    };
    // The span reported as progress: to the last line's time (GINS layout
    // only; otherwise unknown).
    let end = if settings.imu_format.is_gins() {
        last_time(&inputs.imu).unwrap_or(settings.start.time)
    } else {
        settings.start.time
    };
    let sink = Sink::new(SinkSetup {
        label: settings.kind.label(),
        week: settings.week,
        interval: settings.output_interval,
        nav_path: &dir.join("result.nav"),
        csv_path: &dir.join("result.csv"),
        evaluation,
        progress: Ticker::new(progress, settings.start.time, end),
    })?;
    Job::new(readers, sink, smoother, settings, inputs, dir)
}

/// The smoother's record, comparing the smoothed solution with the truth
/// the forward comparison read (replayed from the scratch folder).
fn smoother(
    inputs: &Inputs,
    settings: &Settings,
    gap: Option<f64>,
    dir: &Path,
) -> Result<ForwardRecord, Error> {
    let evaluation = match inputs.truth.as_deref() {
        None => None,
        Some(_) => Some(compare_with(
            inputs,
            settings,
            Truth::replay(&dir.join(".work-truth"), inputs.truth.as_deref())?,
            gap,
            dir.join("errors_smoothed.csv"),
        )?),
    };
    ForwardRecord::new(
        dir,
        SmoothSetup {
            label: settings.kind.label(),
            week: settings.week,
            interval: settings.output_interval,
            earth: settings.earth,
            nav_path: dir.join("smoothed.nav"),
            csv_path: dir.join("smoothed.csv"),
            out: dir.to_path_buf(),
            evaluation,
        },
    )
}

/// The comparison of a solution with `truth`, writing `csv`.
fn compare_with(
    inputs: &Inputs,
    settings: &Settings,
    truth: Truth,
    gap: Option<f64>,
    csv: PathBuf,
) -> Result<Evaluation, Error> {
    Evaluation::new(EvaluationSetup {
        earth: settings.earth,
        axes: settings.axes,
        truth,
        antenna: settings.truth.at_antenna.then_some(settings.lever_arm),
        csv_path: csv,
        drift: DriftTable::new(&inputs.outages, gap, settings.start.time),
    })
}

/// 1.5 × the median interval of the first 21 intervals of the GNSS file:
/// longer intervals between fixes are data gaps. `None` if the file has
/// fewer than two fixes. The fixes are read ahead in the pass's own stream.
fn gnss_gap_threshold(gnss: &mut GnssSource) -> Result<Option<f64>, InputError> {
    let mut times = Vec::with_capacity(22);
    for i in 0..22 {
        // A bad line ends the look-ahead; the pass reports it at its turn.
        match gnss.ahead(i)? {
            Some(f) => times.push(f.time),
            None => break,
        }
    }
    Ok(gap_threshold(&times))
}
