//! Tick labels.

/// Labels for a linear axis from `lo` to `hi`: as many decimals as the span
/// needs, trailing zeros dropped, the rounding noise of a tick at zero
/// (`-1.4e-17`) shown as `0`, an exponent for very large or very fine
/// ranges.
pub(crate) fn linear_ticks(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let span = (hi - lo).abs();
    let big = lo.abs().max(hi.abs());
    move |v: &f64| {
        if v.abs() <= span * 1e-9 {
            "0".into()
        } else if big >= 1e6 || span < 1e-4 || !span.is_finite() {
            exponent(*v)
        } else {
            let decimals = (3 - span.log10().floor() as i32).clamp(0, 12) as usize;
            trim(format!("{v:.decimals$}"))
        }
    }
}

/// A value on its own (a log-axis tick, a peak), without the span of an
/// axis to go by: five significant digits at most, an exponent when very
/// small or large.
pub(crate) fn compact(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e6).contains(&a) {
        let decimals = (4 - a.log10().floor() as i32).clamp(0, 8) as usize;
        return trim(format!("{v:.decimals$}"));
    }
    exponent(*v)
}

/// `1.25e-5` rather than `1.250e-5`.
fn exponent(v: f64) -> String {
    let s = format!("{v:.3e}");
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", trim(m.to_string())),
        None => s,
    }
}

/// Drops trailing zeros of a decimal fraction, and a `-` of a zero.
fn trim(s: String) -> String {
    let t = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s.as_str()
    };
    if t.trim_start_matches('-').chars().all(|c| c == '0') {
        "0".into()
    } else {
        t.into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_are_tidy() {
        let t = linear_ticks(-0.1, 0.15);
        assert_eq!(t(&-1.4e-17), "0");
        assert_eq!(t(&0.05), "0.05");
        assert_eq!(t(&-0.1), "-0.1");
        assert_eq!(t(&0.30000000000000004), "0.3");
        let t = linear_ticks(0.0, 3600.0);
        assert_eq!(t(&500.0), "500");
        assert_eq!(t(&3599.99999999), "3600");
        let t = linear_ticks(0.0, 2.0e6);
        assert_eq!(t(&1.25e6), "1.25e6");
        let t = linear_ticks(1e-6, 3e-6);
        assert_eq!(t(&2e-6), "2e-6");
    }

    #[test]
    fn compacts_are_tidy() {
        assert_eq!(compact(&100.0), "100");
        assert_eq!(compact(&0.01), "0.01");
        assert_eq!(compact(&2.5e7), "2.5e7");
        assert_eq!(compact(&1e-5), "1e-5");
    }
}
