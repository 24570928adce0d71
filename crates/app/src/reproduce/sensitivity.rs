//! The sensitivity study: the favoured filter's improvement over the
//! baseline across a scenario's free choices ([`variants`]), per seed, as
//! median and interquartile range.

use std::fmt::Write as _;
use std::path::Path;

use crate::experiment::{run_together, RunOptions, RunSummary};
use crate::scenario::{variants, FilterKind, Scenario, Variant, STUDY_SEEDS_FROM};
use rayon::prelude::*;

use super::monte_carlo::worker_pool;
use super::stats::Quartiles;
use super::table::TextTable;
use crate::transaction::Cancel;
use crate::Error;

/// The ratios a study reports: the baseline's RMS ÷ the favoured filter's.
pub const STUDY_METRICS: [&str; 3] = ["horizontal position", "vertical position", "3-D velocity"];

/// One variant's result.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyRow {
    /// The scenario ("000" …).
    pub paper: String,
    /// What the variant changes.
    pub variant: String,
    /// Whether it is the built-in scenario's choice.
    pub headline: bool,
    /// Whether its baseline is a competent one on the headline's fault
    /// ([`Variant::competent`](crate::scenario::Variant::competent)).
    pub competent: bool,
    /// The baseline's label.
    pub baseline: &'static str,
    /// The favoured filter's label.
    pub favoured: &'static str,
    /// Per [`STUDY_METRICS`]: the quartiles of the per-seed ratio over the
    /// seeds where both filters completed (`None` if there are none).
    pub ratios: [Option<Quartiles>; 3],
    /// Per [`STUDY_METRICS`]: the seeds (both filters completed) where the
    /// favoured filter was worse than the baseline (ratio below 1).
    pub worse: [usize; 3],
    /// Seeds run.
    pub seeds: usize,
    /// Runs that failed: (baseline, favoured).
    pub failed: (usize, usize),
    /// Runs the health monitor found diverged at their end (its alarm
    /// still raised): (baseline, favoured).
    pub diverged: (usize, usize),
}

/// How a study is run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyPlan {
    /// Seeds per variant, from [`STUDY_SEEDS_FROM`].
    pub runs: usize,
    /// Worker threads (0: one per core).
    pub threads: usize,
    /// Simulate only the first seconds of each run.
    pub duration: Option<f64>,
}

/// The three figures a study compares from one run, and whether the run
/// ended diverged.
type Figures = ([f64; 3], bool);

/// The [`Figures`] of run `s`.
fn figures(s: &RunSummary) -> Figures {
    (
        [
            s.horizontal_rms(),
            s.rms_position[2].abs(),
            s.velocity_rms(),
        ],
        s.health.diverged(),
    )
}

