//! The process configuration file (TOML): what the filter is told about
//! the start, the IMU, the GNSS antenna and receiver, the odometer and the
//! output. `crates/app/configs/process-example.toml` documents every key.

use std::path::Path;

use crate::experiment::PositionAxes;
use crate::scenario::{ErrorModelKind, FilterKind, InitialUncertainty};
use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::{Ellipsoid, Euler, Geodetic, ImuBiases, ImuSpec, NavState};
use serde::{Deserialize, Deserializer};

use crate::config::filter::{read_kind, Keys, Kinds};
use crate::config::read::Source;
use crate::config::units::{DEG, DEG_PER_H, DEG_PER_SQRT_H, M_S_PER_SQRT_H, PPM, UG};
use crate::process::timing::{LongGap, TimingRule};

fn deg(x: f64) -> f64 {
    DEG.si(x)
}
fn deg_per_h(x: f64) -> f64 {
    DEG_PER_H.si(x)
}
fn deg_per_sqrt_h(x: f64) -> f64 {
    DEG_PER_SQRT_H.si(x)
}
fn m_s_per_sqrt_h(x: f64) -> f64 {
    M_S_PER_SQRT_H.si(x)
}
fn ppm(x: f64) -> f64 {
    PPM.si(x)
}
fn ug(x: f64) -> f64 {
    UG.si(x)
}
use crate::{Error, InputError};
use kestrel_io::gins::imu_format::{signed_axis, ImuFormat, Measures, TimeBase};
use kestrel_io::gins::physical;
use kestrel_io::gins::Delimiter;
use std::f64::consts::PI;

type V3 = Exact<3>;

/// An array of exactly `N` numbers: a longer or shorter one is an error at
/// its line and column, never truncated.
#[derive(Clone, Copy, Debug)]
struct Exact<const N: usize>([f64; N]);

impl<const N: usize> Default for Exact<N> {
    fn default() -> Self {
        Self([0.0; N])
    }
}

impl<'de, const N: usize> Deserialize<'de> for Exact<N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Count(usize);
        impl serde::de::Expected for Count {
            fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of exactly {} numbers", self.0)
            }
        }
        let v = Vec::<f64>::deserialize(d)?;
        <[f64; N]>::try_from(v.as_slice())
            .map(Exact)
            .map_err(|_| serde::de::Error::invalid_length(v.len(), &Count(N)))
    }
}

/// A key `process` reads but cannot honour: any value is an error that
/// says what to use instead.
#[derive(Debug)]
struct Refused;

impl<'de> Deserialize<'de> for Refused {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        serde::de::IgnoredAny::deserialize(d).map(|_| Refused)
    }
}

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    earth: Option<String>,
    initial: Initial,
    #[serde(default)]
    imu: Imu,
    #[serde(default)]
    filter: Filter,
    #[serde(default)]
    gnss: Gnss,
    odometer: Option<Odometer>,
    nhc: Option<Nhc>,
    zupt: Option<Zupt>,
    alignment: Option<Alignment>,
    #[serde(default)]
    output: Output,
    imu_file: Option<ImuFile>,
    gnss_file: Option<GnssFile>,
    truth_file: Option<TruthFile>,
}

/// `[truth_file]`: the reference's format and where it is.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct TruthFile {
    format: Option<String>,
    quality: Option<Vec<u8>>,
    at: Option<String>,
}

/// The reference's format.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum TruthFormat {
    /// The navigation format (position, velocity, attitude).
    #[default]
    Nav,
    /// RTKLIB `.pos` of a better receiver: position only.
    Rtklib {
        /// The accepted `Q` flags.
        quality: Vec<u8>,
    },
}

/// How the reference is read and compared.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TruthSettings {
    /// Its format.
    pub format: TruthFormat,
    /// Whether its positions are the GNSS antenna's (else the IMU's): the
    /// solution is then moved by the lever arm before comparing.
    pub at_antenna: bool,
}

/// `[gnss_file]`: the GNSS file's format.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct GnssFile {
    format: Option<String>,
    quality: Option<Vec<u8>>,
}

/// The GNSS file's format.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum GnssFormat {
    /// The GINS text format (7 or 13 columns).
    #[default]
    Gins,
    /// RTKLIB `.pos`, keeping the fixes whose quality flag `Q` is listed.
    Rtklib {
        /// The accepted `Q` values (1 fix, 2 float, 3 SBAS, 4 DGPS, 5 single,
        /// 6 PPP).
        quality: Vec<u8>,
    },
}

/// `[imu_file]`: how the IMU file is laid out (default: the GINS format).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ImuFile {
    delimiter: Option<String>,
    header_lines: Option<usize>,
    columns: Option<ImuColumns>,
    time: Option<String>,
    leap_seconds: Option<f64>,
    measures: Option<String>,
    gyro_unit: Option<String>,
    accel_unit: Option<String>,
    g: Option<f64>,
    axes: Option<[String; 3]>,
    mounting: Option<Exact<3>>,
}

