//! Before the pass: the inputs checked and opened, the output folder made
//! safe to write, and the job assembled with its result files, comparison
//! with the truth and smoother's record.
//!
//! The order matters: everything that can be refused (a flag without its
//! table, an unreadable input, an output that would replace an input) is
//! refused before the first result file is created.

use std::fs::File;
use std::io::BufReader;
use std::path::{Component, Path};

use kestrel_io::gins::{last_time, ImuReader};

use super::dispatch::GnssLayout;
use super::drift::{gap_threshold, DriftTable};
use super::evaluation::{Evaluation, EvaluationSetup, Truth};
use super::pipeline::{GnssInput, GnssSource, Job};
use super::sink::{Sink, SinkSetup};
use super::smooth::{ForwardRecord, SmoothSetup};
use super::state_files::StateFiles;
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

/// The input files, open: the IMU file, the GNSS file at its first fix
/// (an error before it is reported now) and the truth.
pub(super) struct Readers {
    pub imu: ImuReader<BufReader<File>>,
    pub gnss: Option<GnssSource>,
    /// What the first fix holds: the GNSS measurement of the filter.
    pub layout: GnssLayout,
    pub truth: Option<Truth>,
}

impl Readers {
    /// Opens the files `inputs` names in the formats of `settings`.
    pub(super) fn open(inputs: &Inputs, settings: &Settings) -> Result<Self, Error> {
        let imu = ImuReader::open_with_format(
            &inputs.imu,
            &settings.imu_format,
            settings.week,
            settings.start.time,
        )?;
        let (gnss, layout) = match &inputs.gnss {
            None => (None, GnssLayout::None),
            Some(p) => {
                let mut g =
                    GnssSource::open(GnssInput::open(p, &settings.gnss_format, settings.week)?)?;
                let layout = match g.peek()? {
                    None => GnssLayout::None,
                    Some(f) if f.vel.is_some() => GnssLayout::PositionVelocity,
                    Some(_) => GnssLayout::Position,
                };
                (Some(g), layout)
            }
        };
        let truth = inputs
            .truth
            .as_deref()
            .map(|p| Truth::open(p, &settings.truth.format, settings.week))
            .transpose()?;
        Ok(Self {
            imu,
            gnss,
            layout,
            truth,
        })
    }
}

/// Makes `--out` ready: created, checked not to hold an input under an
/// output's name, and freed of symbolic links under those names.
pub(super) fn prepare_output(inputs: &Inputs) -> Result<(), Error> {
    // A caller's name is a file in `out`, never a path out of it.
    if let Some(bad) = inputs.also_written.iter().find(|n| {
        let mut parts = Path::new(n.as_str()).components();
        !matches!(
            (parts.next(), parts.next()),
            (Some(Component::Normal(_)), None)
        )
    }) {
        return Err(Error::Failed(format!(
            "also_written: `{bad}` is not a plain file name (no folders, `.` or `..`)"
        )));
    }
    std::fs::create_dir_all(&inputs.out).map_err(|e| Error::io(&inputs.out, e))?;
    let names = output_names(&inputs.also_written);
    refuse_overwriting_inputs(inputs, &names)?;
    remove_output_links(&inputs.out, &names)
}

/// The job of the pass: the readers, the result files (with the
/// comparison with the truth and the progress report) and, with
/// `--smooth`, the smoother's record. Files are created from here on.
pub(super) fn job<'p>(
    inputs: &Inputs,
    settings: &Settings,
    readers: Readers,
    progress: &'p mut dyn Progress,
) -> Result<Job<'p>, Error> {
    let Readers {
        imu, gnss, truth, ..
    } = readers;
    let evaluation = truth
        .map(|truth| compare_with(inputs, settings, truth, "errors.csv"))
        .transpose()?;
    let smoother = if inputs.smooth {
        Some(smoother(inputs, settings)?)
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
        nav_path: &inputs.out.join("result.nav"),
        csv_path: &inputs.out.join("result.csv"),
        evaluation,
        progress: Ticker::new(progress, settings.start.time, end),
    })?;
    Job::new(imu, gnss, sink, smoother, settings, inputs)
}