/// Runs the sensitivity study of built-in scenario `name` (no rows for a
/// scenario without [`variants`]). A (set-up, filter) pair shared by
/// several variants is run once per seed, and the filters of one set-up
/// share one simulation per seed.
///
/// # Errors
/// [`Error::Failed`] if the worker threads cannot start;
/// [`Error::Cancelled`] once `cancel` is set (no run starts after that).
pub fn run_study(name: &str, plan: &StudyPlan, cancel: &Cancel) -> Result<Vec<StudyRow>, Error> {
    let variants = variants(name);
    if variants.is_empty() || plan.runs == 0 {
        return Ok(Vec::new());
    }
    // The unique set-ups (the scenario without its filter list), each with
    // the filters to run on it; a variant's pair is (set-up, filter) twice.
    let mut setups: Vec<(Scenario, Vec<FilterKind>)> = Vec::new();
    let mut index = |v: &Variant, k: FilterKind| -> (usize, usize) {
        let mut s = v.scenario.clone();
        s.filters.clear();
        let g = setups
            .iter()
            .position(|(gs, _)| *gs == s)
            .unwrap_or_else(|| {
                setups.push((s, Vec::new()));
                setups.len() - 1
            });
        let kinds = &mut setups[g].1;
        let i = kinds.iter().position(|x| *x == k).unwrap_or_else(|| {
            kinds.push(k);
            kinds.len() - 1
        });
        (g, i)
    };
    let pairs: Vec<((usize, usize), (usize, usize))> = variants
        .iter()
        .map(|v| {
            let first = v.scenario.filters[0];
            let last = *v.scenario.filters.last().unwrap_or(&first);
            (index(v, first), index(v, last))
        })
        .collect();
    let pool = worker_pool(plan.threads)?;
    let work: Vec<(usize, u64)> = (0..setups.len())
        .flat_map(|g| (0..plan.runs as u64).map(move |r| (g, STUDY_SEEDS_FROM + r)))
        .collect();
    let options = RunOptions {
        duration: plan.duration,
        ..RunOptions::default()
    }
    .without_records();
    // One job per (set-up, seed): its filters share one simulation.
    let results: Vec<Vec<Option<Figures>>> = pool.install(|| {
        work.par_iter()
            .map(|&(g, seed)| {
                let (s, kinds) = &setups[g];
                if cancel.is_cancelled() {
                    return vec![None; kinds.len()];
                }
                match run_together(s, kinds, seed, &options, |_, _| {}) {
                    Ok(runs) => runs.iter().map(|r| r.as_ref().ok().map(figures)).collect(),
                    Err(_) => vec![None; kinds.len()],
                }
            })
            .collect()
    });
    cancel.check()?;
    let of = |(g, i): (usize, usize)| -> Vec<Option<Figures>> {
        results[g * plan.runs..(g + 1) * plan.runs]
            .iter()
            .map(|run| run[i])
            .collect()
    };
    Ok(variants
        .iter()
        .zip(pairs)
        .map(|(v, (b, f))| {
            let (base, fav) = (of(b), of(f));
            let per_seed = |m: usize| -> Vec<f64> {
                base.iter()
                    .zip(&fav)
                    .filter_map(|(x, y)| Some(x.as_ref()?.0[m] / y.as_ref()?.0[m]))
                    .collect()
            };
            let ratios = core::array::from_fn(|m| Quartiles::of(&per_seed(m)));
            let worse = core::array::from_fn(|m| per_seed(m).iter().filter(|&&r| r < 1.0).count());
            let failed = |runs: &[Option<Figures>]| runs.iter().filter(|r| r.is_none()).count();
            let diverged = |runs: &[Option<Figures>]| {
                runs.iter().filter(|r| r.is_some_and(|(_, d)| d)).count()
            };
            StudyRow {
                paper: name.to_string(),
                variant: v.name.clone(),
                headline: v.headline,
                competent: v.competent,
                baseline: setups[b.0].1[b.1].label(),
                favoured: setups[f.0].1[f.1].label(),
                ratios,
                worse,
                seeds: plan.runs,
                failed: (failed(&base), failed(&fav)),
                diverged: (diverged(&base), diverged(&fav)),
            }
        })
        .collect())
}

/// The study as a text table.
pub fn study_table(rows: &[StudyRow]) -> String {
    let Some(first) = rows.first() else {
        return String::new();
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "sensitivity: baseline RMS ÷ {} RMS per seed (> 1: {} better), median [interquartile range] over seeds {}–{}",
        first.favoured,
        first.favoured,
        STUDY_SEEDS_FROM,
        STUDY_SEEDS_FROM + first.seeds as u64 - 1
    );
    let mut header = vec![
        "variant (* = as in the reproduction)".to_string(),
        "baseline".to_string(),
    ];
    header.extend(STUDY_METRICS.iter().map(|m| m.to_string()));
    header.push("worse (hor.)".to_string());
    header.push("failed base/fav".to_string());
    header.push("diverged base/fav".to_string());
    let mut t = TextTable::new(header);
    for r in rows {
        let mut cells = vec![
            format!("{}{}", if r.headline { "* " } else { "" }, r.variant),
            r.baseline.to_string(),
        ];
        cells.extend(r.ratios.iter().map(|q| match q {
            Some(q) => format!("{q:.2}"),
            None => "—".to_string(),
        }));
        cells.push(format!("{} of {}", r.worse[0], r.seeds));
        cells.push(format!("{}/{} of {}", r.failed.0, r.failed.1, r.seeds));
        cells.push(format!("{}/{}", r.diverged.0, r.diverged.1));
        t.row(cells);
    }
    let _ = writeln!(out, "{t}");
    let _ = writeln!(
        out,
        "   worse: seeds where the favoured filter's horizontal RMS exceeded the baseline's; diverged: runs whose health alarm was still raised at the end\n"
    );
    out
}

