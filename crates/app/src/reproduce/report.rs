//! The printed report of a Monte Carlo and its summary CSV.

use std::fmt::Write as _;
use std::path::Path;

use crate::experiment::PositionAxes;
use crate::experiment::ScaleEstimate;
use crate::scenario::{Scenario, TUNING_SEEDS};

use super::metric::Metric;
use super::monte_carlo::{FilterOutcome, MonteCarloPlan};
use super::paper::{Paper, PaperTable};
use super::stats::MeanStd;
use super::table::TextTable;
use crate::Error;

/// Everything a report is made from.
#[derive(Clone, Copy, Debug)]
pub struct ReportInput<'a> {
    /// The scenario that was run.
    pub scenario: &'a Scenario,
    /// How it was run.
    pub plan: &'a MonteCarloPlan,
    /// The outcome per filter, in the scenario's order (baseline first).
    pub outcomes: &'a [FilterOutcome],
    /// The paper, for built-in scenarios run by `reproduce`.
    pub paper: Option<&'a Paper>,
}

impl ReportInput<'_> {
    fn axes(&self) -> PositionAxes {
        PositionAxes::for_scenario(&self.scenario.name)
    }

    /// `metric` over the runs that completed with at least one aiding
    /// epoch: a run without one has no RMS (never a 0).
    fn stats(&self, outcome: &FilterOutcome, metric: Metric) -> MeanStd {
        MeanStd::of(
            outcome
                .completed()
                .filter(|s| s.rms_epochs > 0)
                .map(|s| metric.value(s)),
        )
    }
}

/// The text report: RMS tables (mean ± std over the runs), the paper's
/// table beside kestrel's with improvement ratios, failures, window errors.
pub fn text_report(input: &ReportInput<'_>) -> String {
    let mut out = String::new();
    let s = input.scenario;
    let plan = input.plan;
    let _ = writeln!(out, "== Scenario {}: {}", s.name, s.description);
    let _ = writeln!(
        out,
        "   {} run(s) per filter, seeds {}–{}; RMS over each run's aiding epochs, mean ± std (median) over the runs that completed\n",
        plan.runs,
        plan.seed,
        plan.seed.wrapping_add(plan.runs as u64 - 1),
    );
    if input.paper.is_some() {
        out.push_str(&tuning_overlap(&s.name, plan));
    }
    let axes = input.axes();
    let (position, motion) = Metric::ALL.split_at(Metric::POSITION_METRICS);
    let groups = [
        ("position error, m", position),
        ("velocity error, m/s and attitude error, deg", motion),
    ];
    for (title, metrics) in groups {
        let mut header = vec![format!("{title}")];
        header.extend(metrics.iter().map(|m| m.heading(axes)));
        header.push("failed runs".to_string());
        let mut t = TextTable::new(header);
        for o in input.outcomes {
            let mut row = vec![o.label.to_string()];
            row.extend(metrics.iter().map(|m| format!("{:.3}", input.stats(o, *m))));
            row.push(format!("{} of {}", o.failures().count(), o.runs.len()));
            t.row(row);
        }
        let _ = writeln!(out, "{t}");
    }
    if let Some(table) = input.paper.and_then(|p| p.table.as_ref()) {
        paper_comparison(&mut out, input, table);
    }
    if let Some(paper) = input.paper {
        window_table(&mut out, input, paper);
    }
    no_epochs(&mut out, input.outcomes);
    failures(&mut out, input.outcomes, plan);
    health(&mut out, input.outcomes, plan);
    let scales: Vec<(String, Vec<ScaleEstimate>)> = input
        .outcomes
        .iter()
        .map(|o| {
            let v = o.completed().filter_map(|s| s.odometer_scale).collect();
            (o.label.clone(), v)
        })
        .collect();
    out.push_str(&scale_table(
        "odometer scale factor at the end of the runs (with the scenario's faults)",
        &scales,
    ));
    out
}

/// Says which filters had runs without an aiding epoch (their RMS is left
/// out of the tables, shown as — when no run had one).
fn no_epochs(out: &mut String, outcomes: &[FilterOutcome]) {
    for o in outcomes {
        let none = o.completed().filter(|s| s.rms_epochs == 0).count();
        if none > 0 {
            let _ = writeln!(
                out,
                "{}: {none} of {} run(s) had no aiding epoch counted in the RMS: no RMS for them (—); \
                 run longer or aid more often\n",
                o.label,
                o.runs.len()
            );
        }
    }
}

