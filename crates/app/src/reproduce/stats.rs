//! Mean, standard deviation, median and quartiles over Monte Carlo runs.

use std::fmt;

/// The mean, sample standard deviation and median of a set of values.
///
/// ```
/// use kestrel_app::reproduce::MeanStd;
/// let m = MeanStd::of([1.0, 2.0, 3.0, 10.0]);
/// assert_eq!((m.mean, m.median, m.count), (4.0, 2.5, 4));
/// assert_eq!(MeanStd::of([]).count, 0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanStd {
    /// Mean (NaN when there are no values).
    pub mean: f64,
    /// Sample standard deviation (0 for a single value, NaN for none).
    pub std: f64,
    /// Median (NaN when there are no values).
    pub median: f64,
    /// Number of values.
    pub count: usize,
}

impl MeanStd {
    /// The statistics of `values`.
    pub fn of(values: impl IntoIterator<Item = f64>) -> Self {
        let values: Vec<f64> = values.into_iter().collect();
        let n = values.len();
        if n == 0 {
            return Self {
                mean: f64::NAN,
                std: f64::NAN,
                median: f64::NAN,
                count: 0,
            };
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let std = if n > 1 {
            let ss: f64 = values.iter().map(|v| (v - mean).powi(2)).sum();
            (ss / (n - 1) as f64).sqrt()
        } else {
            0.0
        };
        Self {
            mean,
            std,
            median: quantile(&values, 0.5).unwrap_or(f64::NAN),
            count: n,
        }
    }
}

/// The `q`-quantile of `values` (linear interpolation between order
/// statistics, the "type 7" of Hyndman and Fan, 1996); `None` for no values
/// or a NaN among them.
///
/// ```
/// use kestrel_app::reproduce::quantile;
/// assert_eq!(quantile(&[4.0, 1.0, 3.0, 2.0], 0.5), Some(2.5));
/// assert_eq!(quantile(&[4.0, 1.0, 3.0, 2.0], 0.25), Some(1.75));
/// assert_eq!(quantile(&[], 0.5), None);
/// ```
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() || values.iter().any(|v| v.is_nan()) {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    Some(v[lo] + (h - lo as f64) * (v[hi] - v[lo]))
}

/// Median and interquartile range of a set of values.
///
/// ```
/// use kestrel_app::reproduce::Quartiles;
/// let q = Quartiles::of(&[1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
/// assert_eq!((q.q1, q.median, q.q3, q.count), (2.0, 3.0, 4.0, 5));
/// assert!(Quartiles::of(&[]).is_none());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quartiles {
    /// First quartile.
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile.
    pub q3: f64,
    /// Number of values.
    pub count: usize,
}

impl Quartiles {
    /// The quartiles of `values`; `None` for no values or a NaN among them.
    pub fn of(values: &[f64]) -> Option<Self> {
        Some(Self {
            q1: quantile(values, 0.25)?,
            median: quantile(values, 0.5)?,
            q3: quantile(values, 0.75)?,
            count: values.len(),
        })
    }
}

impl fmt::Display for Quartiles {
    /// `median [q1, q3]` with the formatter's precision (default 2).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = f.precision().unwrap_or(2);
        write!(f, "{:.p$} [{:.p$}, {:.p$}]", self.median, self.q1, self.q3)
    }
}

impl fmt::Display for MeanStd {
    /// `mean ± std (median)` with the precision given to the formatter
    /// (default 3 decimals), `—` when there are no values.
    ///
    /// ```
    /// use kestrel_app::reproduce::MeanStd;
    /// assert_eq!(format!("{:.1}", MeanStd::of([1.0, 2.0, 9.0])), "4.0 ± 4.4 (2.0)");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.count == 0 {
            return write!(f, "—");
        }
        let p = f.precision().unwrap_or(3);
        write!(
            f,
            "{:.p$} ± {:.p$} ({:.p$})",
            self.mean, self.std, self.median
        )
    }
}
