//! Where the sensor-error states sit in an error-state vector.

/// The positions of the sensor-error states in an `N`-dimensional error
/// state whose first nine components are always the navigation errors
/// φ (0..3), δv (3..6), δr (6..9).
///
/// Measurement models use it to fill the columns of `H` that belong to
/// sensor errors (the gyro bias in a lever-arm velocity, the odometer scale
/// factor); the engine uses it to feed the estimates back. A layout that does
/// not fit in `N` is refused at compile time where a model or an engine is
/// built with it.
///
/// ```
/// use kestrel_nav::measurement::ErrorLayout;
///
/// /// Navigation errors and a gyro bias only.
/// struct Twelve;
/// impl ErrorLayout<12> for Twelve {
///     const GYRO_BIAS: &'static [usize] = &[9];
///     const ACCEL_BIAS: &'static [usize] = &[];
/// }
/// assert_eq!(<Twelve as ErrorLayout<12>>::ODOMETER_SCALE, None);
/// ```
pub trait ErrorLayout<const N: usize> {
    /// First indices of the 3-blocks (body x, y, z, rad/s) whose sum is the
    /// gyro error: one block for a bias, two for a constant plus a Markov
    /// drift.
    const GYRO_BIAS: &'static [usize];
    /// First indices of the 3-blocks (body, m/s²) whose sum is the
    /// accelerometer error.
    const ACCEL_BIAS: &'static [usize];
    /// Index of the odometer scale-factor error (ratio), if the state has one.
    const ODOMETER_SCALE: Option<usize> = None;
    /// First index of the 3-block of gyro scale-factor errors (body,
    /// ratio), if the state has one.
    const GYRO_SCALE: Option<usize> = None;
    /// First index of the 3-block of accelerometer scale-factor errors
    /// (body, ratio), if the state has one.
    const ACCEL_SCALE: Option<usize> = None;
}

/// Whether layout `L` fits in `N` states without overlapping the navigation
/// errors; evaluated at compile time by the users of a layout.
pub(crate) const fn fits<const N: usize, L: ErrorLayout<N>>() -> bool {
    N >= 9
        && blocks_fit(L::GYRO_BIAS, N)
        && blocks_fit(L::ACCEL_BIAS, N)
        && match L::ODOMETER_SCALE {
            Some(i) => i >= 9 && i < N,
            None => true,
        }
        && match L::GYRO_SCALE {
            Some(i) => i >= 9 && i + 3 <= N,
            None => true,
        }
        && match L::ACCEL_SCALE {
            Some(i) => i >= 9 && i + 3 <= N,
            None => true,
        }
}

const fn blocks_fit(blocks: &[usize], n: usize) -> bool {
    let mut i = 0;
    while i < blocks.len() {
        if blocks[i] < 9 || blocks[i] + 3 > n {
            return false;
        }
        i += 1;
    }
    true
}
