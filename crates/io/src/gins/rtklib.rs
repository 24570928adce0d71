//! GNSS solutions in RTKLIB's `.pos` format (RTKPOST / RTKNAVI output):
//! `%` header lines, then `GPST lat lon h Q ns sdn sde sdu sdne sdeu sdun
//! age ratio [vn ve vu sdvn sdve sdvu sdvne sdveu sdvun]`, the time as
//! `YYYY/MM/DD hh:mm:ss.sss` or as `week tow`.
//!
//! The columns are found by their names in the last header line, so the
//! optional velocity columns are read when present. Latitude and longitude
//! must be in decimal degrees and heights ellipsoidal, in GPS time: other
//! RTKLIB output options are refused with the option to change. Velocities
//! are east-north-up in the file and north-east-down in the fixes.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use kestrel_nav::measurement::GnssFix;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::Geodetic;

use super::angle::degrees_to_radians;
use super::line::{open, Lines};
use super::nav::WEEK_SECONDS;
use super::physical;
use crate::InputError;

/// The columns of a `.pos` file, as token indices of a data line.
#[derive(Clone, Copy, Debug)]
struct Columns {
    lat: usize,
    lon: usize,
    h: usize,
    q: usize,
    sd: [usize; 3],
    /// vn, ve, vu and sdvn, sdve, sdvu.
    vel: Option<([usize; 3], [usize; 3])>,
}

/// Streams the fixes of an RTKLIB `.pos` file whose quality flag `Q` is
/// accepted; the others are counted ([`RtklibReader::refused`]).
///
/// ```
/// use kestrel_io::gins::RtklibReader;
/// let text = "% GPST latitude(deg) longitude(deg) height(m) Q ns sdn(m) sde(m) sdu(m) sdne(m) sdeu(m) sdun(m) age(s) ratio\n\
///             2300 100.0 30.5 114.4 25.0 1 9 0.01 0.01 0.02 0 0 0 0 99.9\n\
///             2300 101.0 30.5 114.4 25.0 5 9 1.50 1.20 3.00 0 0 0 0 0.0\n";
/// let mut r = RtklibReader::new(text.as_bytes(), "a.pos".as_ref(), 2300, &[1, 2]);
/// let fix = r.next().unwrap().unwrap();
/// assert_eq!((fix.time, fix.pos_std.z), (100.0, 0.02));
/// assert!(r.next().is_none());
/// assert_eq!(r.refused(), 1);
/// ```
#[derive(Debug)]
pub struct RtklibReader<R> {
    lines: Lines<R>,
    columns: Option<Columns>,
    week0: u32,
    quality: Vec<u8>,
    refused: usize,
    previous: Option<(f64, usize)>,
    last_line: Option<usize>,
    failed: bool,
}

impl RtklibReader<BufReader<File>> {
    /// Opens the `.pos` file at `path` (see [`RtklibReader::new`]).
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open(path: &Path, week0: u32, quality: &[u8]) -> Result<Self, InputError> {
        Ok(Self::new(open(path)?, path, week0, quality))
    }
}

impl<R: BufRead> RtklibReader<R> {
    /// Reads `.pos` lines from `reader` (named `path` in errors); times
    /// become seconds of GPS week `week0`; fixes whose `Q` is not in
    /// `quality` are skipped and counted.
    pub fn new(reader: R, path: &Path, week0: u32, quality: &[u8]) -> Self {
        Self {
            lines: Lines::raw(reader, path),
            columns: None,
            week0,
            quality: quality.to_vec(),
            refused: 0,
            previous: None,
            last_line: None,
            failed: false,
        }
    }

    /// Fixes skipped for their quality flag so far.
    pub fn refused(&self) -> usize {
        self.refused
    }

    /// The line of the last fix returned.
    pub fn last_line(&self) -> Option<usize> {
        self.last_line
    }

    /// The file's name.
    pub fn path(&self) -> &Path {
        self.lines.path()
    }

    fn at(&self, line: usize, column: usize, message: impl Into<String>) -> InputError {
        InputError::at(self.lines.path(), line, column, message)
    }