/// The smoother's record, comparing the smoothed solution with its own
/// reading of the truth.
fn smoother(inputs: &Inputs, settings: &Settings) -> Result<ForwardRecord, Error> {
    let evaluation = match inputs.truth.as_deref() {
        None => None,
        Some(p) => {
            let truth = Truth::open(p, &settings.truth.format, settings.week)?;
            Some(compare_with(
                inputs,
                settings,
                truth,
                "errors_smoothed.csv",
            )?)
        }
    };
    ForwardRecord::new(
        &inputs.out,
        SmoothSetup {
            label: settings.kind.label(),
            week: settings.week,
            interval: settings.output_interval,
            earth: settings.earth,
            nav_path: inputs.out.join("smoothed.nav"),
            csv_path: inputs.out.join("smoothed.csv"),
            out: inputs.out.clone(),
            evaluation,
        },
    )
}

/// The comparison of a solution with `truth`, writing `csv` in `--out`.
fn compare_with(
    inputs: &Inputs,
    settings: &Settings,
    truth: Truth,
    csv: &str,
) -> Result<Evaluation, Error> {
    Evaluation::new(EvaluationSetup {
        earth: settings.earth,
        axes: settings.axes,
        truth,
        antenna: settings.truth.at_antenna.then_some(settings.lever_arm),
        csv_path: inputs.out.join(csv),
        drift: DriftTable::new(
            &inputs.outages,
            inputs
                .gnss
                .as_deref()
                .and_then(|p| gnss_gap_threshold(p, settings)),
            settings.start.time,
        ),
    })
}

/// 1.5 × the median interval of the first 21 intervals of the GNSS file:
/// longer intervals between fixes are data gaps. `None` if the file has
/// fewer than two fixes (an unreadable line is the main reader's to report).
fn gnss_gap_threshold(path: &Path, settings: &Settings) -> Option<f64> {
    let times: Vec<f64> = GnssInput::open(path, &settings.gnss_format, settings.week)
        .ok()?
        .take(22)
        .map_while(Result::ok)
        .map(|f| f.time)
        .collect();
    gap_threshold(&times)
}

/// The names written in `--out`: the run's own and the caller's `extra`.
fn output_names(extra: &[String]) -> Vec<String> {
    let states = ["result", "smoothed"]
        .into_iter()
        .flat_map(StateFiles::names);
    [
        "result.nav",
        "result.csv",
        "errors.csv",
        "error_summary.csv",
        "drift.csv",
        "smoothed.nav",
        "smoothed.csv",
        "errors_smoothed.csv",
        ".smoother-epochs.partial",
        ".smoother-samples.partial",
        ".smoother-corrections.partial",
    ]
    .map(String::from)
    .into_iter()
    .chain(states)
    .chain(extra.iter().cloned())
    .collect()
}

/// Refuses a run whose outputs would replace one of its inputs (say
/// `--truth out/result.nav --out out`), comparing resolved paths, so a
/// symbolic link in `--out` pointing at an input is caught too.
fn refuse_overwriting_inputs(inputs: &Inputs, names: &[String]) -> Result<(), Error> {
    let out = std::fs::canonicalize(&inputs.out).map_err(|e| Error::io(&inputs.out, e))?;
    let odometer = match &inputs.odometer {
        OdometerInput::File(p) => Some(p),
        _ => None,
    };
    let given = [
        ("--imu", Some(&inputs.imu)),
        ("--gnss", inputs.gnss.as_ref()),
        ("--truth", inputs.truth.as_ref()),
        ("--odometer", odometer),
        ("--config", Some(&inputs.config)),
    ];
    for (flag, input) in given {
        let Some(input) = input else { continue };
        let Ok(input_real) = std::fs::canonicalize(input) else {
            continue;
        };
        for name in names {
            let output = out.join(name);
            let resolved = std::fs::canonicalize(&output).unwrap_or(output.clone());
            if resolved == input_real || output == input_real {
                return Err(Error::Failed(format!(
                    "refusing to write {}: it is the {flag} input {}; choose another --out",
                    inputs.out.join(name).display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

/// Removes symbolic links standing under output names in `out`, so no
/// output is ever written through one (the link goes, its target is never
/// touched; inputs were checked before).
fn remove_output_links(out: &Path, names: &[String]) -> Result<(), Error> {
    for name in names {
        let p = out.join(name);
        if std::fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink()) {
            std::fs::remove_file(&p).map_err(|e| Error::io(&p, e))?;
        }
    }
    Ok(())
}
