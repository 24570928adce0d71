//! The input files' formats: `[gnss_file]`, `[truth_file]` and the IMU
//! file's layout (`[imu_file]`).

use super::check::Check;
use super::schema::*;
use super::*;

impl Check<'_> {
    /// `[gnss_file]`: `format` (`gins`, default, or `rtklib`) and, for
    /// RTKLIB, the accepted quality flags (default all, 1 … 6).
    pub(super) fn gnss_format(&self, g: Option<&GnssFile>) -> Result<GnssFormat, InputError> {
        let Some(g) = g else {
            return Ok(GnssFormat::Gins);
        };
        match g.format.as_deref().unwrap_or("gins") {
            "gins" => {
                if g.quality.is_some() {
                    return Err(self.err(
                        "gnss_file.quality",
                        "only format = `rtklib` has quality flags",
                    ));
                }
                Ok(GnssFormat::Gins)
            }
            "rtklib" => {
                let quality = g.quality.clone().unwrap_or_else(|| (1..=6).collect());
                if quality.is_empty() {
                    return Err(self.err("gnss_file.quality", "accept at least one quality flag"));
                }
                if let Some(q) = quality.iter().find(|q| !(1..=6).contains(*q)) {
                    return Err(self.err(
                        "gnss_file.quality",
                        format!(
                            "expected RTKLIB's flags 1 (fix), 2 (float), 3 (SBAS), 4 (DGPS), \
                             5 (single), 6 (PPP), found {q}"
                        ),
                    ));
                }
                Ok(GnssFormat::Rtklib { quality })
            }
            other => Err(self.err(
                "gnss_file.format",
                format!("expected `gins` or `rtklib`, found `{other}`"),
            )),
        }
    }

    /// `[truth_file]`: `format` (`nav`, default, or `rtklib`: position
    /// only), RTKLIB `quality`, and `at` (`imu`, default, or `antenna`).
    pub(super) fn truth(&self, t: Option<&TruthFile>) -> Result<TruthSettings, InputError> {
        let Some(t) = t else {
            return Ok(TruthSettings::default());
        };
        let format = match t.format.as_deref().unwrap_or("nav") {
            "nav" => {
                if t.quality.is_some() {
                    return Err(self.err(
                        "truth_file.quality",
                        "only format = `rtklib` has quality flags",
                    ));
                }
                TruthFormat::Nav
            }
            "rtklib" => {
                let g = GnssFile {
                    format: Some("rtklib".into()),
                    quality: t.quality.clone(),
                };
                match self
                    .gnss_format(Some(&g))
                    .map_err(|e| e.with_key("truth_file.quality"))?
                {
                    GnssFormat::Rtklib { quality } => TruthFormat::Rtklib { quality },
                    GnssFormat::Gins => TruthFormat::Nav,
                }
            }
            other => {
                return Err(self.err(
                    "truth_file.format",
                    format!("expected `nav` or `rtklib`, found `{other}`"),
                ))
            }
        };
        let at_antenna = match t.at.as_deref().unwrap_or("imu") {
            "imu" => false,
            "antenna" => true,
            other => {
                return Err(self.err(
                    "truth_file.at",
                    format!("expected `imu` or `antenna`, found `{other}`"),
                ))
            }
        };
        Ok(TruthSettings { format, at_antenna })
    }

    /// `[imu_file]`: the layout and units of the IMU file.
    pub(super) fn imu_format(&self, m: &ImuFile) -> Result<ImuFormat, InputError> {
        let header_lines = m.header_lines.unwrap_or(0);
        if header_lines > 1000 {
            return Err(self.err(
                "imu_file.header_lines",
                format!("expected at most 1000 header lines, found {header_lines}"),
            ));
        }
        // Without a columns table the GINS columns, and no odometer column
        // unless one is named.
        let mut f = ImuFormat {
            delimiter: self.delimiter(m)?,
            header_lines,
            odometer: None,
            ..ImuFormat::default()
        };
        if let Some(c) = &m.columns {
            self.columns(c, &mut f)?;
        }
        f.time_base = self.time_base(m)?;
        self.week_column(m, &f)?;
        f.measures = match m.measures.as_deref().unwrap_or("increments") {
            "increments" => Measures::Increments,
            "rates" => Measures::Rates,
            other => {
                return Err(self.err(
                    "imu_file.measures",
                    format!("expected `increments` or `rates`, found `{other}`"),
                ));
            }
        };
        (f.gyro_unit, f.accel_unit) = self.units(m, f.measures == Measures::Rates)?;
        if let Some(axes) = &m.axes {
            f.axes = self.axes(axes)?;
        }
        if let Some(mt) = &m.mounting {
            let [r, p, y] = mt.0;
            let k = "imu_file.mounting";
            let r = self.within(&format!("{k}[0]"), "a roll", "deg", r, (-180.0, 180.0))?;
            let p = self.within(&format!("{k}[1]"), "a pitch", "deg", p, (-90.0, 90.0))?;
            let y = self.within(&format!("{k}[2]"), "a yaw", "deg", y, (-180.0, 360.0))?;
            f.mounting = Some(Euler::new(deg(r), deg(p), deg(y)));
        }
        Ok(f)
    }

    /// `delimiter`: whitespace (default), `,`, `;` or `tab`.
    fn delimiter(&self, m: &ImuFile) -> Result<Delimiter, InputError> {
        Ok(match m.delimiter.as_deref().unwrap_or("whitespace") {
            "whitespace" => Delimiter::Whitespace,
            "," => Delimiter::Char(','),
            ";" => Delimiter::Char(';'),
            "tab" => Delimiter::Char('\t'),
            other => {
                return Err(self.err(
                    "imu_file.delimiter",
                    format!("expected `whitespace`, `,`, `;` or `tab`, found `{other}`"),
                ));
            }
        })
    }

    /// `[imu_file.columns]` (1-based, each once, at most 64) into `f`
    /// (0-based).
    fn columns(&self, c: &ImuColumns, f: &mut ImuFormat) -> Result<(), InputError> {
        let key = |name: &str| format!("imu_file.columns.{name}");
        let mut all = vec![("time", c.time)];
        all.extend(c.week.map(|w| ("week", w)));
        all.extend(c.gyro.iter().map(|&g| ("gyro", g)));
        all.extend(c.accel.iter().map(|&a| ("accel", a)));
        all.extend(c.odometer.map(|o| ("odometer", o)));
        for (name, col) in &all {
            if *col == 0 || *col > 64 {
                return Err(self.err(
                    &key(name),
                    format!("expected a column number from 1 to 64, found {col}"),
                ));
            }
        }
        for (i, (name, col)) in all.iter().enumerate() {
            if let Some((other, _)) = all[..i].iter().find(|(_, c)| c == col) {
                return Err(self.err(
                    &key(name),
                    format!("column {col} is already the {other} column"),
                ));
            }
        }
        f.time = c.time - 1;
        f.week = c.week.map(|w| w - 1);
        f.gyro = c.gyro.map(|g| g - 1);
        f.accel = c.accel.map(|a| a - 1);
        f.odometer = c.odometer.map(|o| o - 1);
        Ok(())
    }

    /// `time` (`seconds-of-week`, `week-seconds` or `unix` with
    /// `leap_seconds`).
    fn time_base(&self, m: &ImuFile) -> Result<TimeBase, InputError> {
        let base = match m.time.as_deref().unwrap_or("seconds-of-week") {
            "seconds-of-week" => TimeBase::SecondsOfWeek,
            "week-seconds" => TimeBase::WeekSeconds,
            "unix" => match m.leap_seconds {
                Some(l) if (0.0..=100.0).contains(&l) && l.fract() == 0.0 => {
                    TimeBase::Unix { leap_seconds: l }
                }
                Some(l) => {
                    return Err(self.err(
                        "imu_file.leap_seconds",
                        format!("expected whole seconds from 0 to 100 (18 since 2017), found {l}"),
                    ));
                }
                None => {
                    return Err(self.err(
                        "imu_file.leap_seconds",
                        "`unix` time needs leap_seconds, GPS − UTC (18 s since 2017-01-01)",
                    ));
                }
            },
            other => {
                return Err(self.err(
                    "imu_file.time",
                    format!(
                        "expected `seconds-of-week`, `week-seconds` or `unix`, found `{other}`"
                    ),
                ));
            }
        };
        if m.leap_seconds.is_some() && !matches!(base, TimeBase::Unix { .. }) {
            return Err(self.err(
                "imu_file.leap_seconds",
                "only `unix` time takes leap_seconds",
            ));
        }
        Ok(base)
    }

    /// A week column exactly with `week-seconds` time.
    fn week_column(&self, m: &ImuFile, f: &ImuFormat) -> Result<(), InputError> {
        let _ = m;
        match (f.time_base, f.week) {
            (TimeBase::WeekSeconds, None) => {
                Err(self.err("imu_file.time", "`week-seconds` needs a columns.week"))
            }
            (TimeBase::WeekSeconds, Some(_)) | (_, None) => Ok(()),
            (_, Some(_)) => Err(self.err(
                "imu_file.columns.week",
                "a week column needs time = `week-seconds`",
            )),
        }
    }

    /// `gyro_unit`, `accel_unit` and `g`: the factors to rad(/s) and
    /// m/s(²) of increments or rates.
    fn units(&self, m: &ImuFile, rates: bool) -> Result<(f64, f64), InputError> {
        let (gyro_units, accel_units): (&[(&str, f64)], &[&str]) = if rates {
            (
                &[
                    ("rad/s", 1.0),
                    ("deg/s", PI / 180.0),
                    ("deg/h", PI / 180.0 / 3600.0),
                ],
                &["m/s^2", "g"],
            )
        } else {
            (&[("rad", 1.0), ("deg", PI / 180.0)], &["m/s", "g*s"])
        };
        let names = |u: &[&str]| {
            u.iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let gyro_names: Vec<&str> = gyro_units.iter().map(|u| u.0).collect();
        let measures = if rates { "rates" } else { "increments" };
        let gyro = match (m.gyro_unit.as_deref(), rates) {
            (None, true) => {
                return Err(self.err(
                    "imu_file.gyro_unit",
                    format!("rates need their unit: one of {}", names(&gyro_names)),
                ));
            }
            (None, false) => "rad",
            (Some(u), _) => u,
        };
        let Some(&(_, gyro_unit)) = gyro_units.iter().find(|u| u.0 == gyro) else {
            return Err(self.err(
                "imu_file.gyro_unit",
                format!("{measures} are in {}, found `{gyro}`", names(&gyro_names)),
            ));
        };
        let accel = match (m.accel_unit.as_deref(), rates) {
            (None, true) => {
                return Err(self.err(
                    "imu_file.accel_unit",
                    format!("rates need their unit: one of {}", names(accel_units)),
                ));
            }
            (None, false) => "m/s",
            (Some(u), _) => u,
        };
        if !accel_units.contains(&accel) {
            return Err(self.err(
                "imu_file.accel_unit",
                format!("{measures} are in {}, found `{accel}`", names(accel_units)),
            ));
        }
        Ok((gyro_unit, self.g(m, accel.starts_with('g'))?))
    }

    /// `g`: the g of an accelerometer unit in g (required with one, refused
    /// without).
    fn g(&self, m: &ImuFile, in_g: bool) -> Result<f64, InputError> {
        match (in_g, m.g) {
            (true, Some(g)) if (9.7..=9.9).contains(&g) => Ok(g),
            (true, Some(g)) => Err(self.err(
                "imu_file.g",
                format!(
                    "expected the g of the accelerometer's unit in [9.7, 9.9] m/s², found {}",
                    physical::show(g)
                ),
            )),
            (true, None) => Err(self.err(
                "imu_file.g",
                "an accelerometer unit in g needs the g value it means (9.80665 for \
                 standard gravity; a datasheet may use another)",
            )),
            (false, Some(_)) => {
                Err(self.err("imu_file.g", "only an accelerometer unit in g takes g"))
            }
            (false, None) => Ok(1.0),
        }
    }

    /// `axes`: the file axes that are forward, right, down; a right-handed
    /// frame with each axis once.
    fn axes(&self, axes: &[String; 3]) -> Result<[(usize, f64); 3], InputError> {
        let mut mapped = [(0, 1.0); 3];
        for (i, a) in axes.iter().enumerate() {
            mapped[i] = signed_axis(a).ok_or_else(|| {
                self.err(
                    &format!("imu_file.axes[{i}]"),
                    format!("expected `x`, `y` or `z` with an optional sign, found `{a}`"),
                )
            })?;
        }
        let probe = ImuFormat {
            axes: mapped,
            ..ImuFormat::default()
        };
        let det = probe.to_vehicle().determinant();
        if det.abs() < 0.5 {
            return Err(self.err("imu_file.axes", "each of x, y and z must appear once"));
        }
        if det < 0.0 {
            return Err(self.err(
                "imu_file.axes",
                "these axes mirror the IMU (a left-handed frame): one sign is wrong",
            ));
        }
        Ok(mapped)
    }
}