    /// Takes the column names of a header line, if it is the one naming
    /// the solution's columns.
    fn header(&mut self, line: usize, text: &str) -> Result<(), InputError> {
        let names: Vec<&str> = text.trim_start_matches('%').split_whitespace().collect();
        let Some(first) = names.first() else {
            return Ok(());
        };
        let time_systems = ["GPST", "UTC", "JST", "GST", "BDT"];
        if !time_systems.contains(first) {
            return Ok(());
        }
        if *first != "GPST" {
            return Err(self.at(
                line,
                1,
                format!("time in {first}: set RTKLIB's time system to GPST (out-timesys = gpst)"),
            ));
        }
        // Token k of the header (k ≥ 1) is token k + 1 of a data line: the
        // time takes two tokens.
        let find = |name: &str| names.iter().position(|n| *n == name).map(|k| k + 1);
        if find("x-ecef(m)").is_some() || find("e-baseline(m)").is_some() {
            return Err(self.at(
                line,
                1,
                "positions in ECEF or ENU: set RTKLIB's solution format to lat/lon/height \
                 (out-solformat = llh) in decimal degrees",
            ));
        }
        let (Some(lat), Some(lon)) = (find("latitude(deg)"), find("longitude(deg)")) else {
            return Err(self.at(
                line,
                1,
                "latitude and longitude not in decimal degrees: set RTKLIB's output to \
                 degrees (out-degform = deg)",
            ));
        };
        let need = |name: &str| {
            find(name).ok_or_else(|| self.at(line, 1, format!("no `{name}` column in the header")))
        };
        let vel = match (find("vn(m/s)"), find("ve(m/s)"), find("vu(m/s)")) {
            (Some(n), Some(e), Some(u)) => {
                Some(([n, e, u], [need("sdvn")?, need("sdve")?, need("sdvu")?]))
            }
            _ => None,
        };
        self.columns = Some(Columns {
            lat,
            lon,
            h: need("height(m)")?,
            q: need("Q")?,
            sd: [need("sdn(m)")?, need("sde(m)")?, need("sdu(m)")?],
            vel,
        });
        Ok(())
    }

