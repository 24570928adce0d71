//! The figures of `kestrel process`: errors with the filter's ±3σ envelope,
//! the position NEES with its χ² band, the IMU error estimates, the σ of
//! every state group, and the track.
//!
//! | file | what |
//! |---|---|
//! | `position`, `velocity`, `attitude` | errors against the truth per axis, each solution with its ±3σ envelope (with `--truth`) |
//! | `nees` | position NEES of each solution on a log axis, with the two-sided 95 % χ²(3) band (with `--truth`) |
//! | `track` | north against east from the start, m: the solutions, the fixes used, the outage stretches marked |
//! | `imu_errors` | gyro and accelerometer bias (and scale-factor) estimates over time, per body axis |
//! | `std` | σ of attitude, velocity, position and the sensor states over time, log axis |
//!
//! Forward and smoothed solutions share each figure when both exist.

use std::path::{Path, PathBuf};

use kestrel::nav::nalgebra::Vector3;
use kestrel_app::experiment::{EpochRecord, PositionAxes};
use kestrel_app::process::{chi_square_band, StateRow, StateTraces, Track};

use super::figure::{Figure, Panel, Scale, Series};
use super::panels;
use super::track::TrackFigure;
use super::FilterTrace;
use crate::CliError;

/// The figure stems [`process_figures`] may write (each as PNG and SVG).
///
/// ```
/// assert!(kestrel_cli::plot::PROCESS_FIGURES.contains(&"track"));
/// ```
pub const PROCESS_FIGURES: [&str; 7] = [
    "position",
    "velocity",
    "attitude",
    "nees",
    "track",
    "imu_errors",
    "std",
];

/// One solution's errors and σ at the compared epochs.
#[derive(Clone, Copy, Debug)]
pub struct SolutionErrors<'a> {
    /// Its name (legend).
    pub label: &'a str,
    /// Errors at the compared epochs.
    pub errors: &'a [EpochRecord],
    /// σ of the navigation errors at the same epochs (attitude rad,
    /// velocity m/s, position m; NED).
    pub sigma: &'a [[f64; 9]],
    /// Position NEES (time, value).
    pub nees: &'a [(f64, f64)],
}

/// What `kestrel process` draws.
#[derive(Clone, Copy, Debug)]
pub struct ProcessPlots<'a> {
    /// Title prefix.
    pub title: &'a str,
    /// Axes of the position errors.
    pub axes: PositionAxes,
    /// Forward (then smoothed) errors, with a truth.
    pub solutions: &'a [SolutionErrors<'a>],
    /// The track.
    pub track: &'a Track,
    /// The estimates and σ over time.
    pub states: &'a StateTraces,
}

/// Draws the figures of `plots` into `dir`; returns the files written.
///
/// # Errors
/// [`CliError`] if a file cannot be written or drawing fails.
pub fn process_figures(dir: &Path, plots: &ProcessPlots<'_>) -> Result<Vec<PathBuf>, CliError> {
    std::fs::create_dir_all(dir).map_err(|e| CliError::io(dir, e))?;
    let mut written = Vec::new();
    let titled = |what: &str| {
        if plots.title.is_empty() {
            what.to_owned()
        } else {
            format!("{}: {what}", plots.title)
        }
    };
    // One panel figure titled `what`, saved as `stem`.
    let mut save = |what: &str, filters: Vec<String>, panels: Vec<Panel>, stem: &str| {
        let figure = Figure {
            title: titled(what),
            filters,
            panels,
        };
        figure.save(dir, stem).map(|files| written.extend(files))
    };
    if !plots.solutions.is_empty() {
        let (filters, figures) = error_panels(plots.solutions, plots.axes);
        for ((what, panels), stem) in figures
            .into_iter()
            .zip(["position", "velocity", "attitude"])
        {
            save(what, filters.clone(), panels, stem)?;
        }
        let (filters, panel) = nees_panel(plots.solutions);
        save(
            "position NEES (3 degrees of freedom)",
            filters,
            vec![panel],
            "nees",
        )?;
    }
    if !plots.states.forward.is_empty() {
        let (filters, panels) = estimate_panels(plots.states);
        save(
            "IMU error estimates (body axes)",
            filters,
            panels,
            "imu_errors",
        )?;
        let (filters, panels) = sigma_panels(plots.states);
        save("filter standard deviations", filters, panels, "std")?;
    }
    if !plots.track.forward.is_empty() {
        let figure = TrackFigure {
            title: titled("track (north against east from the start)"),
            track: plots.track,
        };
        written.extend(figure.save(dir, "track")?);
    }
    Ok(written)
}