/// The study's disclosure line, computed from its rows: the failed runs,
/// and each variant where the favoured filter was worse than its baseline
/// (horizontal RMS) on some seeds, with the count; `None` without rows.
///
/// For a robust filter these are the runs where it followed a fault the
/// baseline did not (002's lock-on onto a burst).
pub fn study_disclosure(rows: &[StudyRow]) -> Option<String> {
    let first = rows.first()?;
    let seeds = format!(
        "seeds {}–{}",
        STUDY_SEEDS_FROM,
        STUDY_SEEDS_FROM + first.seeds as u64 - 1
    );
    let failed: usize = rows.iter().map(|r| r.failed.0 + r.failed.1).sum();
    let runs = rows.len() * 2 * first.seeds;
    let worse: Vec<String> = rows
        .iter()
        .filter(|r| r.worse[0] > 0)
        .map(|r| {
            format!(
                "{} vs {} {} of {}",
                r.variant, r.baseline, r.worse[0], r.seeds
            )
        })
        .collect();
    let worse = if worse.is_empty() {
        format!("in no variant was {} worse on any seed", first.favoured)
    } else {
        format!(
            "{} worse than the baseline (horizontal RMS) in {}",
            first.favoured,
            worse.join("; ")
        )
    };
    Some(format!(
        "study, {seeds} (computed): {failed} failed of {runs} runs compared (a run shared by variants counted in each); {worse}"
    ))
}

/// Writes the study as CSV: one row per paper, variant and metric.
///
/// Columns: `paper, variant, headline, baseline, favoured, metric, q1,
/// median, q3, pairs, seeds, baseline_failed, favoured_failed, worse,
/// baseline_diverged, favoured_diverged` (the quartiles empty when no seed
/// completed with both filters; `worse`: the seeds where the favoured
/// filter was worse in the metric).
///
/// # Errors
/// [`Error::Failed`] if the file cannot be written.
pub fn write_study_csv(path: &Path, rows: &[StudyRow]) -> Result<(), Error> {
    let io = |e: csv::Error| Error::Failed(format!("{}: {e}", path.display()));
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    w.write_record([
        "paper",
        "variant",
        "headline",
        "baseline",
        "favoured",
        "metric",
        "q1",
        "median",
        "q3",
        "pairs",
        "seeds",
        "baseline_failed",
        "favoured_failed",
        "worse",
        "baseline_diverged",
        "favoured_diverged",
    ])
    .map_err(io)?;
    for r in rows {
        for (k, (metric, q)) in STUDY_METRICS.iter().zip(&r.ratios).enumerate() {
            let (q1, med, q3, n) = match q {
                Some(q) => (
                    q.q1.to_string(),
                    q.median.to_string(),
                    q.q3.to_string(),
                    q.count,
                ),
                None => (String::new(), String::new(), String::new(), 0),
            };
            w.write_record([
                r.paper.clone(),
                r.variant.clone(),
                r.headline.to_string(),
                r.baseline.to_string(),
                r.favoured.to_string(),
                metric.to_string(),
                q1,
                med,
                q3,
                n.to_string(),
                r.seeds.to_string(),
                r.failed.0.to_string(),
                r.failed.1.to_string(),
                r.worse[k].to_string(),
                r.diverged.0.to_string(),
                r.diverged.1.to_string(),
            ])
            .map_err(io)?;
        }
    }
    w.flush().map_err(|e| Error::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(variant: &str, worse: usize, failed: (usize, usize)) -> StudyRow {
        let q = Quartiles::of(&[1.0, 2.0]);
        StudyRow {
            paper: "002".to_string(),
            variant: variant.to_string(),
            headline: false,
            competent: false,
            baseline: "KF",
            favoured: "ICT-EREKF",
            ratios: [q, q, q],
            worse: [worse, 0, 0],
            seeds: 20,
            failed,
            diverged: (0, 0),
        }
    }

    #[test]
    fn the_disclosure_counts_failed_runs_and_worse_seeds() {
        assert_eq!(study_disclosure(&[]), None);
        let d = study_disclosure(&[row("capped", 0, (0, 0)), row("doubled", 2, (1, 0))]).unwrap();
        assert_eq!(
            d,
            "study, seeds 2000–2019 (computed): 1 failed of 80 runs compared (a run shared by variants counted in each); ICT-EREKF worse than the baseline (horizontal RMS) in doubled vs KF 2 of 20"
        );
        let d = study_disclosure(&[row("capped", 0, (0, 0))]).unwrap();
        assert!(d.ends_with("0 failed of 40 runs compared (a run shared by variants counted in each); in no variant was ICT-EREKF worse on any seed"));
    }
}