    /// The fix of a data line, or `None` for a refused quality.
    fn fix(&mut self, line: usize, text: &str) -> Result<Option<GnssFix>, InputError> {
        let Some(c) = self.columns else {
            return Err(self.at(
                line,
                1,
                "a data line before the header line naming the columns (`%  GPST latitude(deg) …`)",
            ));
        };
        let tokens: Vec<&str> = text.split_whitespace().collect();
        // Every column the line is read at (a header may name them in any
        // order, or twice).
        let last = [c.lat, c.lon, c.h, c.q]
            .into_iter()
            .chain(c.sd)
            .chain(c.vel.into_iter().flat_map(|(v, s)| v.into_iter().chain(s)))
            .max()
            .unwrap_or(0);
        if tokens.len() <= last {
            return Err(self.at(
                line,
                tokens.len() + 1,
                format!(
                    "expected {} columns like the header, found {}",
                    last + 1,
                    tokens.len()
                ),
            ));
        }
        let path = self.lines.path().to_path_buf();
        let num = |k: usize, what: &str| -> Result<f64, InputError> {
            tokens[k]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    let m = format!("expected a number ({what}), found `{}`", tokens[k]);
                    InputError::at(&path, line, k + 1, m)
                })
        };
        let q = num(c.q, "quality flag Q")?;
        if !(1.0..=6.0).contains(&q) || q.fract() != 0.0 {
            return Err(self.at(
                line,
                c.q + 1,
                format!("expected a quality flag Q from 1 to 6, found {q}"),
            ));
        }
        let time = self.time(line, tokens[0], tokens[1])?;
        match self.previous {
            Some((t0, l0)) if time <= t0 => {
                return Err(self.at(
                    line,
                    1,
                    format!("time does not increase: not after line {l0} ({t0} s of the week)"),
                ))
            }
            _ => self.previous = Some((time, line)),
        }
        let (lat, lon, h) = (
            num(c.lat, "latitude, deg")?,
            num(c.lon, "longitude, deg")?,
            num(c.h, "height, m")?,
        );
        let checks = [
            (
                c.lat,
                physical::outside("a latitude", "deg", lat, physical::LATITUDE),
            ),
            (
                c.lon,
                physical::outside("a longitude", "deg", lon, physical::LONGITUDE),
            ),
            (c.h, physical::outside("a height", "m", h, physical::HEIGHT)),
        ];
        if let Some((k, Some(m))) = checks.into_iter().find(|(_, m)| m.is_some()) {
            return Err(self.at(line, k + 1, m));
        }
        let mut sd = [0.0; 3];
        for (i, k) in c.sd.iter().enumerate() {
            sd[i] = self.sigma(line, *k, num(*k, "σ, m")?)?;
        }
        if !self.quality.contains(&(q as u8)) {
            self.refused += 1;
            return Ok(None);
        }
        let pos = Geodetic::new(degrees_to_radians(lat), degrees_to_radians(lon), h);
        let pos_std = Vector3::new(sd[0], sd[1], sd[2]);
        let fix = match c.vel {
            Some((v, s)) => {
                let mut vel = [0.0; 3];
                for (i, k) in v.iter().enumerate() {
                    vel[i] = num(*k, "velocity, m/s")?;
                    if let Some(m) = physical::outside(
                        "a speed",
                        "m/s",
                        vel[i],
                        (-physical::SPEED, physical::SPEED),
                    ) {
                        return Err(self.at(line, k + 1, m));
                    }
                }
                let mut vs = [0.0; 3];
                for (i, k) in s.iter().enumerate() {
                    vs[i] = self.sigma(line, *k, num(*k, "σ velocity, m/s")?)?;
                }
                // East-north-up in the file.
                GnssFix::new(time, pos, Vector3::new(vel[0], vel[1], -vel[2]))
                    .with_std(pos_std, Vector3::new(vs[0], vs[1], vs[2]))
            }
            None => {
                let p = GnssFix::position_only(time, pos);
                p.with_std(pos_std, p.vel_std)
            }
        };
        Ok(Some(fix))
    }

    fn sigma(&self, line: usize, k: usize, x: f64) -> Result<f64, InputError> {
        match physical::bad_sigma(x) {
            None => Ok(x),
            Some(m) => Err(self.at(
                line,
                k + 1,
                format!("{m} (RTKLIB writes 0 when it has no estimate; use [gnss] noise = \"fixed\" and drop such lines)"),
            )),
        }
    }

    /// The time of the two time tokens as seconds of week `week0`.
    fn time(&self, line: usize, a: &str, b: &str) -> Result<f64, InputError> {
        let w0 = f64::from(self.week0) * WEEK_SECONDS;
        if let Some((y, m, d)) = date(a) {
            let s = clock(b).ok_or_else(|| {
                self.at(
                    line,
                    2,
                    format!("expected a time hh:mm:ss.sss, found `{b}`"),
                )
            })?;
            let gps =
                (days_from_civil(y, m, d) - days_from_civil(1980, 1, 6)) as f64 * 86_400.0 + s;
            return Ok(gps - w0);
        }
        match (a.parse::<u32>(), b.parse::<f64>()) {
            (Ok(week), Ok(tow))
                if week <= super::physical::GPS_WEEK_MAX && (0.0..WEEK_SECONDS).contains(&tow) =>
            {
                Ok(f64::from(week) * WEEK_SECONDS + tow - w0)
            }
            _ => Err(self.at(
                line,
                1,
                format!("expected the time as YYYY/MM/DD hh:mm:ss or as GPS week and seconds, found `{a} {b}`"),
            )),
        }
    }
}

impl<R: BufRead> Iterator for RtklibReader<R> {
    type Item = Result<GnssFix, InputError>;