/// Records holding `sign · 3σ` in place of the errors, at the same times.
fn envelope(s: &SolutionErrors<'_>, sign: f64) -> Vec<EpochRecord> {
    s.errors
        .iter()
        .zip(s.sigma)
        .map(|(r, sigma)| {
            let v = |first: usize| {
                Vector3::new(sigma[first], sigma[first + 1], sigma[first + 2]) * (3.0 * sign)
            };
            EpochRecord {
                attitude: v(0),
                velocity: v(3),
                position: v(6),
                ..*r
            }
        })
        .collect()
}

/// The position, velocity and attitude error panels with envelopes, and
/// the legend: each solution, then its ±3σ.
fn error_panels(
    solutions: &[SolutionErrors<'_>],
    axes: PositionAxes,
) -> (Vec<String>, [(&'static str, Vec<Panel>); 3]) {
    let bounds: Vec<[Vec<EpochRecord>; 2]> = solutions
        .iter()
        .map(|s| [envelope(s, 1.0), envelope(s, -1.0)])
        .collect();
    // Three traces per solution: the errors, +3σ, −3σ.
    let mut traces = Vec::with_capacity(3 * solutions.len());
    for (s, [up, down]) in solutions.iter().zip(&bounds) {
        traces.push(FilterTrace {
            label: s.label,
            records: s.errors,
        });
        traces.push(FilterTrace {
            label: s.label,
            records: up,
        });
        traces.push(FilterTrace {
            label: s.label,
            records: down,
        });
    }
    // Legend entries: solution k is 2k, its envelope 2k + 1.
    let regroup = |mut panels: Vec<Panel>| {
        for p in &mut panels {
            for series in &mut p.series {
                let (k, part) = (series.filter / 3, series.filter % 3);
                series.filter = 2 * k + usize::from(part != 0);
            }
        }
        panels
    };
    let filters = solutions
        .iter()
        .flat_map(|s| [s.label.to_owned(), format!("{} ±3σ", s.label)])
        .collect();
    (
        filters,
        [
            ("position error", regroup(panels::position(&traces, axes))),
            ("velocity error", regroup(panels::velocity(&traces))),
            ("attitude error", regroup(panels::attitude(&traces))),
        ],
    )
}

/// The NEES of every solution and the band's ends as two more lines.
fn nees_panel(solutions: &[SolutionErrors<'_>]) -> (Vec<String>, Panel) {
    let (low, high) = chi_square_band(3);
    let times = solutions.iter().flat_map(|s| s.nees.iter().map(|p| p.0));
    let (t0, t1) = times.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
        (a.min(t), b.max(t))
    });
    let mut series: Vec<Series> = solutions
        .iter()
        .enumerate()
        .map(|(k, s)| Series {
            filter: k,
            points: s.nees.to_vec(),
            marks: Vec::new(),
        })
        .collect();
    let band = solutions.len();
    if t0 <= t1 {
        for v in [low, high] {
            series.push(Series {
                filter: band,
                points: vec![(t0, v), (t1, v)],
                marks: Vec::new(),
            });
        }
    }
    let mut filters: Vec<String> = solutions.iter().map(|s| s.label.to_owned()).collect();
    filters.push(format!("95 % χ²(3) band [{low:.3}, {high:.2}]"));
    let panel = Panel {
        caption: "position NEES δrᵀ P⁻¹ δr: a consistent filter stays in the band at 95 % of the \
                  epochs"
            .to_owned(),
        y_label: "NEES".to_owned(),
        scale: Scale::Log,
        series,
        reference: None,
    };
    (filters, panel)
}

/// Groups of three columns with a common stem (`gyro_bias_x_deg_per_h` …):
/// (caption, unit, column indices x y z).
fn groups(names: &[String]) -> Vec<(String, String, [usize; 3])> {
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let Some((stem, unit)) = split_axis(name, "_x_").or_else(|| split_axis(name, "_n_")) else {
            continue;
        };
        let (y, z) = if name.contains("_x_") {
            ("_y_", "_z_")
        } else {
            ("_e_", "_d_")
        };
        let find = |axis: &str| {
            names
                .iter()
                .position(|n| *n == format!("{stem}{axis}{unit}"))
        };
        if let (Some(j), Some(k)) = (find(y), find(z)) {
            let caption = match stem {
                "att" => "attitude".to_owned(),
                "vel" => "velocity".to_owned(),
                "pos" => "position".to_owned(),
                other => other.replace('_', " "),
            };
            let unit = match unit {
                "mps" => "m/s".to_owned(),
                other => other.replace("_per_", "/"),
            };
            out.push((caption, unit, [i, j, k]));
        }
    }
    out
}

/// `gyro_bias_x_deg_per_h` split at `_x_`: (`gyro_bias`, `deg_per_h`).
fn split_axis<'a>(name: &'a str, axis: &str) -> Option<(&'a str, &'a str)> {
    name.split_once(axis)
}

