//! Thinning of long series for drawing.

/// The finite points of `points`, at most `max_points` of them (but at least
/// two when there are two): the points are cut into consecutive buckets and
/// each bucket keeps its lowest and highest point in their original order,
/// so spikes stay visible however long the series is.
///
/// ```
/// use kestrel_cli::plot::thin;
/// let mut series: Vec<(f64, f64)> = (0..10_000).map(|i| (i as f64, 0.0)).collect();
/// series[5_000].1 = 20.0; // a spike
/// series[7].1 = f64::NAN; // skipped
/// let t = thin(&series, 100);
/// assert!(t.len() <= 100);
/// assert!(t.contains(&(5_000.0, 20.0)));
/// assert!(t.iter().all(|p| p.1.is_finite()));
/// ```
pub fn thin(points: &[(f64, f64)], max_points: usize) -> Vec<(f64, f64)> {
    let finite: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let max_points = max_points.max(2);
    if finite.len() <= max_points {
        return finite;
    }
    let buckets = max_points / 2;
    let size = finite.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets);
    for chunk in finite.chunks(size) {
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[lo].1 {
                lo = i;
            }
            if p.1 > chunk[hi].1 {
                hi = i;
            }
        }
        let (first, second) = (lo.min(hi), lo.max(hi));
        out.push(chunk[first]);
        if second != first {
            out.push(chunk[second]);
        }
    }
    out
}

/// A time step this many times the median step is a gap (an outage): the
/// line is broken there instead of bridging it.
const GAP_FACTOR: f64 = 5.0;

/// `points` cut where the time step exceeds [`GAP_FACTOR`] times the median
/// step, so that an outage shows as a gap, not a straight line.
///
/// ```
/// use kestrel_cli::plot::split_at_gaps;
/// let p = [(0.0, 1.0), (1.0, 1.0), (2.0, 1.0), (30.0, 1.0), (31.0, 1.0)];
/// let parts = split_at_gaps(&p);
/// assert_eq!(parts, vec![&p[..3], &p[3..]]);
/// ```
pub fn split_at_gaps(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    let mut steps: Vec<f64> = points
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if steps.is_empty() {
        return vec![points];
    }
    let mid = steps.len() / 2;
    let median = *steps.select_nth_unstable_by(mid, f64::total_cmp).1;
    let mut parts = Vec::new();
    let mut start = 0;
    for i in 1..points.len() {
        if points[i].0 - points[i - 1].0 > GAP_FACTOR * median {
            parts.push(&points[start..i]);
            start = i;
        }
    }
    parts.push(&points[start..]);
    parts
}
