//! A paper's verdict computed from the run's own comparisons by a stated
//! rule, naming the seeds and variants it rests on.
//!
//! The comparisons are per-seed ratios of horizontal RMS, the baseline's ÷
//! the favoured filter's, summarised by their quartiles. One comparison
//! reads **better** when its first quartile exceeds 1 (the favoured filter
//! ahead on at least three seeds of four), **worse** when its third
//! quartile is below 1, and **no difference** otherwise: a rule on the
//! seeds' spread, not on a mean a single run can pull.
//!
//! The verdict: **not reproduced** unless the favoured filter reads better
//! than the paper's baseline in the headline variant; then **reproduced**
//! when it also reads better than every competent baseline (protected or
//! tuned, [`Variant::competent`](crate::scenario::Variant::competent)) or
//! when none was studied, **not reproduced against a competent baseline**
//! when a competent baseline reads better than it, and **partly
//! reproduced** otherwise (no difference from some competent baseline).

use std::fmt::{self, Write as _};
use std::ops::Range;

use super::monte_carlo::FilterOutcome;
use super::sensitivity::StudyRow;
use super::stats::Quartiles;

/// How the favoured filter compares with a baseline over seeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Comparison {
    /// First quartile of baseline ÷ favoured above 1.
    Better,
    /// Third quartile below 1.
    Worse,
    /// The interquartile range contains 1.
    NoDifference,
}

impl Comparison {
    /// The reading of the quartiles of the per-seed ratio baseline ÷
    /// favoured.
    ///
    /// ```
    /// use kestrel_app::reproduce::{Comparison, Quartiles};
    /// let q = |q1, q3| Quartiles { q1, median: (q1 + q3) / 2.0, q3, count: 10 };
    /// assert_eq!(Comparison::of(&q(1.05, 1.4)), Comparison::Better);
    /// assert_eq!(Comparison::of(&q(0.99, 1.29)), Comparison::NoDifference);
    /// assert_eq!(Comparison::of(&q(0.8, 0.99)), Comparison::Worse);
    /// ```
    pub fn of(q: &Quartiles) -> Self {
        if q.q1 > 1.0 {
            Self::Better
        } else if q.q3 < 1.0 {
            Self::Worse
        } else {
            Self::NoDifference
        }
    }
}

impl fmt::Display for Comparison {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Better => "better",
            Self::Worse => "worse",
            Self::NoDifference => "no difference",
        })
    }
}

/// One comparison a verdict rests on.
#[derive(Clone, Debug, PartialEq)]
pub struct Evidence {
    /// The variant (or `headline runs`).
    pub variant: String,
    /// The baseline's label.
    pub baseline: String,
    /// Whether the baseline is a competent one.
    pub competent: bool,
    /// Whether it is the headline comparison against the paper's baseline.
    pub headline: bool,
    /// Quartiles of the per-seed horizontal ratio baseline ÷ favoured.
    pub ratio: Quartiles,
}

impl Evidence {
    /// The comparison's [`Comparison`].
    pub fn reading(&self) -> Comparison {
        Comparison::of(&self.ratio)
    }
}

/// The verdict's word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Better than the paper's baseline and every competent one.
    Reproduced,
    /// Better than the paper's baseline, no different from a competent one.
    PartlyReproduced,
    /// Better than the paper's baseline, worse than a competent one.
    NotAgainstCompetent,
    /// Not better than the paper's baseline in the headline variant (or no
    /// such comparison).
    NotReproduced,
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Reproduced => "reproduced",
            Self::PartlyReproduced => "partly reproduced",
            Self::NotAgainstCompetent => "not reproduced against a competent baseline",
            Self::NotReproduced => "not reproduced",
        })
    }
}