/// The legend of the state figures: per solution, one entry per axis.
fn axis_legend(states: &StateTraces, axes: [&str; 3]) -> Vec<String> {
    let mut labels: Vec<String> = axes.iter().map(|a| format!("{a} (forward)")).collect();
    if !states.smoothed.is_empty() {
        labels.extend(axes.iter().map(|a| format!("{a} (smoothed)")));
    }
    labels
}

/// One panel per group of columns taken by `column` from the rows.
fn row_panels(
    states: &StateTraces,
    names: &[String],
    column: impl Fn(&StateRow, usize) -> f64,
    scale: Scale,
) -> Vec<Panel> {
    groups(names)
        .into_iter()
        .map(|(caption, unit, idx)| {
            let mut series = Vec::new();
            for (solution, rows) in [&states.forward, &states.smoothed].iter().enumerate() {
                for (axis, &c) in idx.iter().enumerate() {
                    if rows.is_empty() {
                        continue;
                    }
                    series.push(Series {
                        filter: 3 * solution + axis,
                        points: rows.iter().map(|r| (r.time, column(r, c))).collect(),
                        marks: Vec::new(),
                    });
                }
            }
            Panel {
                caption: caption.clone(),
                y_label: format!("{caption} ({unit})"),
                scale,
                series,
                reference: None,
            }
        })
        .collect()
}

/// The sensor-error estimates: bias and scale-factor panels.
fn estimate_panels(states: &StateTraces) -> (Vec<String>, Vec<Panel>) {
    let mut panels = row_panels(
        states,
        &states.estimates,
        |r, c| r.estimates[c],
        Scale::Linear,
    );
    // A model without scale states has them fixed at their initial values.
    panels.retain(|p| {
        p.series
            .iter()
            .any(|s| s.points.windows(2).any(|w| w[0].1 != w[1].1))
            || !p.caption.contains("scale")
    });
    (axis_legend(states, ["x", "y", "z"]), panels)
}

/// σ of every state group (navigation axes N E D, sensors x y z).
fn sigma_panels(states: &StateTraces) -> (Vec<String>, Vec<Panel>) {
    let panels = row_panels(states, &states.sigmas, |r, c| r.sigmas[c], Scale::Log);
    (
        axis_legend(states, ["north / x", "east / y", "down / z"]),
        panels,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_groups_pair_the_axes() {
        let names: Vec<String> = [
            "att_n_deg",
            "att_e_deg",
            "att_d_deg",
            "gyro_bias_x_deg_per_h",
            "gyro_bias_y_deg_per_h",
            "gyro_bias_z_deg_per_h",
            "odometer_scale_ppm",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let g = groups(&names);
        assert_eq!(g.len(), 2);
        assert_eq!(g[0], ("attitude".to_owned(), "deg".to_owned(), [0, 1, 2]));
        assert_eq!(
            g[1],
            ("gyro bias".to_owned(), "deg/h".to_owned(), [3, 4, 5])
        );
    }
}
