//! The papers' figures as panels: errors per axis and what the adapters
//! did.

use kestrel::nav::nalgebra::Vector3;
use kestrel_app::experiment::{Adaptation, EpochRecord, PositionAxes};

use super::figure::{Panel, Reference, Scale, Series};
use super::range::wants_log;
use super::FilterTrace;

/// Attitude errors above this (rad, 2°) are drawn in degrees, smaller ones
/// in arcminutes.
const DEGREE_THRESHOLD: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// The axis names of the position panels.
pub(crate) fn position_names(axes: PositionAxes) -> [&'static str; 3] {
    match axes {
        PositionAxes::NorthEastDown => ["north", "east", "down"],
        PositionAxes::EastNorthUp => ["east", "north", "up"],
    }
}

/// One panel per component of `value`, with `scale` applied to it.
fn component_panels(
    traces: &[FilterTrace<'_>],
    names: [&str; 3],
    quantity: &str,
    unit: &str,
    value: impl Fn(&EpochRecord) -> Vector3<f64>,
) -> Vec<Panel> {
    (0..3)
        .map(|k| Panel {
            caption: format!("{} {quantity}", capitalised(names[k])),
            y_label: format!("{} ({unit})", names[k]),
            scale: Scale::Linear,
            series: traces
                .iter()
                .enumerate()
                .map(|(f, t)| Series {
                    filter: f,
                    points: t.records.iter().map(|r| (r.time, value(r)[k])).collect(),
                    marks: Vec::new(),
                })
                .collect(),
            reference: None,
        })
        .collect()
}

fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// Position error panels in `axes`, m.
pub(crate) fn position(traces: &[FilterTrace<'_>], axes: PositionAxes) -> Vec<Panel> {
    component_panels(traces, position_names(axes), "position error", "m", |r| {
        axes.from_ned(&r.position)
    })
}

/// Velocity error panels, north, east, down, m/s.
pub(crate) fn velocity(traces: &[FilterTrace<'_>]) -> Vec<Panel> {
    component_panels(
        traces,
        ["north", "east", "down"],
        "velocity error",
        "m/s",
        |r| r.velocity,
    )
}

/// Attitude error panels, north, east, down, in degrees when some error
/// exceeds two degrees, arcminutes otherwise.
pub(crate) fn attitude(traces: &[FilterTrace<'_>]) -> Vec<Panel> {
    let largest = traces
        .iter()
        .flat_map(|t| t.records.iter())
        .flat_map(|r| r.attitude.iter().copied())
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let (unit, per_rad) = if largest > DEGREE_THRESHOLD {
        ("deg", 180.0 / std::f64::consts::PI)
    } else {
        ("arcmin", 60.0 * 180.0 / std::f64::consts::PI)
    };
    component_panels(
        traces,
        ["north", "east", "down"],
        "attitude error φ",
        unit,
        |r| r.attitude * per_rad,
    )
}

/// An adapter quantity: caption, axis label, value and neutral value
/// (`None`: a panel whenever the value varies).
struct Quantity {
    caption: &'static str,
    y_label: &'static str,
    value: fn(&Adaptation) -> f64,
    neutral: Option<f64>,
}

const QUANTITIES: [Quantity; 5] = [
    Quantity {
        caption: "Fading factor λ applied to the predicted covariance",
        y_label: "λ (–)",
        value: |a| a.fade,
        neutral: Some(1.0),
    },
    Quantity {
        caption: "Largest measurement-noise inflation factor (1/α)",
        y_label: "inflation (–)",
        value: |a| a.inflation,
        neutral: Some(1.0),
    },
    Quantity {
        caption: "Innovation compression factor",
        y_label: "compression (–)",
        value: |a| a.compression,
        neutral: Some(1.0),
    },
    Quantity {
        caption: "Fuzzy odometer gain α₁",
        y_label: "α₁ (–)",
        value: |a| a.alpha1,
        neutral: Some(1.0),
    },
    Quantity {
        caption: "Trace of the measurement noise R used by the gain",
        y_label: "tr R",
        value: |a| a.noise_trace,
        neutral: None,
    },
];

/// Whether `q` ever differs from its neutral value (or, without one,
/// varies) in `records`; non-finite values are ignored.
fn changed(q: &Quantity, records: &[EpochRecord]) -> bool {
    let mut values = records
        .iter()
        .map(|r| (q.value)(&r.adaptation))
        .filter(|v| v.is_finite());
    match q.neutral {
        Some(n) => values.any(|v| v != n),
        None => match values.next() {
            Some(first) => values.any(|v| v != first),
            None => false,
        },
    }
}

/// Panels for the adapter quantities some filter changed (only those
/// filters drawn) and the NIS of every filter on a log axis with the
/// rejected updates marked, with `nis_bound` as reference line.
pub(crate) fn adaptation(traces: &[FilterTrace<'_>], nis_bound: Option<Reference>) -> Vec<Panel> {
    let mut panels = Vec::new();
    for q in &QUANTITIES {
        let series: Vec<Series> = traces
            .iter()
            .enumerate()
            .filter(|(_, t)| changed(q, t.records))
            .map(|(f, t)| Series {
                filter: f,
                points: t
                    .records
                    .iter()
                    .map(|r| (r.time, (q.value)(&r.adaptation)))
                    .collect(),
                marks: Vec::new(),
            })
            .collect();
        if series.is_empty() {
            continue;
        }
        let slices: Vec<&[(f64, f64)]> = series.iter().map(|s| s.points.as_slice()).collect();
        let scale = if wants_log(&slices) {
            Scale::Log
        } else {
            Scale::Linear
        };
        panels.push(Panel {
            caption: q.caption.into(),
            y_label: q.y_label.into(),
            scale,
            series,
            reference: None,
        });
    }
    let has_nis = traces
        .iter()
        .flat_map(|t| t.records.iter())
        .any(|r| r.adaptation.nis.is_finite() && r.adaptation.nis > 0.0);
    if has_nis {
        panels.push(Panel {
            caption: "NIS of the raw innovation (log scale; × rejected update)".into(),
            y_label: "NIS (–)".into(),
            scale: Scale::Log,
            series: traces
                .iter()
                .enumerate()
                .map(|(f, t)| Series {
                    filter: f,
                    points: t
                        .records
                        .iter()
                        .map(|r| (r.time, r.adaptation.nis))
                        .collect(),
                    marks: t
                        .records
                        .iter()
                        .filter(|r| r.adaptation.rejected)
                        .map(|r| (r.time, r.adaptation.nis))
                        .collect(),
                })
                .collect(),
            reference: nis_bound,
        });
    }
    panels
}
