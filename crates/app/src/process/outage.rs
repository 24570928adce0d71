//! GNSS outage windows given on the command line.

use std::str::FromStr;

/// GNSS fixes with `start ≤ t < end` (seconds of week) are not used: the
/// window is half-open, so `100:160` drops the 60 fixes of a 1 Hz file from
/// 100 to 159 s, exactly as deleting those lines would.
///
/// ```
/// use kestrel_app::process::Outage;
/// let o: Outage = "100:160.5".parse().unwrap();
/// assert!(o.contains(100.0) && o.contains(160.0) && !o.contains(160.5));
/// assert!("160:100".parse::<Outage>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outage {
    /// First second of the window.
    pub start: f64,
    /// End of the window (not in it).
    pub end: f64,
}

impl Outage {
    /// Whether `t` falls in the window.
    pub fn contains(&self, t: f64) -> bool {
        t >= self.start && t < self.end
    }
}

impl FromStr for Outage {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let (a, b) = s
            .split_once(':')
            .ok_or_else(|| format!("expected START:END in seconds of week, found `{s}`"))?;
        let num = |x: &str| {
            x.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("expected a number of seconds, found `{x}`"))
        };
        let (start, end) = (num(a)?, num(b)?);
        if end <= start {
            return Err(format!(
                "the outage must end after it starts, found {start}:{end}"
            ));
        }
        Ok(Self { start, end })
    }
}
