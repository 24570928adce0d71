//! What a run keeps in memory for figures: the track, the fixes and the
//! filter's estimates over time, thinned evenly to a bounded number of
//! points.

/// The horizontal track in metres north and east of the initial position.
///
/// ```
/// let t = kestrel_app::process::Track::default();
/// assert!(t.forward.is_empty() && t.outages.is_empty());
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    /// The forward solution: (time s, north m, east m).
    pub forward: Vec<(f64, f64, f64)>,
    /// The smoothed solution (empty without smoothing).
    pub smoothed: Vec<(f64, f64, f64)>,
    /// The GNSS fixes used.
    pub fixes: Vec<(f64, f64, f64)>,
    /// The outage windows given (start, end), s of week.
    pub outages: Vec<(f64, f64)>,
}

/// One row of the filter's estimates: the sensor corrections in output
/// units and the σ of every error state.
#[derive(Clone, Debug, PartialEq)]
pub struct StateRow {
    /// Time, s of week.
    pub time: f64,
    /// The sensor-error estimates, named by [`StateTraces::estimates`].
    pub estimates: Vec<f64>,
    /// σ of every error state, named by [`StateTraces::sigmas`].
    pub sigmas: Vec<f64>,
}

/// The filter's estimates and σ per covariance epoch, as written to the
/// `*_imu_errors` and `*_std` files.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StateTraces {
    /// Names of the estimate columns, with units (e.g. `gyro_bias_x_deg_per_h`).
    pub estimates: Vec<String>,
    /// Names of the σ columns, with units, in state order.
    pub sigmas: Vec<String>,
    /// The forward filter.
    pub forward: Vec<StateRow>,
    /// The smoothed solution (empty without smoothing).
    pub smoothed: Vec<StateRow>,
}
