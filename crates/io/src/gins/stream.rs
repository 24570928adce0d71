//! What every reader does with a data line before it is a record: the
//! column count of the first data line kept, increasing times, checks
//! whose errors name the file, line and column, and the end after an
//! error.

use std::io::BufRead;
use std::path::Path;

use super::line::{Fields, Lines};
use super::nav::WEEK_SECONDS as WEEK;
use super::physical;
use crate::InputError;

/// The data lines of one file with the state every reader keeps.
#[derive(Debug)]
pub(crate) struct Stream<R> {
    lines: Lines<R>,
    columns: Option<usize>,
    previous: Option<(f64, usize)>,
    /// Weeks added to seconds of week after a rollover, s.
    week_offset: f64,
    failed: bool,
}

impl<R: BufRead> Stream<R> {
    /// A stream over `lines`.
    pub(crate) fn new(lines: Lines<R>) -> Self {
        Self {
            lines,
            columns: None,
            previous: None,
            week_offset: 0.0,
            failed: false,
        }
    }

    /// The line of the last record read without error.
    pub(crate) fn last_line(&self) -> Option<usize> {
        self.previous.map(|(_, line)| line)
    }

    /// The file's name for errors.
    pub(crate) fn path(&self) -> &Path {
        self.lines.path()
    }

    /// The next data line turned into a record by `parse`; `None` at the
    /// end of the file and after the first error (a reader stops there).
    pub(crate) fn next<T>(
        &mut self,
        parse: impl FnOnce(&mut Self, &Fields) -> Result<T, InputError>,
    ) -> Option<Result<T, InputError>> {
        if self.failed {
            return None;
        }
        let r = self.fields().map(|f| f.and_then(|f| parse(&mut *self, &f)));
        self.failed = matches!(r, Some(Err(_)));
        r
    }

    /// The next data line, with the column count of the first one.
    fn fields(&mut self) -> Option<Result<Fields, InputError>> {
        let f = match self.lines.next_fields()? {
            Ok(f) => f,
            Err(e) => return Some(Err(e)),
        };
        match self.columns {
            None => self.columns = Some(f.count),
            Some(c) if c != f.count => {
                return Some(Err(self.at(
                    &f,
                    c.min(f.count) + 1,
                    format!(
                        "expected {c} columns like the first data line, found {}",
                        f.count
                    ),
                )))
            }
            Some(_) => {}
        }
        Some(Ok(f))
    }

    /// The error `message` at `column` (1-based) of the line of `f`.
    pub(crate) fn at(&self, f: &Fields, column: usize, message: String) -> InputError {
        InputError::at(self.path(), f.line, column, message)
    }

    /// Takes `time` as the latest time, returning the previous time and
    /// its line, if any; `Err` with them when `time` is not after them.
    pub(crate) fn advance(
        &mut self,
        time: f64,
        f: &Fields,
    ) -> Result<Option<(f64, usize)>, (f64, usize)> {
        match self.previous {
            Some((t0, l0)) if time <= t0 => Err((t0, l0)),
            previous => {
                self.previous = Some((time, f.line));
                Ok(previous)
            }
        }
    }

    /// [`advance`](Self::advance) for a time in seconds of week in column 1,
    /// returning it continued across week rollovers: a time more than half
    /// a week before the previous one is taken to be in the next week
    /// (604 800 s added from there on).
    pub(crate) fn advance_seconds(&mut self, f: &Fields) -> Result<f64, InputError> {
        let mut time = f.get(0) + self.week_offset;
        if let Some((t0, _)) = self.previous
            && time < t0 - 0.5 * WEEK
        {
            self.week_offset += WEEK;
            time += WEEK;
        }
        self.advance(time, f).map(|_| time).map_err(|(t0, l0)| {
            self.at(
                f,
                1,
                format!(
                    "time does not increase: {time} s after {t0} s at line {l0} \
                     (expected increasing seconds of week)"
                ),
            )
        })
    }

    /// Checks a geodetic position in columns `i..i + 3` (0-based): latitude
    /// and longitude in degrees, ellipsoidal height in metres, each within
    /// its [physical range](super::physical).
    pub(crate) fn position(&self, f: &Fields, i: usize) -> Result<(), InputError> {
        let checks = [
            ("a latitude", "deg", physical::LATITUDE),
            ("a longitude", "deg", physical::LONGITUDE),
            ("a height", "m", physical::HEIGHT),
        ];
        for (k, (what, unit, range)) in checks.into_iter().enumerate() {
            if let Some(m) = physical::outside(what, unit, f.get(i + k), range) {
                return Err(self.at(f, i + k + 1, m));
            }
        }
        Ok(())
    }

    /// Checks that the values in `columns` (0-based) are speeds within
    /// ±[`SPEED`](physical::SPEED).
    pub(crate) fn speeds(&self, f: &Fields, columns: &[usize]) -> Result<(), InputError> {
        self.within(f, columns, "a speed", physical::SPEED)
    }

    /// Checks that the values in `columns` (0-based) are odometer speeds
    /// within ±[`WHEEL_SPEED`](physical::WHEEL_SPEED).
    pub(crate) fn wheel_speeds(&self, f: &Fields, columns: &[usize]) -> Result<(), InputError> {
        self.within(f, columns, "an odometer speed", physical::WHEEL_SPEED)
    }

    /// Checks that the values in `columns` are speeds (`what`) within ±`max`.
    fn within(
        &self,
        f: &Fields,
        columns: &[usize],
        what: &str,
        max: f64,
    ) -> Result<(), InputError> {
        for &c in columns.iter().filter(|&&c| c < f.count) {
            if let Some(m) = physical::outside(what, "m/s", f.get(c), (-max, max)) {
                return Err(self.at(f, c + 1, m));
            }
        }
        Ok(())
    }

    /// Checks that the values in `columns` (0-based) are standard
    /// deviations whose squares are normal doubles; `names` name them.
    pub(crate) fn sigmas(
        &self,
        f: &Fields,
        columns: &[usize],
        names: &[&str],
    ) -> Result<(), InputError> {
        for &c in columns.iter().filter(|&&c| c < f.count) {
            if let Some(m) = physical::bad_sigma(f.get(c)) {
                return Err(self.at(f, c + 1, format!("{m} ({})", names[c])));
            }
        }
        Ok(())
    }
}
