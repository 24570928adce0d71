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
use crate::config::units::{DEG, DEG_PER_H, PPM, UG};
use crate::process::timing::{LongGap, TimingRule};

fn deg(x: f64) -> f64 {
    DEG.si(x)
}
fn deg_per_h(x: f64) -> f64 {
    DEG_PER_H.si(x)
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

mod check;
mod files;
pub(crate) mod schema;
mod sensors;
mod settings;

use check::Check;
use schema::File;

/// Where the GNSS `R` comes from: `Reported` is `noise = "file"` (the σ
/// each line of the GNSS file reports).
pub use crate::experiment::GnssNoise;

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
    load_recorded(path).map(|(settings, _)| settings)
}

/// As [`load`], also returning the input's record for a manifest (size,
/// hash) and the configuration resolved (the file's tables, the filter's
/// parameters with their defaults filled in) as JSON.
///
/// # Errors
/// As [`load`].
pub fn load_recorded(path: &Path) -> Result<(Settings, Recorded), Error> {
    let (text, tally) = crate::config::read::read_config(path)?;
    let source = Source::new(&text, path);
    let file: File = source.parse()?;
    let mut resolved = serde_json::to_value(&file).unwrap_or_default();
    let settings = Check { source: &source }.settings(file)?;
    if let Some(filter) = resolved.get_mut("filter").and_then(|f| f.as_object_mut()) {
        filter.insert("kind".into(), settings.kind.name().into());
        for p in settings.kind.params() {
            let value = match p.value {
                crate::scenario::ParamValue::Number(x) => serde_json::json!(x),
                crate::scenario::ParamValue::Window(w) => serde_json::json!(w),
                crate::scenario::ParamValue::Fade(b) => serde_json::json!(b.name()),
            };
            filter.insert(p.key.into(), value);
        }
    }
    Ok((settings, Recorded { tally, resolved }))
}

/// What was read of a configuration, for a manifest.
#[derive(Clone, Debug)]
pub struct Recorded {
    /// Its bytes and hash.
    pub tally: kestrel_io::input::Tally,
    /// The configuration resolved, as JSON.
    pub resolved: serde_json::Value,
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
