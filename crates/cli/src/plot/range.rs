//! Axis ranges: every spike of every filter stays visible, except a filter
//! that explodes, which would flatten all the others into a line.

/// How many times larger than the next-largest series a series' amplitude
/// must be to be drawn off scale. A filter three or five times worse than
/// another is a result worth seeing on one scale; beyond ten times the
/// better filters shrink to a flat line.
pub(crate) const OFF_SCALE_RATIO: f64 = 10.0;

/// Largest magnitude an axis shows: beyond it the axis arithmetic of the
/// drawing library loses all precision (values are clamped to it).
const MAGNITUDE: f64 = 1e100;

/// Smallest fraction of the largest value a log axis shows, so that a few
/// near-zero values do not squeeze the rest.
const LOG_DEPTH: f64 = 1e-6;

/// A y range and the series left out of it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct YRange {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Series (index, signed peak) drawn clipped to the range.
    pub off_scale: Vec<(usize, f64)>,
}

/// The finite (min, max) of the y values, if any.
pub(crate) fn extent(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    points
        .iter()
        .map(|p| p.1)
        .filter(|y| y.is_finite())
        .fold(None, |acc, y| match acc {
            None => Some((y, y)),
            Some((lo, hi)) => Some((lo.min(y), hi.max(y))),
        })
}

/// The range of finite x values of all `series`, widened when it is a
/// single instant, `0..1` without data.
pub(crate) fn x_range<'a>(series: impl Iterator<Item = &'a [(f64, f64)]>) -> (f64, f64) {
    let mut r: Option<(f64, f64)> = None;
    for s in series {
        for x in s.iter().map(|p| p.0).filter(|x| x.is_finite()) {
            r = Some(r.map_or((x, x), |(lo, hi)| (lo.min(x), hi.max(x))));
        }
    }
    match r {
        None => (0.0, 1.0),
        Some((lo, hi)) => {
            let (lo, hi) = (
                lo.clamp(-MAGNITUDE, MAGNITUDE),
                hi.clamp(-MAGNITUDE, MAGNITUDE),
            );
            if hi - lo > 1e-9 * lo.abs().max(hi.abs()) {
                (lo, hi)
            } else {
                let mid = 0.5 * (lo + hi);
                let d = 0.5_f64.max(1e-6 * mid.abs());
                (mid - d, mid + d)
            }
        }
    }
}

/// A linear range holding every series but those whose amplitude (largest
/// |y|) exceeds [`OFF_SCALE_RATIO`] times the next largest's; `extra`
/// values (reference lines) are included too.
pub(crate) fn linear_range(series: &[&[(f64, f64)]], extra: &[f64]) -> YRange {
    let extents: Vec<Option<(f64, f64)>> = series.iter().map(|s| extent(s)).collect();
    let amplitude = |e: (f64, f64)| e.0.abs().max(e.1.abs());
    let mut order: Vec<usize> = (0..series.len())
        .filter(|&i| extents[i].is_some())
        .collect();
    order.sort_by(|&a, &b| {
        let (ea, eb) = (
            extents[a].map_or(0.0, amplitude),
            extents[b].map_or(0.0, amplitude),
        );
        eb.total_cmp(&ea)
    });
    let mut off_scale = Vec::new();
    let mut start = 0;
    while order.len() - start >= 2 {
        let big = extents[order[start]].map_or(0.0, amplitude);
        let next = extents[order[start + 1]].map_or(0.0, amplitude);
        if next > 0.0 && big > OFF_SCALE_RATIO * next {
            let (lo, hi) = extents[order[start]].unwrap_or((0.0, 0.0));
            let peak = if hi.abs() >= lo.abs() { hi } else { lo };
            off_scale.push((order[start], peak));
            start += 1;
        } else {
            break;
        }
    }
    let mut bounds: Option<(f64, f64)> = None;
    let values = order[start..]
        .iter()
        .filter_map(|&i| extents[i])
        .flat_map(|(lo, hi)| [lo, hi])
        .chain(extra.iter().copied().filter(|v| v.is_finite()));
    for v in values {
        bounds = Some(bounds.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))));
    }
    let (lo, hi) = bounds.unwrap_or((0.0, 1.0));
    let (lo, hi) = (
        lo.clamp(-MAGNITUDE, MAGNITUDE),
        hi.clamp(-MAGNITUDE, MAGNITUDE),
    );
    // A span lost in the rounding of its ends counts as a single value.
    let (lo, hi) = if hi - lo > 1e-9 * lo.abs().max(hi.abs()) {
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    } else {
        let mid = 0.5 * (lo + hi);
        let d = if mid != 0.0 { 0.1 * mid.abs() } else { 1.0 };
        (mid - d, mid + d)
    };
    off_scale.sort_unstable_by_key(|o| o.0);
    YRange { lo, hi, off_scale }
}