/// `[imu_file.columns]`, 1-based.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ImuColumns {
    time: usize,
    week: Option<usize>,
    gyro: [usize; 3],
    accel: [usize; 3],
    odometer: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Initial {
    #[serde(default)]
    week: u32,
    time: f64,
    position: Option<V3>,
    velocity: Option<V3>,
    attitude: Option<V3>,
    /// Known sensor errors at the start (values, not σ): removed from the
    /// readings from the first sample; the filter estimates what is left.
    gyro_bias: Option<V3>,
    accel_bias: Option<V3>,
    gyro_scale: Option<V3>,
    accel_scale: Option<V3>,
    std: InitialStd,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct InitialStd {
    attitude: V3,
    velocity: V3,
    position: V3,
    #[serde(default)]
    gyro_bias: V3,
    #[serde(default)]
    gyro_markov: V3,
    #[serde(default)]
    accel_bias: V3,
    #[serde(default)]
    odometer_scale: f64,
    #[serde(default)]
    gyro_scale: V3,
    #[serde(default)]
    accel_scale: V3,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Imu {
    gyro_arw: Option<f64>,
    gyro_arw_deg_per_s_per_sqrt_hz: Option<f64>,
    gyro_bias_rw: Option<f64>,
    accel_bias_rw: Option<f64>,
    accel_vrw: Option<f64>,
    accel_vrw_ug_per_sqrt_hz: Option<f64>,
    gyro_bias: Option<Refused>,
    accel_bias: Option<Refused>,
    #[serde(default)]
    gyro_markov_sigma: f64,
    gyro_markov_tau: Option<f64>,
    #[serde(default)]
    accel_markov_sigma: f64,
    accel_markov_tau: Option<f64>,
    gyro_scale: Option<Refused>,
    accel_scale: Option<Refused>,
    scale_tau: Option<f64>,
    gyro_scale_sigma: Option<f64>,
    accel_scale_sigma: Option<f64>,
    max_gap: Option<f64>,
    long_gap: Option<String>,
}

/// `[filter]`: the error model, the covariance interval and the lever arm;
/// every other key is the filter kind's ([`read_kind`]). Read key by key
/// (not with `serde(flatten)`), so a wrong type keeps its line and column.
#[derive(Debug, Default)]
struct Filter {
    error_model: Option<String>,
    covariance_interval: Option<f64>,
    lever_arm: V3,
    kind: Keys,
}

impl<'de> Deserialize<'de> for Filter {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Table;
        impl<'de> serde::de::Visitor<'de> for Table {
            type Value = Filter;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("the [filter] table")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Filter, A::Error> {
                let mut out = Filter::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "error_model" => out.error_model = Some(map.next_value()?),
                        "covariance_interval" => out.covariance_interval = Some(map.next_value()?),
                        "lever_arm" => out.lever_arm = map.next_value()?,
                        _ => {
                            let value = map.next_value()?;
                            out.kind.insert(key, value);
                        }
                    }
                }
                Ok(out)
            }
        }
        d.deserialize_map(Table)
    }
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Gnss {
    noise: Option<String>,
    position_std: Option<V3>,
    velocity_std: Option<V3>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Odometer {
    rate: f64,
    speed_std: f64,
    nhc_std: f64,
    #[serde(default)]
    mounting: Exact<2>,
    #[serde(default)]
    lever_arm: V3,
    scale_tau: f64,
    scale_sigma: f64,
}

/// The highest pseudo-measurement rate accepted, Hz (an update per IMU
/// sample of a 10 kHz IMU).
const MAX_RATE: f64 = 10_000.0;

/// `[alignment]`: the initial attitude from the data.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Alignment {
    static_time: f64,
    yaw: String,
    min_speed: Option<f64>,
    gyro_bias: Option<bool>,
    max_accel_std: Option<f64>,
}

/// `[nhc]`: the non-holonomic constraint without an odometer.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Nhc {
    rate: f64,
    std: Exact<2>,
    #[serde(default)]
    mounting: Exact<2>,
    #[serde(default)]
    lever_arm: V3,
}

/// `[zupt]`: zero-velocity (and zero-angular-rate) updates at detected
/// standstill.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Zupt {
    window: Option<f64>,
    accel_std: f64,
    gyro_std: f64,
    rate: f64,
    velocity_std: f64,
    #[serde(default)]
    angular_rate_std: f64,
    max_speed: Option<f64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Output {
    interval: Option<f64>,
    position_axes: Option<String>,
}

/// Where the GNSS `R` comes from: `Reported` is `noise = "file"` (the σ
/// each line of the GNSS file reports).
pub use crate::experiment::GnssNoise;

/// Odometer aiding (the IMU file's 8th column).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometerSettings {
    /// Update rate, Hz: updates at the IMU samples reaching `k / rate` s.
    pub rate: f64,
    /// σ of the forward speed, m/s.
    pub speed_std: f64,
    /// σ of the non-holonomic constraints, m/s.
    pub nhc_std: f64,
    /// Mounting pitch and yaw of the odometer against the IMU, rad.
    pub mounting: [f64; 2],
    /// The odometer's reference point from the IMU, body
    /// forward-right-down, m.
    pub lever_arm: Vector3<f64>,
    /// Steady-state σ of the scale-factor Markov process (ratio).
    pub scale_sigma: f64,
}

/// Where the initial yaw comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum YawSource {
    /// The course of the first GNSS fix faster than `min_speed`: the run
    /// starts there (position and velocity from the fix).
    GnssCourse,
    /// The horizontal Earth rate in the levelled gyro readings of the
    /// static window (a gyro whose bias is well below the Earth rate); the
    /// run starts at the end of the window.
    Gyrocompass,
}

/// The automatic initial alignment (`[alignment]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlignmentSettings {
    /// Seconds after `initial.time` the vehicle stands still: roll and
    /// pitch from the mean specific force (levelling).
    pub static_time: f64,
    /// The yaw's source.
    pub yaw: YawSource,
    /// GNSS horizontal speed for the course, m/s.
    pub min_speed: f64,
    /// Whether the static window's mean rate less the Earth rate becomes
    /// the initial gyro bias (course alignment only).
    pub gyro_bias: bool,
    /// The static window is refused when the specific force's spread
    /// exceeds this, m/s².
    pub max_accel_std: f64,
}

