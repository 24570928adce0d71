//! What a run can be told besides the scenario, the filter and the seed.

/// The axes the position RMS is given in.
///
/// ```
/// use kestrel_app::experiment::{PositionAxes, RunOptions};
/// let o = RunOptions { axes: Some(PositionAxes::NorthEastDown), ..Default::default() };
/// assert_eq!(o.axes, Some(PositionAxes::NorthEastDown));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
pub enum PositionAxes {
    /// North, east, down (m); `ned` in files.
    #[default]
    #[serde(rename = "ned")]
    NorthEastDown,
    /// East, north, up (m): paper 000's longitude, latitude and height
    /// errors, and the E, N, U order of papers 002 and 004; `enu` in files.
    #[serde(rename = "enu")]
    EastNorthUp,
}

impl PositionAxes {
    /// The axes a built-in scenario's paper prints its position errors in:
    /// east, north, up for "000" (longitude, latitude, height), "002" and
    /// "004"; north, east, down otherwise.
    ///
    /// ```
    /// use kestrel_app::experiment::PositionAxes;
    /// assert_eq!(PositionAxes::for_scenario("000"), PositionAxes::EastNorthUp);
    /// assert_eq!(PositionAxes::for_scenario("003"), PositionAxes::NorthEastDown);
    /// ```
    pub fn for_scenario(name: &str) -> Self {
        match name {
            "000" | "002" | "004" => Self::EastNorthUp,
            _ => Self::NorthEastDown,
        }
    }

    /// A NED vector in these axes.
    ///
    /// ```
    /// use kestrel_app::experiment::PositionAxes;
    /// use kestrel::nalgebra::Vector3;
    /// let v = PositionAxes::EastNorthUp.from_ned(&Vector3::new(1.0, 2.0, 3.0));
    /// assert_eq!(v, Vector3::new(2.0, 1.0, -3.0));
    /// ```
    pub fn from_ned(&self, v: &kestrel::nalgebra::Vector3<f64>) -> kestrel::nalgebra::Vector3<f64> {
        match self {
            Self::NorthEastDown => *v,
            Self::EastNorthUp => kestrel::nalgebra::Vector3::new(v.y, v.x, -v.z),
        }
    }
}

/// Options of a run.
///
/// ```
/// use kestrel_app::experiment::RunOptions;
/// let o = RunOptions::default().with_duration(120.0);
/// assert_eq!(o.duration, Some(120.0));
/// assert_eq!(o.covariance_interval, 0.1);
/// assert!(o.keep_records);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunOptions {
    /// Stop after this many seconds of the trajectory (`None`: all of it).
    pub duration: Option<f64>,
    /// IMU rate override, Hz (`None`: the scenario's). Other rates give
    /// other sensor data.
    pub imu_rate: Option<f64>,
    /// Covariance propagation interval of the engine, s.
    pub covariance_interval: f64,
    /// Whether [`run`](super::run) stores the per-epoch records.
    pub keep_records: bool,
    /// Epochs before this time (s) are left out of the RMS (transient).
    pub rms_from: f64,
    /// Axes of the position RMS (`None`: the scenario's paper's, see
    /// [`PositionAxes::for_scenario`]).
    pub axes: Option<PositionAxes>,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            duration: None,
            imu_rate: None,
            covariance_interval: 0.1,
            keep_records: true,
            rms_from: 0.0,
            axes: None,
        }
    }
}

impl RunOptions {
    /// The same options stopping after `seconds`.
    ///
    /// ```
    /// let o = kestrel_app::experiment::RunOptions::default().with_duration(60.0);
    /// assert_eq!(o.duration, Some(60.0));
    /// ```
    pub fn with_duration(mut self, seconds: f64) -> Self {
        self.duration = Some(seconds);
        self
    }

    /// The same options with the IMU at `hz`.
    ///
    /// ```
    /// let o = kestrel_app::experiment::RunOptions::default().with_imu_rate(100.0);
    /// assert_eq!(o.imu_rate, Some(100.0));
    /// ```
    pub fn with_imu_rate(mut self, hz: f64) -> Self {
        self.imu_rate = Some(hz);
        self
    }

    /// The same options without stored records (the summary only).
    ///
    /// ```
    /// assert!(!kestrel_app::experiment::RunOptions::default().without_records().keep_records);
    /// ```
    pub fn without_records(mut self) -> Self {
        self.keep_records = false;
        self
    }
}