/// The odometer scale-factor estimates of each filter's runs against the
/// simulated truth: the mean error and its standard error, the mean σ,
/// the mean z² (1 for an honest σ) and the runs beyond 3σ. Empty when no
/// filter has a scale state.
pub fn scale_table(title: &str, rows: &[(String, Vec<ScaleEstimate>)]) -> String {
    if rows.iter().all(|(_, v)| v.is_empty()) {
        return String::new();
    }
    let mut t = TextTable::new(
        [
            "filter",
            "mean k̂ − k (standard error)",
            "mean σ",
            "mean z²",
            "|z| > 3",
            "runs",
        ]
        .map(String::from)
        .to_vec(),
    );
    for (label, v) in rows {
        if v.is_empty() {
            continue;
        }
        let n = v.len() as f64;
        let errors: Vec<f64> = v.iter().map(|s| s.estimate - s.truth).collect();
        let mean = errors.iter().sum::<f64>() / n;
        let se = if v.len() > 1 {
            (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() / n.sqrt()
        } else {
            f64::NAN
        };
        let sigma = v.iter().map(|s| s.sigma).sum::<f64>() / n;
        let z2 = v.iter().map(|s| s.z().powi(2)).sum::<f64>() / n;
        let beyond = v.iter().filter(|s| s.z().abs() > 3.0).count();
        t.row(vec![
            label.clone(),
            format!("{mean:+.2e} ({se:.1e})"),
            format!("{sigma:.2e}"),
            format!("{z2:.2}"),
            beyond.to_string(),
            v.len().to_string(),
        ]);
    }
    format!(
        "{title}: k̂ the estimate, k the simulated truth (constant plus Markov part), z = (k̂ − k)/σ\n{t}\n"
    )
}

/// The health monitor's findings per filter: runs with an alarm, runs
/// diverged (an alarm still raised at the end), and the first of each.
fn health(out: &mut String, outcomes: &[FilterOutcome], plan: &MonteCarloPlan) {
    let mut t = TextTable::new(
        [
            "health monitor",
            "runs with an alarm",
            "first alarm (run: time, statistic)",
            "runs diverged",
        ]
        .map(String::from)
        .to_vec(),
    );
    for o in outcomes {
        let done: Vec<(usize, &crate::experiment::RunSummary)> = o
            .runs
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().ok().map(|(s, _)| (i, s)))
            .collect();
        let alarmed = done.iter().filter(|(_, s)| s.health.alarms > 0).count();
        let diverged = done.iter().filter(|(_, s)| s.health.diverged()).count();
        let first = done
            .iter()
            .find_map(|(i, s)| s.health.first_alarm.map(|e| (*i, e)))
            .map_or("—".to_string(), |(i, e)| {
                let seed = plan.seed.wrapping_add(i as u64);
                format!("run {i} (seed {seed}): {} s, {}", e.time, e.check)
            });
        t.row(vec![
            o.label.clone(),
            format!("{alarmed} of {}", done.len()),
            first,
            format!("{diverged} of {}", done.len()),
        ]);
    }
    let _ = writeln!(out, "{t}");
    let _ = writeln!(
        out,
        "   alarm: the GNSS/odometer NIS (or the position NEES) beyond its χ² bound for 3 windows of 20 updates in a row; diverged: an alarm still raised at the end of the run (the NEES's, the truth being known)\n"
    );
}

/// Which of the runs' seeds the scenario's parameters were chosen on.
fn tuning_overlap(name: &str, plan: &MonteCarloPlan) -> String {
    let runs = plan.seed..plan.seed.saturating_add(plan.runs as u64);
    let Some((_, tuning)) = TUNING_SEEDS.iter().find(|(n, _)| *n == name) else {
        return String::new();
    };
    let used: Vec<u64> = runs
        .filter(|s| tuning.iter().any(|r| r.contains(s)))
        .collect();
    let ranges: Vec<String> = tuning
        .iter()
        .map(|r| format!("{}–{}", r.start(), r.end()))
        .collect();
    if used.is_empty() {
        format!(
            "   parameters were chosen on seeds {}, none of which is run here\n",
            ranges.join(", ")
        )
    } else {
        format!(
            "   parameters were chosen on seeds {}: {} of these runs use them; the sensitivity study below runs held-out seeds\n",
            ranges.join(", "),
            used.len()
        )
    }
}

