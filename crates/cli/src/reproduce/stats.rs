//! Mean and standard deviation over Monte Carlo runs.

use std::fmt;

/// The mean and sample standard deviation of a set of values.
///
/// ```
/// use kestrel_cli::reproduce::MeanStd;
/// let m = MeanStd::of([1.0, 2.0, 3.0]);
/// assert_eq!((m.mean, m.std, m.count), (2.0, 1.0, 3));
/// assert_eq!(MeanStd::of([]).count, 0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanStd {
    /// Mean (NaN when there are no values).
    pub mean: f64,
    /// Sample standard deviation (0 for a single value, NaN for none).
    pub std: f64,
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
            count: n,
        }
    }
}

impl fmt::Display for MeanStd {
    /// `mean ± std` with the precision given to the formatter (default 3
    /// significant-looking decimals), `—` when there are no values.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.count == 0 {
            return write!(f, "—");
        }
        let p = f.precision().unwrap_or(3);
        write!(f, "{:.p$} ± {:.p$}", self.mean, self.std)
    }
}