/// The non-holonomic constraint (`[nhc]`): a ground vehicle's lateral
/// and vertical velocity are zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NhcSettings {
    /// Update rate, Hz.
    pub rate: f64,
    /// σ of the lateral and vertical velocity, m/s.
    pub std: [f64; 2],
    /// The vehicle frame's pitch and yaw against the IMU, rad.
    pub mounting: [f64; 2],
    /// The constrained point (rear-axle centre) from the IMU, body
    /// forward-right-down, m.
    pub lever_arm: Vector3<f64>,
}

/// Zero-velocity / zero-angular-rate updates at standstill (`[zupt]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZuptSettings {
    /// Detection window, s.
    pub window: f64,
    /// Standstill when the specific force's spread over the window is
    /// below this, m/s² …
    pub accel_std: f64,
    /// … and the angular rate's below this, rad/s.
    pub gyro_std: f64,
    /// Update rate while standing, Hz.
    pub rate: f64,
    /// σ of the zero velocity, m/s.
    pub velocity_std: f64,
    /// σ of the zero angular rate, rad/s (0: no zero-angular-rate update).
    pub angular_rate_std: f64,
    /// Standing still needs the INS speed below this too, m/s: a smooth
    /// drive at constant velocity looks like standstill to the IMU.
    pub max_speed: f64,
}

/// A validated configuration in SI units.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The Earth model.
    pub earth: Ellipsoid,
    /// GNSS week of the output.
    pub week: u32,
    /// The initial navigation state (time in seconds of week).
    pub start: NavState,
    /// P0 as standard deviations.
    pub p0: InitialUncertainty,
    /// Known sensor errors at the start (`initial.gyro_bias`, …): the
    /// engine's first corrections.
    pub initial_imu: ImuBiases,
    /// The non-holonomic constraint without an odometer, if configured.
    pub nhc: Option<NhcSettings>,
    /// Standstill updates, if configured.
    pub zupt: Option<ZuptSettings>,
    /// The automatic alignment, if configured: `start` is then completed
    /// by [`process`](super::process) (with `yaw = "gnss-course"` its
    /// position and attitude are placeholders until then).
    pub alignment: Option<AlignmentSettings>,
    /// The filter's IMU error model.
    pub imu: ImuSpec,
    /// The error-state model.
    pub error_model: ErrorModelKind,
    /// The filter (adapter or odometer processing).
    pub kind: FilterKind,
    /// Covariance propagation interval, s.
    pub covariance_interval: f64,
    /// GNSS antenna lever arm, body forward-right-down, m.
    pub lever_arm: Vector3<f64>,
    /// GNSS `R`.
    pub gnss_noise: GnssNoise,
    /// Odometer aiding, if configured.
    pub odometer: Option<OdometerSettings>,
    /// Output interval, s (0: every IMU sample).
    pub output_interval: f64,
    /// Axes of the position errors.
    pub axes: PositionAxes,
    /// The treatment of gaps in the IMU data.
    pub timing: TimingRule,
    /// How the IMU file is laid out.
    pub imu_format: ImuFormat,
    /// The GNSS file's format.
    pub gnss_format: GnssFormat,
    /// The reference's format and point.
    pub truth: TruthSettings,
}

/// Reads and validates the configuration at `path`.
///
/// # Errors
/// [`Error::Input`] naming the file and the line and column (syntax,
/// unknown or missing key, wrong type) or the key (value out of range).
pub fn load(path: &Path) -> Result<Settings, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::file(path, format!("cannot read the file: {e}")))?;
    parse(&text, path)
}

/// As [`load`] from the text of the file.
///
/// # Errors
/// As [`load`].
///
/// ```
/// let text = "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
///     [initial.std]\nattitude = [1, 1, 1]\nvelocity = [1, 1, 1]\nposition = [1, 1, 1]\n\
///     [filter]\nkind = \"ekf\"\nrho = 0.5\n";
/// let e = kestrel_app::config::process::parse(text, "p.toml".as_ref()).unwrap_err();
/// assert_eq!(
///     e.to_string(),
///     "p.toml:11:7: key `filter.rho`: does not apply to kind = \"ekf\", which takes no parameters"
/// );
/// ```
pub fn parse(text: &str, path: &Path) -> Result<Settings, Error> {
    let source = Source::new(text, path);
    let file: File = source.parse()?;
    Check { source: &source }
        .settings(file)
        .map_err(Error::from)
}

/// Whether a σ of 0 means "none" or is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Zero {
    Absent,
    Refused,
}

fn id(x: f64) -> f64 {
    x
}

struct Check<'a> {
    source: &'a Source<'a>,
}

