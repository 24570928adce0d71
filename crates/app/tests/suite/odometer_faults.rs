//! Paper 003's odometer faults (wheel spin 1.5× at 600 s and a skid 0.25×
//! at 1600 s, 3 s each; slipping 1–1.3× during 2000–2100 s) on scenario
//! 003, with no processing, the max-threshold baseline (1 m/s) and the
//! fuzzy adaptive processing, against the same run without faults.
//!
//! What the paper reports (figures only): unprocessed faults add a large
//! error at the spin and a growing one while slipping; the fuzzy filter
//! suppresses both. Asserted: unprocessed faults ruin dead reckoning
//! (hundreds of metres); both processings remove the spin and skid (the
//! error just after them stays within 3 m of the fault-free run); the
//! fuzzy processing rejects exactly the spin and skid readings, rescales
//! the slipping ones instead of dropping them, and keeps the whole run
//! within 0.1 % of the distance, while the threshold method, which uses
//! slipping readings below its threshold and isolates the others, does not.

use crate::odometer_run::{run_003, DrRun, Processing};
use kestrel::nav::odometer::{FuzzyOdometer, MaxThreshold};

fn summary(name: &str, r: &DrRun) {
    eprintln!(
        "{name:>9}: error at 590 s {:6.2} m, 700 s {:6.2}, 1700 s {:6.2}, 1990 s {:6.2}, \
         2200 s {:6.2}, end {:6.2}, worst {:7.2}; rejected {} (faulty {} of {})",
        r.error_at(590.0),
        r.error_at(700.0),
        r.error_at(1700.0),
        r.error_at(1990.0),
        r.error_at(2200.0),
        r.errors.last().unwrap().1,
        r.worst,
        r.rejected,
        r.rejected_faulty,
        r.faulty
    );
}

#[test]
fn fault_processing_suppresses_the_odometer_faults() {
    let clean = run_003(false, Processing::Plain);
    let plain = run_003(true, Processing::Plain);
    let threshold = run_003(true, Processing::Threshold(MaxThreshold::new(1.0)));
    let fuzzy = run_003(
        true,
        Processing::Fuzzy(Box::new(FuzzyOdometer::as_published().unwrap())),
    );
    for (name, r) in [
        ("clean", &clean),
        ("plain", &plain),
        ("threshold", &threshold),
        ("fuzzy", &fuzzy),
    ] {
        summary(name, r);
    }
    let limit = 1e-3 * clean.distance;

    // 10 Hz: 30 spin + 30 skid readings, 1000 slipping ones.
    assert_eq!(plain.faulty, 1060);
    assert!(plain.error_at(700.0) > 50.0 && plain.worst > 10.0 * limit);

    for (name, r) in [("threshold", &threshold), ("fuzzy", &fuzzy)] {
        for t in [700.0, 1700.0] {
            assert!(
                r.error_at(t) < clean.error_at(t) + 3.0,
                "{name}: {:.1} m at {t} s",
                r.error_at(t)
            );
        }
    }

    assert_eq!(fuzzy.rejected, 60, "the spin and skid readings only");
    assert_eq!(fuzzy.rejected_faulty, 60);
    assert!(
        fuzzy.worst < limit,
        "fuzzy worst {:.1} m > {limit:.1} m",
        fuzzy.worst
    );
    assert!(
        threshold.rejected_faulty > 500,
        "the threshold isolates most slipping readings"
    );
    assert!(threshold.worst > limit && threshold.worst > 4.0 * fuzzy.worst);
}
