//! The configuration as a whole, in the order it is checked (so the same
//! problem is always reported first): the start, P0, the sensors, the
//! error model and what depends on it, the filter, the GNSS noise, the
//! output and the files' formats.

use super::check::{id, Check, Zero};
use super::schema::*;
use super::*;
use crate::config::names::ErrorModelName;

impl Check<'_> {
    /// Every table of `f`, checked.
    pub(super) fn settings(&self, f: File) -> Result<Settings, InputError> {
        let i = &f.initial;
        let alignment = f
            .alignment
            .as_ref()
            .map(|a| self.alignment(a))
            .transpose()?;
        self.given_or_aligned(i, alignment.as_ref())?;
        let start = self.start(i)?;
        let p0 = self.p0(&i.std)?;
        let initial_imu = self.initial_imu(i)?;
        let mut imu = self.imu(&f.imu)?;
        let odometer = f.odometer.as_ref().map(|o| self.odometer(o)).transpose()?;
        let error_model = self.error_model(&f)?;
        self.scale_factors(&f.imu, &error_model, &p0, &mut imu)?;
        self.odometer_fits(&f, odometer.is_some(), &error_model)?;
        let kind = self.kind(&f.filter, error_model)?;
        let gnss_noise = self.gnss_noise(&f.gnss)?;
        Ok(Settings {
            earth: f.earth.ellipsoid(),
            week: self.week(i.week)?,
            start,
            p0,
            initial_imu,
            nhc: f.nhc.as_ref().map(|n| self.nhc(n)).transpose()?,
            alignment,
            zupt: f.zupt.as_ref().map(|z| self.zupt(z)).transpose()?,
            imu,
            error_model,
            kind,
            covariance_interval: self.non_negative(
                "filter.covariance_interval",
                f.filter.covariance_interval.unwrap_or(0.1),
            )?,
            lever_arm: self.lever_arm("filter.lever_arm", f.filter.lever_arm)?,
            gnss_noise,
            odometer,
            output_interval: self
                .non_negative("output.interval", f.output.interval.unwrap_or(0.0))?,
            axes: f.output.position_axes,
            timing: self.timing(&f.imu)?,
            imu_format: match &f.imu_file {
                Some(m) => self.imu_format(m)?,
                None => ImuFormat::default(),
            },
            gnss_format: self.gnss_format(f.gnss_file.as_ref())?,
            truth: self.truth(f.truth_file.as_ref())?,
        })
    }

    /// What the alignment provides is not given, what it does not is.
    fn given_or_aligned(
        &self,
        i: &Initial,
        alignment: Option<&AlignmentSettings>,
    ) -> Result<(), InputError> {
        let course = alignment.is_some_and(|a| a.yaw == YawSource::GnssCourse);
        let given = [
            ("initial.position", i.position.is_some(), !course),
            (
                "initial.attitude",
                i.attitude.is_some(),
                alignment.is_none(),
            ),
        ];
        for (key, present, wanted) in given {
            if present && !wanted {
                return Err(self.err(key, "not used: the [alignment] sets it; remove the key"));
            }
            if !present && wanted {
                return Err(self.err(key, "missing (or give an [alignment] table)"));
            }
        }
        if alignment.is_some() && i.velocity.is_some() {
            return Err(self.err(
                "initial.velocity",
                "not used: the alignment starts standing still (or from the GNSS velocity)",
            ));
        }
        Ok(())
    }

    /// `[initial]`: the navigation state at `time`, each value within its
    /// physical range (placeholders where the alignment sets it).
    fn start(&self, i: &Initial) -> Result<NavState, InputError> {
        let [lat, lon, h] = i.position.map_or([0.0; 3], |p| p.0);
        let key = "initial.position";
        let lat = self.within(
            &format!("{key}[0]"),
            "a latitude",
            "deg",
            lat,
            physical::LATITUDE,
        )?;
        let lon = self.within(
            &format!("{key}[1]"),
            "a longitude",
            "deg",
            lon,
            physical::LONGITUDE,
        )?;
        let h = self.within(&format!("{key}[2]"), "a height", "m", h, physical::HEIGHT)?;
        let [roll, pitch, yaw] = i.attitude.map_or([0.0; 3], |a| a.0);
        let key = "initial.attitude";
        let roll = self.within(&format!("{key}[0]"), "a roll", "deg", roll, (-180.0, 180.0))?;
        let pitch = self.within(&format!("{key}[1]"), "a pitch", "deg", pitch, (-90.0, 90.0))?;
        let yaw = self.within(&format!("{key}[2]"), "a yaw", "deg", yaw, (-180.0, 360.0))?;
        let speed = |c: &Self, key: &str, v: f64| {
            c.within(
                key,
                "a speed",
                "m/s",
                v,
                (-physical::SPEED, physical::SPEED),
            )
        };
        Ok(NavState::new(
            self.non_negative("initial.time", i.time)?,
            Geodetic::new(deg(lat), deg(lon), h),
            self.vec(
                "initial.velocity",
                i.velocity.unwrap_or_default(),
                speed,
                id,
            )?,
            Euler::new(deg(roll), deg(pitch), deg(yaw)),
        ))
    }

    /// `[initial.std]`: P0 as standard deviations ([`P0Table`]).
    fn p0(&self, s: &P0Table) -> Result<InitialUncertainty, InputError> {
        s.uncertainty("initial.std").map_err(|b| self.source.bad(b))
    }

    /// `[filter] error_model` with its scale factors' correlation time
    /// (`imu.scale_tau` for `ins21`, `odometer.scale_tau` for `odometer16`).
    fn error_model(&self, f: &File) -> Result<ErrorModelKind, InputError> {
        let tau = match f.filter.error_model {
            ErrorModelName::Ins21 => match f.imu.scale_tau {
                Some(t) => self.tau("imu.scale_tau", Some(t))?,
                None => f64::INFINITY,
            },
            ErrorModelName::Odometer16 => match &f.odometer {
                Some(o) => self.positive("odometer.scale_tau", o.scale_tau)?,
                None => {
                    return Err(self.err(
                        "filter.error_model",
                        "`odometer16` needs an [odometer] table",
                    ));
                }
            },
            ErrorModelName::Ins15 | ErrorModelName::Ins18 => f64::INFINITY,
        };
        Ok(f.filter.error_model.model(tau))
    }

    /// The scale-factor keys: refused outside `ins21`; with it, the scale
    /// factors' Markov σ (with a finite `scale_tau`) as given, else their
    /// initial σ (the RMS over the axes), into `imu`.
    fn scale_factors(
        &self,
        m: &ImuTable,
        model: &ErrorModelKind,
        p0: &InitialUncertainty,
        imu: &mut ImuSpec,
    ) -> Result<(), InputError> {
        if !matches!(model, ErrorModelKind::Ins21 { .. }) {
            let given = [
                ("initial.std.gyro_scale", p0.gyro_scale != Vector3::zeros()),
                (
                    "initial.std.accel_scale",
                    p0.accel_scale != Vector3::zeros(),
                ),
                ("imu.scale_tau", m.scale_tau.is_some()),
                ("imu.gyro_scale_sigma", m.gyro_scale_sigma.is_some()),
                ("imu.accel_scale_sigma", m.accel_scale_sigma.is_some()),
            ];
            return match given.iter().find(|(_, g)| *g) {
                Some((k, _)) => Err(self.err(
                    k,
                    "scale-factor errors are states of error_model = `ins21` only \
                     (a known scale-factor error is `initial.gyro_scale` / `initial.accel_scale`)",
                )),
                None => Ok(()),
            };
        }
        let markov = [
            ("imu.gyro_scale_sigma", m.gyro_scale_sigma, p0.gyro_scale),
            ("imu.accel_scale_sigma", m.accel_scale_sigma, p0.accel_scale),
        ];
        let mut sigma = [0.0; 2];
        for (out, (key, given, initial)) in sigma.iter_mut().zip(markov) {
            *out = match given {
                Some(_) if m.scale_tau.is_none() => {
                    return Err(self.err(
                        key,
                        "a Markov σ needs `imu.scale_tau` (without it the scale \
                         factors are random constants)",
                    ));
                }
                Some(x) => self.sigma(key, x, ppm, Zero::Absent)?,
                None => (initial.norm_squared() / 3.0).sqrt(),
            };
        }
        [imu.gyro_scale, imu.accel_scale] = sigma;
        Ok(())
    }

    /// An odometer needs the 16-state model and makes `[nhc]` redundant.
    fn odometer_fits(
        &self,
        f: &File,
        odometer: bool,
        model: &ErrorModelKind,
    ) -> Result<(), InputError> {
        if odometer && f.nhc.is_some() {
            return Err(self.err(
                "nhc",
                "the odometer update applies the non-holonomic constraint already \
                 (`odometer.nhc_std`); remove the [nhc] table",
            ));
        }
        if odometer && !matches!(model, ErrorModelKind::Odometer16 { .. }) {
            return Err(self.err(
                "filter.error_model",
                "odometer aiding needs error_model = `odometer16`",
            ));
        }
        Ok(())
    }

    /// `[gnss]`: R from each fix's σ (`noise = "file"`) or fixed σ.
    fn gnss_noise(&self, g: &Gnss) -> Result<GnssNoise, InputError> {
        match g.noise {
            GnssNoiseSource::File => {
                if g.position_std.is_some() || g.velocity_std.is_some() {
                    return Err(self.err("gnss.noise", "fixed σ given but noise = `file`"));
                }
                Ok(GnssNoise::Reported)
            }
            GnssNoiseSource::Fixed => {
                let (Some(p), Some(v)) = (g.position_std, g.velocity_std) else {
                    return Err(
                        self.err("gnss.noise", "`fixed` needs position_std and velocity_std")
                    );
                };
                Ok(GnssNoise::Fixed {
                    position: self.sigmas("gnss.position_std", p, id, Zero::Refused)?,
                    velocity: self.sigmas("gnss.velocity_std", v, id, Zero::Refused)?,
                })
            }
        }
    }
}