/// Where a verdict's comparisons come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Basis {
    /// The sensitivity study: `runs` seeds per variant from `from`.
    Study {
        /// First seed.
        from: u64,
        /// Seeds per variant.
        runs: usize,
    },
    /// The headline runs only: their seeds, and why (the study skipped, or
    /// none for this paper).
    Headline {
        /// The headline runs' seeds.
        seeds: Range<u64>,
        /// Why there is no study, e.g. `"the study was skipped"`.
        why: &'static str,
    },
}

/// A computed verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The word.
    pub outcome: Outcome,
    /// Where the comparisons come from.
    pub basis: Basis,
    /// The comparisons, the headline first.
    pub evidence: Vec<Evidence>,
}

/// The rule of the module documentation on `evidence`.
pub fn decide(evidence: &[Evidence]) -> Outcome {
    let headline = evidence.iter().find(|e| e.headline);
    if headline.map(Evidence::reading) != Some(Comparison::Better) {
        return Outcome::NotReproduced;
    }
    let competent: Vec<Comparison> = evidence
        .iter()
        .filter(|e| e.competent)
        .map(Evidence::reading)
        .collect();
    if competent.contains(&Comparison::Worse) {
        Outcome::NotAgainstCompetent
    } else if competent.contains(&Comparison::NoDifference) {
        Outcome::PartlyReproduced
    } else {
        Outcome::Reproduced
    }
}

/// The verdict from a study's rows: the headline row, the competent rows;
/// `None` without a headline row.
pub fn from_study(rows: &[StudyRow], from: u64) -> Option<Verdict> {
    let evidence: Vec<Evidence> = rows
        .iter()
        .filter(|r| r.headline || r.competent)
        .filter_map(|r| {
            Some(Evidence {
                variant: r.variant.clone(),
                baseline: r.baseline.to_string(),
                competent: r.competent,
                headline: r.headline,
                ratio: r.ratios[0]?,
            })
        })
        .collect();
    if !evidence.iter().any(|e| e.headline) {
        return None;
    }
    Some(Verdict {
        outcome: decide(&evidence),
        basis: Basis::Study {
            from,
            runs: rows.first().map_or(0, |r| r.seeds),
        },
        evidence,
    })
}

/// Quartiles of the per-run horizontal ratio `base` ÷ `fav` over the runs
/// both completed.
fn ratio(base: &FilterOutcome, fav: &FilterOutcome) -> Option<Quartiles> {
    let r: Vec<f64> = base
        .runs
        .iter()
        .zip(&fav.runs)
        .filter_map(|(b, f)| {
            let (b, f) = (&b.as_ref().ok()?.0, &f.as_ref().ok()?.0);
            Some(b.horizontal_rms() / f.horizontal_rms())
        })
        .collect();
    Quartiles::of(&r)
}

/// The verdict from the headline runs only: the scenario's first filter
/// (the paper's baseline) against its last (`paper_filters` outcomes
/// first), and every tuned outcome after them as a competent baseline,
/// against the tuned favoured filter when the tuned set ends with it,
/// else against the scenario's. `None` with fewer than two filters.
pub fn from_headline(
    outcomes: &[FilterOutcome],
    paper_filters: usize,
    seeds: Range<u64>,
    why: &'static str,
) -> Option<Verdict> {
    if paper_filters < 2 || outcomes.len() < paper_filters {
        return None;
    }
    let (paper, tuned) = outcomes.split_at(paper_filters);
    let favoured = &paper[paper_filters - 1];
    let mut evidence = vec![Evidence {
        variant: "headline runs".to_string(),
        baseline: paper[0].label.clone(),
        competent: false,
        headline: true,
        ratio: ratio(&paper[0], favoured)?,
    }];
    let tuned_favoured = tuned
        .last()
        .filter(|t| t.label == format!("{} (tuned)", favoured.label));
    let (baselines, against) = match tuned_favoured {
        Some(t) => (&tuned[..tuned.len() - 1], t),
        None => (tuned, favoured),
    };
    evidence.extend(baselines.iter().filter_map(|b| {
        Some(Evidence {
            variant: "headline runs".to_string(),
            baseline: b.label.clone(),
            competent: true,
            headline: false,
            ratio: ratio(b, against)?,
        })
    }));
    Some(Verdict {
        outcome: decide(&evidence),
        basis: Basis::Headline { seeds, why },
        evidence,
    })
}

