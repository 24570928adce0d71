//! The filter-health monitor ([`ConsistencyMonitor`]): its bounds by hand,
//! the window logic, its false-alarm rate on samples of the distribution
//! it assumes (independent χ²(m) for the NIS; correlated for the NEES),
//! its detection of a statistic that grows, and no allocation.

use kestrel_adaptive::{chi_square_quantile, ConsistencyMonitor, MonitorEvent, SampleDependence};
use kestrel_testkit::heap_calls;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{ChiSquared, Distribution, StandardNormal};

#[test]
fn the_bounds_are_the_chi_square_quantiles() {
    // Independent: the window sum of 20 χ²(6) is χ²(120); its 0.999
    // quantile is 173.617 (tables: 173.62).
    let m = ConsistencyMonitor::<f64>::innovations(6).unwrap();
    assert!((m.bound() - 173.617).abs() < 1e-3, "{}", m.bound());
    assert_eq!((m.window(), m.windows(), m.dof()), (20, 3, 6));
    // Correlated, α = 10⁻⁴: 20 × χ²₀.₉₉₉₉(3) = 20 × 21.108.
    let e = ConsistencyMonitor::<f64>::errors(3).unwrap();
    assert!((e.bound() - 20.0 * 21.1075).abs() < 1e-2, "{}", e.bound());
    // Two samples of χ²(1) at 5 %: χ²₀.₉₅(2) = −2 ln 0.05 = 5.9915.
    let s = ConsistencyMonitor::<f64>::new(1, 2, 1, 0.05, SampleDependence::Independent).unwrap();
    assert!((s.bound() - 5.991_464_547).abs() < 1e-6);
    assert!(ConsistencyMonitor::<f64>::innovations(0).is_err());
    assert!(ConsistencyMonitor::<f64>::new(3, 20, 0, 1e-3, SampleDependence::Correlated).is_err());
    assert!(ConsistencyMonitor::<f64>::new(3, 20, 3, 1.0, SampleDependence::Correlated).is_err());
}

#[test]
fn three_failing_windows_in_a_row_raise_the_alarm() {
    let mut m = ConsistencyMonitor::<f64>::innovations(3).unwrap();
    let bad = m.bound(); // a window of 20 × bound/20 … is exactly the bound: passes
    let feed = |m: &mut ConsistencyMonitor<f64>, v: f64, n: usize| -> Vec<MonitorEvent<f64>> {
        (0..n).filter_map(|_| m.push(v)).collect()
    };
    // Exactly at the bound passes (the test is "exceeds").
    assert!(feed(&mut m, bad / 20.0, 60).is_empty());
    // Two failing windows, one passing, two failing: no alarm.
    let over = 2.0 * bad / 20.0;
    assert!(feed(&mut m, over, 40).is_empty());
    assert!(feed(&mut m, 1.0, 20).is_empty());
    assert!(feed(&mut m, over, 40).is_empty());
    assert!(!m.alarm());
    // The third failing window in a row: the alarm, at its last sample,
    // with the window's mean per degree of freedom.
    let events = feed(&mut m, over, 20);
    let [MonitorEvent::Alarm { level }] = events[..] else {
        panic!("{events:?}");
    };
    assert!((level - over / 3.0).abs() < 1e-12 * over);
    // Raised once: more failing windows say nothing new.
    assert!(feed(&mut m, over, 100).is_empty());
    // Two passing windows are not enough to recover; the third is.
    assert!(feed(&mut m, 1.0, 40).is_empty());
    assert_eq!(feed(&mut m, 1.0, 20), [MonitorEvent::Recovered]);
    assert!(!m.alarm());
    // A NaN fails its window.
    let mut n = ConsistencyMonitor::<f64>::innovations(3).unwrap();
    for _ in 0..3 {
        n.push(f64::NAN);
        assert!(feed(&mut n, 1.0, 19).len() <= 1);
    }
    assert!(n.alarm());
}

#[test]
fn sixty_refusals_in_a_row_raise_refusing_and_accepted_windows_recover() {
    let mut m = ConsistencyMonitor::<f64>::innovations(6).unwrap();
    // 59 refusals, an accepted update, 59 refusals: no event.
    assert!((0..59).all(|_| m.refuse().is_none()));
    assert!(m.push(6.0).is_none());
    assert!((0..59).all(|_| m.refuse().is_none()));
    assert_eq!(m.refuse(), Some(MonitorEvent::Refusing));
    assert!(m.alarm());
    // The partial window of 1 sample plus 59 consistent ones = 3 windows.
    let events: Vec<_> = (0..59).filter_map(|_| m.push(6.0)).collect();
    assert_eq!(events, [MonitorEvent::Recovered]);
}