fn paper_comparison(out: &mut String, input: &ReportInput<'_>, table: &PaperTable) {
    let _ = writeln!(out, "kestrel mean / median (paper) — {}", table.source);
    let mut header = vec!["filter".to_string()];
    header.extend(table.columns.iter().map(|(_, h)| h.to_string()));
    let mut t = TextTable::new(header.clone());
    let find = |label: &str| input.outcomes.iter().find(|o| o.label == label);
    for row in table.rows {
        let mut cells = vec![row.label.to_string()];
        for ((metric, _), paper) in table.columns.iter().zip(row.values) {
            let ours = find(row.label).map(|o| input.stats(o, *metric));
            cells.push(match ours {
                Some(v) if v.count > 0 => format!("{:.3} / {:.3} ({paper})", v.mean, v.median),
                _ => format!("— ({paper})"),
            });
        }
        t.row(cells);
    }
    let _ = writeln!(out, "{t}");
    let Some(base) = table.rows.first() else {
        return;
    };
    let _ = writeln!(
        out,
        "improvement over {} (its RMS ÷ the filter's): kestrel × of means / of medians (paper ×)",
        base.label
    );
    let mut t = TextTable::new(header);
    for row in &table.rows[1..] {
        let mut cells = vec![row.label.to_string()];
        for (i, (metric, _)) in table.columns.iter().enumerate() {
            let paper = base.values[i] / row.values[i];
            cells.push(match (find(base.label), find(row.label)) {
                (Some(b), Some(f)) => {
                    let (b, f) = (input.stats(b, *metric), input.stats(f, *metric));
                    if b.count == 0 || f.count == 0 {
                        format!("— ({paper:.2}×)")
                    } else {
                        format!(
                            "{:.2}× / {:.2}× ({paper:.2}×)",
                            b.mean / f.mean,
                            b.median / f.median
                        )
                    }
                }
                _ => format!("— ({paper:.2}×)"),
            });
        }
        t.row(cells);
    }
    let _ = writeln!(out, "{t}");
}

fn window_table(out: &mut String, input: &ReportInput<'_>, paper: &Paper) {
    if paper.windows.is_empty() {
        return;
    }
    let mut header = vec!["position error in window, m".to_string()];
    for (name, w) in paper.windows {
        header.push(format!("{name} [{}, {}] s: max", w.start, w.end));
        header.push("added".to_string());
    }
    let mut t = TextTable::new(header);
    for o in input.outcomes {
        let mut row = vec![o.label.to_string()];
        for i in 0..paper.windows.len() {
            row.push(format!("{:.2}", MeanStd::of(o.window(i).map(|e| e.max))));
            row.push(format!("{:.2}", MeanStd::of(o.window(i).map(|e| e.growth))));
        }
        t.row(row);
    }
    let _ = writeln!(out, "{t}");
    let _ = writeln!(
        out,
        "   max: largest position error (3-D) in the window; added: largest change of the position error vector since the window began\n"
    );
}

fn failures(out: &mut String, outcomes: &[FilterOutcome], plan: &MonteCarloPlan) {
    for o in outcomes {
        let failed: Vec<_> = o.failures().collect();
        if failed.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            "{} failed in {} of {} runs (left out of its statistics):",
            o.label,
            failed.len(),
            o.runs.len()
        );
        for (run, error) in failed.iter().take(5) {
            let seed = plan.seed.wrapping_add(*run as u64);
            let _ = writeln!(out, "   run {run} (seed {seed}): {error}");
        }
        if failed.len() > 5 {
            let _ = writeln!(out, "   … and {} more", failed.len() - 5);
        }
    }
}