impl Verdict {
    /// The report's lines: the verdict with what it rests on, and the rule.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let basis = match &self.basis {
            Basis::Study { from, runs } => format!(
                "the sensitivity study, seeds {from}–{}",
                from + (*runs as u64).saturating_sub(1)
            ),
            Basis::Headline { seeds, why } => format!(
                "the headline runs only, seeds {}–{} ({why})",
                seeds.start,
                seeds.end.saturating_sub(1)
            ),
        };
        let _ = writeln!(out, "verdict (computed from {basis}): {}", self.outcome);
        for e in &self.evidence {
            let role = if e.headline {
                "the paper's baseline"
            } else {
                "a competent baseline"
            };
            let _ = writeln!(
                out,
                "   {} vs {role} {} ({}): horizontal ratio {:.2} → {}",
                e.variant,
                e.baseline,
                e.ratio.count,
                e.ratio,
                e.reading()
            );
        }
        if !self.evidence.iter().any(|e| e.competent) {
            let _ = writeln!(out, "   no competent baseline was compared");
        }
        let _ = writeln!(
            out,
            "   rule: better when the first quartile of the per-seed ratio exceeds 1, worse when the third is below 1; reproduced when better than the paper's baseline and every competent baseline, partly when no different from one, not reproduced against a competent baseline when worse than one"
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(q1: f64, q3: f64) -> Quartiles {
        Quartiles {
            q1,
            median: (q1 + q3) / 2.0,
            q3,
            count: 10,
        }
    }

    fn e(headline: bool, competent: bool, ratio: Quartiles) -> Evidence {
        Evidence {
            variant: "v".to_string(),
            baseline: "b".to_string(),
            competent,
            headline,
            ratio,
        }
    }

    #[test]
    fn the_rule_reads_each_outcome() {
        let better = e(true, false, q(1.2, 1.5));
        assert_eq!(decide(std::slice::from_ref(&better)), Outcome::Reproduced);
        assert_eq!(
            decide(&[better.clone(), e(false, true, q(1.01, 2.0))]),
            Outcome::Reproduced
        );
        assert_eq!(
            decide(&[better.clone(), e(false, true, q(0.99, 1.29))]),
            Outcome::PartlyReproduced
        );
        assert_eq!(
            decide(&[
                better.clone(),
                e(false, true, q(0.99, 1.29)),
                e(false, true, q(0.8, 0.95))
            ]),
            Outcome::NotAgainstCompetent
        );
        // The paper's baseline decides first.
        assert_eq!(
            decide(&[e(true, false, q(0.9, 1.5)), e(false, true, q(2.0, 3.0))]),
            Outcome::NotReproduced
        );
        assert_eq!(decide(&[]), Outcome::NotReproduced);
        // Exactly 1 is no difference on either side.
        assert_eq!(Comparison::of(&q(1.0, 1.0)), Comparison::NoDifference);
    }

    #[test]
    fn the_text_names_its_basis() {
        let v = Verdict {
            outcome: Outcome::PartlyReproduced,
            basis: Basis::Headline {
                seeds: 0..20,
                why: "the study was skipped",
            },
            evidence: vec![e(true, false, q(1.2, 1.5))],
        };
        let t = v.text();
        assert!(
            t.starts_with("verdict (computed from the headline runs only, seeds 0–19 (the study was skipped)): partly reproduced"),
            "{t}"
        );
        assert!(t.contains("no competent baseline"), "{t}");
        let s = Verdict {
            basis: Basis::Study {
                from: 2000,
                runs: 10,
            },
            ..v
        };
        assert!(s.text().contains("the sensitivity study, seeds 2000–2009"));
    }
}