impl Check<'_> {
    /// The error `msg` about `key`, at its line and column.
    fn err(&self, key: &str, msg: impl Into<String>) -> InputError {
        self.source.error(key, msg)
    }

    fn finite(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite number, found {x}")))
        }
    }

    fn non_negative(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() && x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value ≥ 0, found {x}")))
        }
    }

    fn positive(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value > 0, found {x}")))
        }
    }

    /// A correlation time: positive, `inf` (or absent) for none.
    fn tau(&self, key: &str, x: Option<f64>) -> Result<f64, InputError> {
        match x {
            None => Ok(f64::INFINITY),
            Some(t) if t > 0.0 => Ok(t),
            Some(t) => Err(self.err(key, format!("expected a time > 0 s (or inf), found {t}"))),
        }
    }

    fn vec(
        &self,
        key: &str,
        v: V3,
        each: impl Fn(&Self, &str, f64) -> Result<f64, InputError>,
        unit: impl Fn(f64) -> f64,
    ) -> Result<Vector3<f64>, InputError> {
        let mut out = Vector3::zeros();
        for (i, x) in v.0.iter().enumerate() {
            out[i] = unit(each(self, &format!("{key}[{i}]"), *x)?);
        }
        Ok(out)
    }

    /// A standard deviation in the unit `unit` converts to SI: positive
    /// (or 0 when `zero` is `Absent`) with a variance in SI units that is
    /// a normal double, so it neither underflows to 0 nor overflows.
    fn sigma(
        &self,
        key: &str,
        x: f64,
        unit: fn(f64) -> f64,
        zero: Zero,
    ) -> Result<f64, InputError> {
        let si = unit(x);
        if (zero == Zero::Absent && x == 0.0) || (x > 0.0 && (si * si).is_normal()) {
            return Ok(si);
        }
        let what = match zero {
            Zero::Absent => "0 (none) or a standard deviation",
            Zero::Refused => "a standard deviation",
        };
        Err(self.err(
            key,
            format!(
                "expected {what} > 0 whose square in SI units is a normal double \
                 (neither 0 nor infinite), found {}",
                physical::show(x)
            ),
        ))
    }

    /// [`sigma`](Self::sigma) for each element of `v`.
    fn sigmas(
        &self,
        key: &str,
        v: V3,
        unit: fn(f64) -> f64,
        zero: Zero,
    ) -> Result<Vector3<f64>, InputError> {
        let mut out = Vector3::zeros();
        for (i, x) in v.0.iter().enumerate() {
            out[i] = self.sigma(&format!("{key}[{i}]"), *x, unit, zero)?;
        }
        Ok(out)
    }

    /// `x` within the physical range `range` ([`physical`]).
    fn within(
        &self,
        key: &str,
        what: &str,
        unit: &str,
        x: f64,
        range: (f64, f64),
    ) -> Result<f64, InputError> {
        match physical::outside(what, unit, x, range) {
            None => Ok(x),
            Some(m) => Err(self.err(key, m)),
        }
    }

    fn settings(&self, f: File) -> Result<Settings, InputError> {
        let i = &f.initial;
        let alignment = f
            .alignment
            .as_ref()
            .map(|a| self.alignment(a))
            .transpose()?;
        // What the alignment provides is not given, what it does not is.
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
        let start = NavState::new(
            self.non_negative("initial.time", i.time)?,
            Geodetic::new(deg(lat), deg(lon), h),
            self.vec(
                "initial.velocity",
                i.velocity.unwrap_or_default(),
                speed,
                id,
            )?,
            Euler::new(deg(roll), deg(pitch), deg(yaw)),
        );
        let s = &i.std;
        let key = |k: &str| format!("initial.std.{k}");
        let p0 = InitialUncertainty {
            attitude: self.sigmas(&key("attitude"), s.attitude, deg, Zero::Refused)?,
            velocity: self.sigmas(&key("velocity"), s.velocity, id, Zero::Refused)?,
            position: self.sigmas(&key("position"), s.position, id, Zero::Refused)?,
            gyro_bias: self.sigmas(&key("gyro_bias"), s.gyro_bias, deg_per_h, Zero::Absent)?,
            gyro_markov: self.sigmas(
                &key("gyro_markov"),
                s.gyro_markov,
                deg_per_h,
                Zero::Absent,
            )?,
            accel_bias: self.sigmas(&key("accel_bias"), s.accel_bias, ug, Zero::Absent)?,
            odometer_scale: self.sigma(
                &key("odometer_scale"),
                s.odometer_scale,
                id,
                Zero::Absent,
            )?,
            gyro_scale: self.sigmas(&key("gyro_scale"), s.gyro_scale, ppm, Zero::Absent)?,
            accel_scale: self.sigmas(&key("accel_scale"), s.accel_scale, ppm, Zero::Absent)?,
        };
        let initial_imu = self.initial_imu(i)?;
        let mut imu = self.imu(&f.imu)?;
        let odometer = f.odometer.as_ref().map(|o| self.odometer(o)).transpose()?;
        let error_model = match f.filter.error_model.as_deref().unwrap_or("ins15") {
            "ins15" => ErrorModelKind::Ins15,
            "ins18" => ErrorModelKind::Ins18,
            "ins21" => ErrorModelKind::Ins21 {
                scale_tau: match f.imu.scale_tau {
                    Some(t) => self.tau("imu.scale_tau", Some(t))?,
                    None => f64::INFINITY,
                },
            },
            "odometer16" => match &f.odometer {
                Some(o) => ErrorModelKind::Odometer16 {
                    scale_tau: self.positive("odometer.scale_tau", o.scale_tau)?,
                },
                None => {
                    return Err(self.err(
                        "filter.error_model",
                        "`odometer16` needs an [odometer] table",
                    ))
                }
            },
            other => {
                return Err(self.err(
                    "filter.error_model",
                    format!("expected `ins15`, `ins18`, `ins21` or `odometer16`, found `{other}`"),
                ))
            }
        };
        let ins21 = matches!(error_model, ErrorModelKind::Ins21 { .. });
        if !ins21 {
            let given = [
                ("initial.std.gyro_scale", p0.gyro_scale != Vector3::zeros()),
                (
                    "initial.std.accel_scale",
                    p0.accel_scale != Vector3::zeros(),
                ),
                ("imu.scale_tau", f.imu.scale_tau.is_some()),
                ("imu.gyro_scale_sigma", f.imu.gyro_scale_sigma.is_some()),
                ("imu.accel_scale_sigma", f.imu.accel_scale_sigma.is_some()),
            ];
            if let Some((k, _)) = given.iter().find(|(_, g)| *g) {
                return Err(self.err(
                    k,
                    "scale-factor errors are states of error_model = `ins21` only \
                     (a known scale-factor error is `initial.gyro_scale` / `initial.accel_scale`)",
                ));
            }
        } else {
            // The scale factors' Markov σ (with a finite `scale_tau`): as
            // given, else their initial σ (the RMS over the axes).
            let markov = [
                (
                    "imu.gyro_scale_sigma",
                    f.imu.gyro_scale_sigma,
                    p0.gyro_scale,
                ),
                (
                    "imu.accel_scale_sigma",
                    f.imu.accel_scale_sigma,
                    p0.accel_scale,
                ),
            ];
            let mut sigma = [0.0; 2];
            for (out, (key, given, initial)) in sigma.iter_mut().zip(markov) {
                *out = match given {
                    Some(_) if f.imu.scale_tau.is_none() => {
                        return Err(self.err(
                            key,
                            "a Markov σ needs `imu.scale_tau` (without it the scale \
                             factors are random constants)",
                        ))
                    }
                    Some(x) => self.sigma(key, x, ppm, Zero::Absent)?,
                    None => (initial.norm_squared() / 3.0).sqrt(),
                };
            }
            [imu.gyro_scale, imu.accel_scale] = sigma;
        }
        if odometer.is_some() && f.nhc.is_some() {
            return Err(self.err(
                "nhc",
                "the odometer update applies the non-holonomic constraint already \
                 (`odometer.nhc_std`); remove the [nhc] table",
            ));
        }
        if odometer.is_some() && !matches!(error_model, ErrorModelKind::Odometer16 { .. }) {
            return Err(self.err(
                "filter.error_model",
                "odometer aiding needs error_model = `odometer16`",
            ));
        }
        let kind = self.kind(&f.filter, error_model)?;
        let gnss_noise = match f.gnss.noise.as_deref().unwrap_or("file") {
            "file" => {
                if f.gnss.position_std.is_some() || f.gnss.velocity_std.is_some() {
                    return Err(self.err("gnss.noise", "fixed σ given but noise = `file`"));
                }
                GnssNoise::Reported
            }
            "fixed" => {
                let (Some(p), Some(v)) = (f.gnss.position_std, f.gnss.velocity_std) else {
                    return Err(
                        self.err("gnss.noise", "`fixed` needs position_std and velocity_std")
                    );
                };
                GnssNoise::Fixed {
                    position: self.sigmas("gnss.position_std", p, id, Zero::Refused)?,
                    velocity: self.sigmas("gnss.velocity_std", v, id, Zero::Refused)?,
                }
            }
            other => {
                return Err(self.err(
                    "gnss.noise",
                    format!("expected `file` or `fixed`, found `{other}`"),
                ))
            }
        };
        let axes = match f.output.position_axes.as_deref().unwrap_or("ned") {
            "ned" => PositionAxes::NorthEastDown,
            "enu" => PositionAxes::EastNorthUp,
            other => {
                return Err(self.err(
                    "output.position_axes",
                    format!("expected `ned` or `enu`, found `{other}`"),
                ))
            }
        };
        let earth = match f.earth.as_deref().unwrap_or("wgs84") {
            "wgs84" => Ellipsoid::wgs84(),
            "grs80" => Ellipsoid::grs80(),
            "krasovsky" => Ellipsoid::krasovsky(),
            other => {
                return Err(self.err(
                    "earth",
                    format!("expected `wgs84`, `grs80` or `krasovsky`, found `{other}`"),
                ))
            }
        };
        Ok(Settings {
            earth,
            week: i.week,
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
            lever_arm: self.vec("filter.lever_arm", f.filter.lever_arm, Self::finite, id)?,
            gnss_noise,
            odometer,
            output_interval: self
                .non_negative("output.interval", f.output.interval.unwrap_or(0.0))?,
            axes,
            timing: self.timing(&f.imu)?,
            imu_format: match &f.imu_file {
                Some(m) => self.imu_format(m)?,
                None => ImuFormat::default(),
            },
            gnss_format: self.gnss_format(f.gnss_file.as_ref())?,
            truth: self.truth(f.truth_file.as_ref())?,
        })
    }

    /// `[gnss_file]`: `format` (`gins`, default, or `rtklib`) and, for
    /// RTKLIB, the accepted quality flags (default all, 1 … 6).
    fn gnss_format(&self, g: Option<&GnssFile>) -> Result<GnssFormat, InputError> {
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
    fn truth(&self, t: Option<&TruthFile>) -> Result<TruthSettings, InputError> {
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
    fn imu_format(&self, m: &ImuFile) -> Result<ImuFormat, InputError> {
        let key = |k: &str| format!("imu_file.{k}");
        let delimiter = match m.delimiter.as_deref().unwrap_or("whitespace") {
            "whitespace" => Delimiter::Whitespace,
            "," => Delimiter::Char(','),
            ";" => Delimiter::Char(';'),
            "tab" => Delimiter::Char('\t'),
            other => {
                return Err(self.err(
                    &key("delimiter"),
                    format!("expected `whitespace`, `,`, `;` or `tab`, found `{other}`"),
                ))
            }
        };
        let header_lines = m.header_lines.unwrap_or(0);
        if header_lines > 1000 {
            return Err(self.err(
                &key("header_lines"),
                format!("expected at most 1000 header lines, found {header_lines}"),
            ));
        }
        // Without a columns table the GINS columns, and no odometer column
        // unless one is named.
        let mut f = ImuFormat {
            delimiter,
            header_lines,
            odometer: None,
            ..ImuFormat::default()
        };
        if let Some(c) = &m.columns {
            let mut all = vec![("time", c.time)];
            all.extend(c.week.map(|w| ("week", w)));
            all.extend(c.gyro.iter().map(|&g| ("gyro", g)));
            all.extend(c.accel.iter().map(|&a| ("accel", a)));
            all.extend(c.odometer.map(|o| ("odometer", o)));
            for (name, col) in &all {
                if *col == 0 || *col > 64 {
                    return Err(self.err(
                        &key(&format!("columns.{name}")),
                        format!("expected a column number from 1 to 64, found {col}"),
                    ));
                }
            }
            for (i, (name, col)) in all.iter().enumerate() {
                if let Some((other, _)) = all[..i].iter().find(|(_, c)| c == col) {
                    return Err(self.err(
                        &key(&format!("columns.{name}")),
                        format!("column {col} is already the {other} column"),
                    ));
                }
            }
            f.time = c.time - 1;
            f.week = c.week.map(|w| w - 1);
            f.gyro = c.gyro.map(|g| g - 1);
            f.accel = c.accel.map(|a| a - 1);
            f.odometer = c.odometer.map(|o| o - 1);
        }
        f.time_base = match m.time.as_deref().unwrap_or("seconds-of-week") {
            "seconds-of-week" => TimeBase::SecondsOfWeek,
            "week-seconds" => TimeBase::WeekSeconds,
            "unix" => match m.leap_seconds {
                Some(l) if (0.0..=100.0).contains(&l) && l.fract() == 0.0 => {
                    TimeBase::Unix { leap_seconds: l }
                }
                Some(l) => {
                    return Err(self.err(
                        &key("leap_seconds"),
                        format!("expected whole seconds from 0 to 100 (18 since 2017), found {l}"),
                    ))
                }
                None => {
                    return Err(self.err(
                        &key("leap_seconds"),
                        "`unix` time needs leap_seconds, GPS − UTC (18 s since 2017-01-01)",
                    ))
                }
            },
            other => {
                return Err(self.err(
                    &key("time"),
                    format!(
                        "expected `seconds-of-week`, `week-seconds` or `unix`, found `{other}`"
                    ),
                ))
            }
        };
        if m.leap_seconds.is_some() && !matches!(f.time_base, TimeBase::Unix { .. }) {
            return Err(self.err(&key("leap_seconds"), "only `unix` time takes leap_seconds"));
        }
        match (f.time_base, f.week) {
            (TimeBase::WeekSeconds, None) => {
                return Err(self.err(&key("time"), "`week-seconds` needs a columns.week"))
            }
            (TimeBase::WeekSeconds, Some(_)) | (_, None) => {}
            (_, Some(_)) => {
                return Err(self.err(
                    &key("columns.week"),
                    "a week column needs time = `week-seconds`",
                ))
            }
        }
        f.measures = match m.measures.as_deref().unwrap_or("increments") {
            "increments" => Measures::Increments,
            "rates" => Measures::Rates,
            other => {
                return Err(self.err(
                    &key("measures"),
                    format!("expected `increments` or `rates`, found `{other}`"),
                ))
            }
        };
        let rates = f.measures == Measures::Rates;
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
                    &key("gyro_unit"),
                    format!("rates need their unit: one of {}", names(&gyro_names)),
                ))
            }
            (None, false) => "rad",
            (Some(u), _) => u,
        };
        f.gyro_unit = match gyro_units.iter().find(|u| u.0 == gyro) {
            Some(u) => u.1,
            None => {
                return Err(self.err(
                    &key("gyro_unit"),
                    format!("{measures} are in {}, found `{gyro}`", names(&gyro_names)),
                ))
            }
        };
        let accel = match (m.accel_unit.as_deref(), rates) {
            (None, true) => {
                return Err(self.err(
                    &key("accel_unit"),
                    format!("rates need their unit: one of {}", names(accel_units)),
                ))
            }
            (None, false) => "m/s",
            (Some(u), _) => u,
        };
        if !accel_units.contains(&accel) {
            return Err(self.err(
                &key("accel_unit"),
                format!("{measures} are in {}, found `{accel}`", names(accel_units)),
            ));
        }
        let in_g = accel.starts_with('g');
        f.accel_unit = match (in_g, m.g) {
            (true, Some(g)) if (9.7..=9.9).contains(&g) => g,
            (true, Some(g)) => {
                return Err(self.err(
                    &key("g"),
                    format!(
                        "expected the g of the accelerometer's unit in [9.7, 9.9] m/s², found {}",
                        physical::show(g)
                    ),
                ))
            }
            (true, None) => {
                return Err(self.err(
                    &key("g"),
                    "an accelerometer unit in g needs the g value it means (9.80665 for \
                     standard gravity; a datasheet may use another)",
                ))
            }
            (false, Some(_)) => {
                return Err(self.err(&key("g"), "only an accelerometer unit in g takes g"))
            }
            (false, None) => 1.0,
        };
        if let Some(axes) = &m.axes {
            let mut mapped = [(0, 1.0); 3];
            for (i, a) in axes.iter().enumerate() {
                mapped[i] = signed_axis(a).ok_or_else(|| {
                    self.err(
                        &format!("{}[{i}]", key("axes")),
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
                return Err(self.err(&key("axes"), "each of x, y and z must appear once"));
            }
            if det < 0.0 {
                return Err(self.err(
                    &key("axes"),
                    "these axes mirror the IMU (a left-handed frame): one sign is wrong",
                ));
            }
            f.axes = mapped;
        }
        if let Some(mt) = &m.mounting {
            let [r, p, y] = mt.0;
            let k = key("mounting");
            let r = self.within(&format!("{k}[0]"), "a roll", "deg", r, (-180.0, 180.0))?;
            let p = self.within(&format!("{k}[1]"), "a pitch", "deg", p, (-90.0, 90.0))?;
            let y = self.within(&format!("{k}[2]"), "a yaw", "deg", y, (-180.0, 360.0))?;
            f.mounting = Some(Euler::new(deg(r), deg(p), deg(y)));
        }
        Ok(f)
    }

    /// `[imu] max_gap` (s, > 0, default 1) and `long_gap` (`"error"`,
    /// the default, or `"coast"`).
    fn timing(&self, m: &Imu) -> Result<TimingRule, InputError> {
        let default = TimingRule::default();
        let max_gap = self.positive("imu.max_gap", m.max_gap.unwrap_or(default.max_gap))?;
        let long_gap = match m.long_gap.as_deref() {
            None | Some("error") => LongGap::Error,
            Some("coast") => LongGap::Coast,
            Some(other) => {
                return Err(self.err(
                    "imu.long_gap",
                    format!("expected `error` or `coast`, found `{other}`"),
                ))
            }
        };
        Ok(TimingRule { max_gap, long_gap })
    }

    /// `initial.gyro_bias` (°/h), `accel_bias` (µg), `gyro_scale`,
    /// `accel_scale` (ppm): known sensor errors, within physical bounds.
    fn initial_imu(&self, i: &Initial) -> Result<ImuBiases, InputError> {
        let bounded = |key: &str, v: Option<V3>, unit: fn(f64) -> f64, name: (&str, &str, f64)| {
            let Some(v) = v else {
                return Ok(Vector3::zeros());
            };
            let (what, unit_name, limit) = name;
            self.vec(
                &format!("initial.{key}"),
                v,
                |c: &Self, k: &str, x: f64| c.within(k, what, unit_name, x, (-limit, limit)),
                unit,
            )
        };
        let scale = ("a scale-factor error", "ppm", 100_000.0);
        Ok(ImuBiases {
            gyro: bounded(
                "gyro_bias",
                i.gyro_bias,
                deg_per_h,
                ("a gyro bias", "°/h", 36_000.0),
            )?,
            accel: bounded(
                "accel_bias",
                i.accel_bias,
                ug,
                ("an accelerometer bias", "µg", 200_000.0),
            )?,
            gyro_scale: bounded("gyro_scale", i.gyro_scale, ppm, scale)?,
            accel_scale: bounded("accel_scale", i.accel_scale, ppm, scale)?,
        })
    }

    fn imu(&self, m: &Imu) -> Result<ImuSpec, InputError> {
        let use_p0 = |sensor: &str, unit: &str| {
            format!(
                "not used by `process`: the filter's initial {sensor} bias σ is \
                 `initial.std.{sensor}_bias` ({unit}) and a drifting bias is \
                 `imu.{sensor}_markov_sigma` / `imu.{sensor}_markov_tau`"
            )
        };
        let no_state = "not used by `process`: the filter's scale-factor σ is \
                        `initial.std.gyro_scale` / `accel_scale` (ppm, error_model = `ins21`) \
                        and a known scale-factor error is `initial.gyro_scale` / `accel_scale`";
        let refused = [
            (
                "imu.gyro_bias",
                m.gyro_bias.is_some(),
                use_p0("gyro", "°/h"),
            ),
            (
                "imu.accel_bias",
                m.accel_bias.is_some(),
                use_p0("accel", "µg"),
            ),
            (
                "imu.gyro_scale",
                m.gyro_scale.is_some(),
                no_state.to_owned(),
            ),
            (
                "imu.accel_scale",
                m.accel_scale.is_some(),
                no_state.to_owned(),
            ),
        ];
        if let Some((key, _, why)) = refused.into_iter().find(|(_, given, _)| *given) {
            return Err(self.err(key, why));
        }
        let vrw = match (m.accel_vrw, m.accel_vrw_ug_per_sqrt_hz) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    "imu.accel_vrw_ug_per_sqrt_hz",
                    "give either accel_vrw or accel_vrw_ug_per_sqrt_hz",
                ))
            }
            (Some(x), None) => self.sigma("imu.accel_vrw", x, m_s_per_sqrt_h, Zero::Absent)?,
            (None, Some(x)) => self.sigma("imu.accel_vrw_ug_per_sqrt_hz", x, ug, Zero::Absent)?,
            (None, None) => 0.0,
        };
        let z = Zero::Absent;
        let arw = match (m.gyro_arw, m.gyro_arw_deg_per_s_per_sqrt_hz) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    "imu.gyro_arw_deg_per_s_per_sqrt_hz",
                    "give either gyro_arw or gyro_arw_deg_per_s_per_sqrt_hz",
                ))
            }
            (Some(x), None) => self.sigma("imu.gyro_arw", x, deg_per_sqrt_h, z)?,
            // °/s/√Hz = °/√s.
            (None, Some(x)) => self.sigma("imu.gyro_arw_deg_per_s_per_sqrt_hz", x, deg, z)?,
            (None, None) => 0.0,
        };
        // Bias random walks, per √h in the datasheet: 1/√h = 1/60 per √s.
        let per_sqrt_h = |key: &str, x: Option<f64>, unit: fn(f64) -> f64, markov: f64| {
            let Some(x) = x else {
                return Ok(0.0);
            };
            if markov != 0.0 {
                return Err(self.err(
                    key,
                    "one bias model per sensor: a Gauss-Markov process (`*_markov_sigma`) or a \
                     random walk, not both",
                ));
            }
            self.sigma(key, x, unit, z).map(|v| v / 60.0)
        };
        Ok(ImuSpec {
            gyro_arw: arw,
            gyro_bias_rw: per_sqrt_h(
                "imu.gyro_bias_rw",
                m.gyro_bias_rw,
                deg_per_h,
                m.gyro_markov_sigma,
            )?,
            accel_bias_rw: per_sqrt_h(
                "imu.accel_bias_rw",
                m.accel_bias_rw,
                ug,
                m.accel_markov_sigma,
            )?,
            gyro_markov_sigma: self.sigma(
                "imu.gyro_markov_sigma",
                m.gyro_markov_sigma,
                deg_per_h,
                z,
            )?,
            gyro_markov_tau: self.tau("imu.gyro_markov_tau", m.gyro_markov_tau)?,
            accel_vrw: vrw,
            accel_markov_sigma: self.sigma(
                "imu.accel_markov_sigma",
                m.accel_markov_sigma,
                ug,
                z,
            )?,
            accel_markov_tau: self.tau("imu.accel_markov_tau", m.accel_markov_tau)?,
            ..ImuSpec::perfect()
        })
    }

    fn alignment(&self, a: &Alignment) -> Result<AlignmentSettings, InputError> {
        let yaw = match a.yaw.as_str() {
            "gnss-course" => YawSource::GnssCourse,
            "gyrocompass" => YawSource::Gyrocompass,
            other => {
                return Err(self.err(
                    "alignment.yaw",
                    format!("expected `gnss-course` or `gyrocompass`, found `{other}`"),
                ))
            }
        };
        if yaw == YawSource::Gyrocompass && (a.min_speed.is_some() || a.gyro_bias == Some(true)) {
            let key = if a.min_speed.is_some() {
                "alignment.min_speed"
            } else {
                "alignment.gyro_bias"
            };
            return Err(self.err(
                key,
                "not used by `gyrocompass` (the static rate is the Earth rate it measures)",
            ));
        }
        Ok(AlignmentSettings {
            static_time: self.within(
                "alignment.static_time",
                "a duration",
                "s",
                self.positive("alignment.static_time", a.static_time)?,
                (0.0, 86_400.0),
            )?,
            yaw,
            min_speed: self.positive("alignment.min_speed", a.min_speed.unwrap_or(3.0))?,
            gyro_bias: a.gyro_bias.unwrap_or(yaw == YawSource::GnssCourse),
            max_accel_std: self
                .positive("alignment.max_accel_std", a.max_accel_std.unwrap_or(0.1))?,
        })
    }

    fn nhc(&self, n: &Nhc) -> Result<NhcSettings, InputError> {
        Ok(NhcSettings {
            rate: self.within(
                "nhc.rate",
                "an update rate",
                "Hz",
                self.positive("nhc.rate", n.rate)?,
                (0.0, MAX_RATE),
            )?,
            std: [
                self.sigma("nhc.std[0]", n.std.0[0], id, Zero::Refused)?,
                self.sigma("nhc.std[1]", n.std.0[1], id, Zero::Refused)?,
            ],
            mounting: [
                deg(self.within(
                    "nhc.mounting[0]",
                    "a pitch",
                    "deg",
                    n.mounting.0[0],
                    (-90.0, 90.0),
                )?),
                deg(self.within(
                    "nhc.mounting[1]",
                    "a yaw",
                    "deg",
                    n.mounting.0[1],
                    (-180.0, 360.0),
                )?),
            ],
            lever_arm: self.vec("nhc.lever_arm", n.lever_arm, Self::finite, id)?,
        })
    }

    fn zupt(&self, z: &Zupt) -> Result<ZuptSettings, InputError> {
        Ok(ZuptSettings {
            window: self.within(
                "zupt.window",
                "a duration",
                "s",
                self.positive("zupt.window", z.window.unwrap_or(1.0))?,
                (0.0, 3_600.0),
            )?,
            accel_std: self.positive("zupt.accel_std", z.accel_std)?,
            gyro_std: deg(self.positive("zupt.gyro_std", z.gyro_std)?),
            rate: self.within(
                "zupt.rate",
                "an update rate",
                "Hz",
                self.positive("zupt.rate", z.rate)?,
                (0.0, MAX_RATE),
            )?,
            velocity_std: self.sigma("zupt.velocity_std", z.velocity_std, id, Zero::Refused)?,
            angular_rate_std: self.sigma(
                "zupt.angular_rate_std",
                z.angular_rate_std,
                deg,
                Zero::Absent,
            )?,
            max_speed: self.positive("zupt.max_speed", z.max_speed.unwrap_or(0.5))?,
        })
    }

    fn odometer(&self, o: &Odometer) -> Result<OdometerSettings, InputError> {
        Ok(OdometerSettings {
            rate: self.positive("odometer.rate", o.rate)?,
            speed_std: self.sigma("odometer.speed_std", o.speed_std, id, Zero::Refused)?,
            nhc_std: self.sigma("odometer.nhc_std", o.nhc_std, id, Zero::Refused)?,
            mounting: [
                deg(self.within(
                    "odometer.mounting[0]",
                    "a pitch",
                    "deg",
                    o.mounting.0[0],
                    (-90.0, 90.0),
                )?),
                deg(self.within(
                    "odometer.mounting[1]",
                    "a yaw",
                    "deg",
                    o.mounting.0[1],
                    (-180.0, 360.0),
                )?),
            ],
            lever_arm: self.vec("odometer.lever_arm", o.lever_arm, Self::finite, id)?,
            scale_sigma: self.sigma("odometer.scale_sigma", o.scale_sigma, id, Zero::Absent)?,
        })
    }

    fn kind(&self, f: &Filter, model: ErrorModelKind) -> Result<FilterKind, InputError> {
        let kind = read_kind(&f.kind, "filter", Some("ekf"), Kinds::Engine)
            .map_err(|b| self.err(&b.key, b.message))?;
        let odometer = matches!(model, ErrorModelKind::Odometer16 { .. });
        let name = kind.name();
        if kind.is_odometer() && !odometer {
            return Err(self.err(
                "filter.kind",
                format!("`{name}` needs error_model = `odometer16`"),
            ));
        }
        if odometer && !(kind.is_odometer() || kind == FilterKind::Standard) {
            return Err(self.err(
                "filter.kind",
                format!(
                    "`odometer16` runs `ekf`, `max-threshold` or `fuzzy-adaptive`, not `{name}`"
                ),
            ));
        }
        Ok(kind)
    }
}