    /// The next accepted fix; after an error the reader ends.
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        loop {
            let (line, text) = match self.lines.next_text()? {
                Ok((l, t)) => (l, t.to_owned()),
                Err(e) => {
                    self.failed = true;
                    return Some(Err(e));
                }
            };
            let r = if text.trim_start().starts_with('%') {
                self.header(line, &text).map(|()| None)
            } else {
                self.fix(line, &text)
            };
            match r {
                Ok(None) => continue,
                Ok(Some(fix)) => {
                    self.last_line = Some(line);
                    return Some(Ok(fix));
                }
                Err(e) => {
                    self.failed = true;
                    return Some(Err(e));
                }
            }
        }
    }
}

/// `YYYY/MM/DD`.
fn date(s: &str) -> Option<(i64, u32, u32)> {
    let mut it = s.split('/');
    // GPS time starts in 1980; the last full week kestrel accepts
    // ([`GPS_WEEK_MAX`](super::physical::GPS_WEEK_MAX)) is in 2171. A wider
    // year overflows the day count.
    let y = it
        .next()?
        .parse()
        .ok()
        .filter(|y| (1980..=2171).contains(y))?;
    let m = it.next()?.parse().ok().filter(|m| (1..=12).contains(m))?;
    let d = it.next()?.parse().ok().filter(|d| (1..=31).contains(d))?;
    it.next().is_none().then_some((y, m, d))
}

/// `hh:mm:ss.sss` as seconds of the day.
fn clock(s: &str) -> Option<f64> {
    let mut it = s.split(':');
    let h: f64 = it.next()?.parse().ok()?;
    let m: f64 = it.next()?.parse().ok()?;
    let sec: f64 = it.next()?.parse().ok()?;
    let ok = it.next().is_none()
        && (0.0..24.0).contains(&h)
        && (0.0..60.0).contains(&m)
        && (0.0..61.0).contains(&sec);
    ok.then_some(h * 3600.0 + m * 60.0 + sec)
}

/// Days from 1970-01-01 to the civil date `y-m-d` (proleptic Gregorian;
/// H. Hinnant's `days_from_civil`).
fn days_from_civil(y: i64, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let m = i64::from(m);
    let doy = (153 * (if m > 2 { m - 3 } else { m + 9 }) + 2) / 5 + i64::from(d) - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

#[cfg(test)]
mod tests {
    use super::super::imu_format::GPS_EPOCH_UNIX;
    use super::*;

    /// Found by fuzzing: a year of 18 digits overflowed the day count.
    #[test]
    fn dates_outside_gps_time_are_refused() {
        assert_eq!(date("400053333333333330/01/02"), None);
        assert_eq!(date("1979/12/31"), None);
        assert_eq!(date("2172/01/01"), None);
        assert_eq!(date("2024/02/29"), Some((2024, 2, 29)));
    }

    #[test]
    fn civil_dates_count_days_from_the_unix_epoch() {
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(
            days_from_civil(1980, 1, 6) as f64 * 86_400.0,
            GPS_EPOCH_UNIX
        );
        assert_eq!(days_from_civil(2024, 1, 1), 19_723);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
    }

    #[test]
    fn dates_and_weeks_give_the_same_seconds() {
        let r = RtklibReader::new(&b""[..], "a.pos".as_ref(), 2295, &[1]);
        // 2024-01-01 00:00:18 GPST is week 2295, 86 418 s.
        assert_eq!(r.time(1, "2024/01/01", "00:00:18.000").unwrap(), 86_418.0);
        assert_eq!(r.time(1, "2295", "86418.000").unwrap(), 86_418.0);
        assert!(r.time(1, "2024/13/01", "00:00:00").is_err());
    }

    /// Found by the fuzz pass: a header naming `height(m)` after every
    /// column a data line has was read past the line's end (a panic).
    #[test]
    fn a_column_named_after_the_line_end_is_an_error() {
        let text = "% GPST latitude(deg) longitude(deg) Q ns sdn(m) sde(m) sdu(m) x y height(m)\n\
                    2300 100.0 30.5 114.4 1 9 0.01 0.01 0.02\n";
        let e = RtklibReader::new(text.as_bytes(), "a.pos".as_ref(), 2300, &[1])
            .next()
            .unwrap()
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "a.pos:2:10: expected 12 columns like the header, found 9"
        );
    }
}