/// Windows of independent χ²(6) samples fail at the rate α = 10⁻³ (the
/// count over 200 000 windows inside its binomial 99.9 % range), and no
/// alarm comes in 4 000 000 samples (the expected number is 2·10⁻⁴).
#[test]
fn a_consistent_statistic_fails_windows_at_the_significance_and_never_alarms() {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let chi = ChiSquared::new(6.0).unwrap();
    let mut m = ConsistencyMonitor::<f64>::innovations(6).unwrap();
    let bound = m.bound();
    let (windows, mut failed, mut alarms) = (200_000, 0usize, 0usize);
    for _ in 0..windows {
        let mut sum = 0.0;
        for _ in 0..20 {
            let v: f64 = chi.sample(&mut rng);
            sum += v;
            alarms += usize::from(m.push(v).is_some());
        }
        failed += usize::from(sum > bound);
    }
    // Binomial(200 000, 10⁻³): mean 200, sd 14.1; 99.9 % within ±3.3 sd.
    assert!((153..=247).contains(&failed), "{failed} failing windows");
    assert_eq!(alarms, 0);
}

/// The NEES bound holds for correlated samples: with each window's 20
/// samples one χ²(3) draw (fully correlated, the worst case), windows fail
/// at α = 10⁻⁴; with AR(1) errors (coefficient 0.95 from one epoch to the
/// next, each epoch's NEES exactly χ²(3)) they fail less often still.
#[test]
fn the_correlated_bound_holds_for_fully_and_partly_correlated_samples() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let chi = ChiSquared::new(3.0).unwrap();
    let bound = ConsistencyMonitor::<f64>::errors(3).unwrap().bound();
    let windows = 1_000_000;
    let failed = (0..windows)
        .filter(|_| 20.0 * chi.sample(&mut rng) > bound)
        .count();
    // Binomial(10⁶, 10⁻⁴): mean 100, sd 10.
    assert!((67..=133).contains(&failed), "{failed}");
    // AR(1) errors of unit variance in 3 axes: NEES = |e|².
    let a: f64 = 0.95;
    let b = (1.0 - a * a).sqrt();
    let mut e = [0.0f64; 3];
    for x in &mut e {
        *x = StandardNormal.sample(&mut rng);
    }
    let mut partly = 0;
    for _ in 0..windows / 10 {
        let mut sum = 0.0;
        for _ in 0..20 {
            for x in &mut e {
                let n: f64 = StandardNormal.sample(&mut rng);
                *x = a * *x + b * n;
            }
            sum += e.iter().map(|x| x * x).sum::<f64>();
        }
        partly += usize::from(sum > bound);
    }
    // Of 10⁵ windows: at most the fully correlated rate (10 expected).
    assert!(partly <= 20, "{partly}");
    println!("fully correlated: {failed} of {windows} windows failed; AR(0.95): {partly}");
}

/// A statistic that grows (a filter running away: the NIS doubling every
/// 10 updates from its mean) raises the alarm within 3 windows of the
/// first failing one.
#[test]
fn a_growing_statistic_is_caught_within_three_windows() {
    let mut m = ConsistencyMonitor::<f64>::innovations(6).unwrap();
    for _ in 0..100 {
        assert!(m.push(6.0).is_none());
    }
    let mut first_failing = None;
    let mut alarm = None;
    for k in 0..400 {
        let v = 6.0 * 2f64.powf(k as f64 / 10.0);
        if first_failing.is_none() && v * 20.0 > m.bound() {
            first_failing = Some(k);
        }
        if let Some(MonitorEvent::Alarm { .. }) = m.push(v) {
            alarm = Some(k);
            break;
        }
    }
    let (f, a) = (first_failing.unwrap(), alarm.unwrap());
    assert!(a - f < 3 * 20, "first failing sample {f}, alarm {a}");
    assert!((chi_square_quantile(0.999, 120).unwrap() - m.bound()).abs() < 1e-12);
}

#[test]
fn pushing_never_allocates() {
    let mut m = ConsistencyMonitor::<f64>::innovations(6).unwrap();
    let mut f = ConsistencyMonitor::<f32>::errors(3).unwrap();
    let ((), calls) = heap_calls(|| {
        for k in 0..1000 {
            let v = if k > 500 { 1e3 } else { 6.0 };
            let _ = m.push(v);
            let _ = f.push(v as f32);
            let _ = m.refuse();
        }
    });
    assert_eq!(calls, 0);
}