/// Writes the summary CSV: one row per filter and metric.
///
/// Columns: `scenario, filter, metric, mean, std, median, runs_ok,
/// runs_failed, paper` (`paper` empty where the paper gives no value;
/// mean, std and median empty when no run completed).
///
/// # Errors
/// [`Error::Io`] if the file cannot be written.
pub fn write_summary_csv(path: &Path, input: &ReportInput<'_>) -> Result<(), Error> {
    let io = |e: csv::Error| Error::Failed(format!("{}: {e}", path.display()));
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    w.write_record([
        "scenario",
        "filter",
        "metric",
        "mean",
        "std",
        "median",
        "runs_ok",
        "runs_failed",
        "paper",
        "runs_with_epochs",
    ])
    .map_err(io)?;
    let axes = input.axes();
    let table = input.paper.and_then(|p| p.table.as_ref());
    for o in input.outcomes {
        for metric in Metric::ALL {
            let stats = input.stats(o, metric);
            let paper = table
                .and_then(|t| {
                    let row = t.rows.iter().find(|r| r.label == o.label)?;
                    let col = t.columns.iter().position(|(m, _)| *m == metric)?;
                    row.values.get(col).copied()
                })
                .map(|v| v.to_string())
                .unwrap_or_default();
            w.write_record([
                input.scenario.name.clone(),
                o.label.to_string(),
                metric.name(axes),
                known(stats.mean),
                known(stats.std),
                known(stats.median),
                o.completed().count().to_string(),
                o.failures().count().to_string(),
                paper,
                stats.count.to_string(),
            ])
            .map_err(io)?;
        }
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// A statistic for a CSV cell: empty when it is not a number (no values).
fn known(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        v.to_string()
    }
}

/// Writes the per-run CSV: one row per filter and run.
///
/// Columns: `scenario, filter, run, seed, status` (`ok` or `failed`),
/// `failure` (why, empty when ok), then every [`Metric`] of the run, then
/// the health monitor's `health_alarms` (alarms raised), `first_alarm_s`
/// (empty without one) and `diverged` (1: an alarm still raised at the
/// end), and for 16-state filters the final `odometer_scale` estimate, its
/// `odometer_scale_sigma` and the simulated `odometer_scale_truth` — all
/// empty when the run failed.
///
/// # Errors
/// [`Error::Io`] if the file cannot be written.
pub fn write_runs_csv(path: &Path, input: &ReportInput<'_>) -> Result<(), Error> {
    let io = |e: csv::Error| Error::Failed(format!("{}: {e}", path.display()));
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    let axes = input.axes();
    let mut header: Vec<String> = ["scenario", "filter", "run", "seed", "status", "failure"]
        .map(String::from)
        .to_vec();
    header.extend(Metric::ALL.iter().map(|m| m.name(axes)));
    header.extend(
        [
            "health_alarms",
            "first_alarm_s",
            "diverged",
            "odometer_scale",
            "odometer_scale_sigma",
            "odometer_scale_truth",
        ]
        .iter()
        .map(|s| s.to_string()),
    );
    w.write_record(&header).map_err(io)?;
    for o in input.outcomes {
        for (run, outcome) in o.runs.iter().enumerate() {
            let seed = input.plan.seed.wrapping_add(run as u64);
            let mut row = vec![
                input.scenario.name.clone(),
                o.label.to_string(),
                run.to_string(),
                seed.to_string(),
            ];
            match outcome {
                Ok((summary, _)) => {
                    row.extend(["ok".to_string(), String::new()]);
                    // No aiding epoch: no RMS, an empty cell (never 0).
                    row.extend(Metric::ALL.iter().map(|m| {
                        if summary.rms_epochs > 0 {
                            m.value(summary).to_string()
                        } else {
                            String::new()
                        }
                    }));
                    let h = &summary.health;
                    row.push(h.alarms.to_string());
                    row.push(h.first_alarm.map_or(String::new(), |e| e.time.to_string()));
                    row.push(u8::from(h.diverged()).to_string());
                    match summary.odometer_scale {
                        Some(k) => {
                            row.extend([k.estimate, k.sigma, k.truth].map(|v| v.to_string()))
                        }
                        None => row.extend([String::new(), String::new(), String::new()]),
                    }
                }
                Err(e) => {
                    row.extend(["failed".to_string(), e.to_string()]);
                    row.extend(Metric::ALL.iter().map(|_| String::new()));
                    row.extend((0..6).map(|_| String::new()));
                }
            }
            w.write_record(&row).map_err(io)?;
        }
    }
    w.flush().map_err(|e| Error::io(path, e))
}