/// A logarithmic range over the positive finite values and `extra`,
/// at most [`LOG_DEPTH`] deep below the largest.
pub(crate) fn log_range(series: &[&[(f64, f64)]], extra: &[f64]) -> YRange {
    let positive = series
        .iter()
        .flat_map(|s| s.iter().map(|p| p.1))
        .chain(extra.iter().copied())
        .filter(|y| y.is_finite() && *y > 0.0);
    let mut bounds: Option<(f64, f64)> = None;
    for v in positive {
        bounds = Some(bounds.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))));
    }
    let (lo, hi) = bounds.unwrap_or((0.1, 10.0));
    let hi = hi.clamp(1.0 / MAGNITUDE, MAGNITUDE);
    let lo = lo.max(hi * LOG_DEPTH).min(hi);
    let (lo, hi) = if hi > lo * (1.0 + 1e-9) {
        (lo / 1.25, hi * 1.25)
    } else {
        (lo / 2.0, hi * 2.0)
    };
    YRange {
        lo,
        hi,
        off_scale: Vec::new(),
    }
}

/// Whether values are better read on a log axis: all positive and
/// spanning at least two decades.
pub(crate) fn wants_log(series: &[&[(f64, f64)]]) -> bool {
    let mut any = false;
    let mut lo = f64::INFINITY;
    let mut hi = 0.0_f64;
    for y in series.iter().flat_map(|s| s.iter().map(|p| p.1)) {
        if !y.is_finite() {
            continue;
        }
        if y <= 0.0 {
            return false;
        }
        any = true;
        lo = lo.min(y);
        hi = hi.max(y);
    }
    any && hi >= 100.0 * lo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exploding_series_is_off_scale_and_the_others_set_the_range() {
        let calm = [(0.0, -1.0), (1.0, 2.0)];
        let worse = [(0.0, 0.0), (1.0, -7.0)];
        let exploded = [(0.0, 0.0), (1.0, 1.0e4), (2.0, f64::NAN)];
        let r = linear_range(&[&exploded, &calm, &worse], &[]);
        assert_eq!(r.off_scale, vec![(0, 1.0e4)]);
        // [-7, 2] padded by 5 % of 9.
        assert!((r.lo - (-7.45)).abs() < 1e-12 && (r.hi - 2.45).abs() < 1e-12);
        // 3.5 times worse is a result, not an explosion.
        let r = linear_range(&[&calm, &worse], &[]);
        assert!(r.off_scale.is_empty());
    }

    #[test]
    fn degenerate_and_empty_ranges_are_widened() {
        let flat = [(0.0, 3.0), (1.0, 3.0)];
        let r = linear_range(&[&flat], &[]);
        assert!((r.lo - 2.7).abs() < 1e-12 && (r.hi - 3.3).abs() < 1e-12);
        let r = linear_range(&[&[]], &[]);
        assert!(r.lo < r.hi);
        assert_eq!(x_range([&[(5.0, 1.0)][..]].into_iter()), (4.5, 5.5));
        assert_eq!(x_range([&[][..]].into_iter()), (0.0, 1.0));
    }

    #[test]
    fn log_ranges_skip_non_positive_values_and_hold_the_reference() {
        let s = [(0.0, 0.0), (1.0, 2.0), (2.0, 4.0), (3.0, -1.0)];
        let r = log_range(&[&s], &[8.0]);
        assert!((r.lo - 1.6).abs() < 1e-12 && (r.hi - 10.0).abs() < 1e-12);
        assert!(!wants_log(&[&s]));
        assert!(wants_log(&[&[(0.0, 0.5), (1.0, 50.0)]]));
    }
}
