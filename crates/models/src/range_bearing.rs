//! Range and bearing to a planar position.

use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector, Vector2};
use kestrel_core::{FilterError, LinearizedMeasurement, MeasurementModel, Real};

use crate::wrap_angle;

/// Range and bearing from a sensor at `s` to the planar position
/// `p = (x[ix], x[iy])` of an `N`-state:
/// `z = [‖p − s‖, atan2(p_y − s_y, p_x − s_x)] + v`, `v ~ N(0, R)`, bearing in
/// radians counter-clockwise from the x axis.
///
/// The [`residual`](MeasurementModel::residual) wraps the bearing difference
/// to `(−π, π]`. The Jacobian is analytic:
/// `∂ρ/∂p = [dx, dy] / ρ`, `∂θ/∂p = [−dy, dx] / ρ²`.
///
/// At zero range (`p = s`) the bearing is undefined: `predict` returns a
/// bearing of 0 and `jacobian` returns NaN in the two position columns, which
/// a filter refuses with `FilterError::NonFinite` (predicted measurement)
/// without changing its state.
///
/// ```
/// use kestrel_models::RangeBearing;
/// use kestrel_core::{LinearizedMeasurement, MeasurementModel,
///     nalgebra::{Matrix2, Vector2, Vector4}};
/// use core::f64::consts::PI;
/// // Position at indices 0 and 2 of [pₓ, vₓ, p_y, v_y], sensor at (1, 1).
/// let rb = RangeBearing::<f64, 4>::new(0, 2, Matrix2::new(1.0, 0.0, 0.0, 1e-4))
///     .unwrap()
///     .with_sensor(Vector2::new(1.0, 1.0));
/// let x = Vector4::new(4.0, 0.0, 5.0, 0.0);
/// let z = rb.predict(&x); // dx = 3, dy = 4
/// assert_eq!(z[0], 5.0);
/// assert!((z[1] - 4.0_f64.atan2(3.0)).abs() < 1e-15);
/// let h = rb.jacobian(&x);
/// assert_eq!((h[(0, 0)], h[(0, 2)], h[(1, 0)], h[(1, 2)], h[(0, 1)]), (0.6, 0.8, -0.16, 0.12, 0.0));
/// // The bearing innovation takes the short way round.
/// let nu = rb.residual(&Vector2::new(1.0, PI - 0.1), &Vector2::new(1.0, -PI + 0.1));
/// assert!((nu[1] + 0.2).abs() < 1e-15);
/// // Invalid indices are refused.
/// assert!(RangeBearing::<f64, 4>::new(0, 4, Matrix2::identity()).is_err());
/// assert!(RangeBearing::<f64, 4>::new(1, 1, Matrix2::identity()).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangeBearing<T: Real, const N: usize> {
    x_index: usize,
    y_index: usize,
    /// The sensor position `s` (origin by default).
    pub sensor: Vector2<T>,
    /// The measurement noise covariance `R` of `[range, bearing]`.
    pub noise: Matrix2<T>,
}

impl<T: Real, const N: usize> RangeBearing<T, N> {
    /// Range and bearing to `(x[x_index], x[y_index])` from the origin with
    /// noise `r` (checked by the filter's input contract at each update).
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"x_index"` / `"y_index"` unless
    /// both are below `N` and distinct.
    pub fn new(x_index: usize, y_index: usize, r: Matrix2<T>) -> Result<Self, FilterError> {
        if x_index >= N {
            return Err(FilterError::InvalidParameter {
                name: "x_index",
                valid: "below the state size N",
            });
        }
        if y_index >= N || y_index == x_index {
            return Err(FilterError::InvalidParameter {
                name: "y_index",
                valid: "below the state size N and different from x_index",
            });
        }
        Ok(Self {
            x_index,
            y_index,
            sensor: Vector2::zeros(),
            noise: r,
        })
    }

    /// The same model with the sensor at `position`.
    pub fn with_sensor(mut self, position: Vector2<T>) -> Self {
        self.sensor = position;
        self
    }

    /// The state indices of the position, `(x, y)`.
    pub fn position_indices(&self) -> (usize, usize) {
        (self.x_index, self.y_index)
    }

    /// `p − s`.
    fn offset(&self, x: &SVector<T, N>) -> (T, T) {
        (
            x[self.x_index] - self.sensor.x,
            x[self.y_index] - self.sensor.y,
        )
    }
}

impl<T: Real, const N: usize> MeasurementModel<T, N, 2> for RangeBearing<T, N> {
    fn predict(&self, x: &SVector<T, N>) -> Vector2<T> {
        let (dx, dy) = self.offset(x);
        Vector2::new(dx.hypot(dy), dy.atan2(dx))
    }

    fn noise(&self) -> Matrix2<T> {
        self.noise
    }

    fn residual(&self, z: &Vector2<T>, predicted: &Vector2<T>) -> Vector2<T> {
        Vector2::new(z[0] - predicted[0], wrap_angle(z[1] - predicted[1]))
    }
}

impl<T: Real, const N: usize> LinearizedMeasurement<T, N, 2> for RangeBearing<T, N> {
    fn jacobian(&self, x: &SVector<T, N>) -> SMatrix<T, 2, N> {
        let (dx, dy) = self.offset(x);
        let range = dx.hypot(dy);
        let r2 = range * range;
        // 0 / 0 = NaN at zero range: the filter's finiteness check rejects it.
        let mut h = SMatrix::zeros();
        h[(0, self.x_index)] = dx / range;
        h[(0, self.y_index)] = dy / range;
        h[(1, self.x_index)] = -dy / r2;
        h[(1, self.y_index)] = dx / r2;
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;
    use kestrel_core::nalgebra::{Vector3, Vector5};

    #[test]
    fn hand_computed_with_sensor() {
        // Sensor at (2, −1), target at (−1, −4): dx = dy = −3.
        let rb = RangeBearing::<f64, 3>::new(2, 0, Matrix2::identity())
            .unwrap()
            .with_sensor(Vector2::new(2.0, -1.0));
        let x = Vector3::new(-4.0, 9.0, -1.0);
        let z = rb.predict(&x);
        assert!((z[0] - 3.0 * 2f64.sqrt()).abs() < 1e-15);
        assert!((z[1] + 3.0 * PI / 4.0).abs() < 1e-15);
        let h = rb.jacobian(&x);
        let s = 1.0 / 2f64.sqrt();
        // ∂ρ/∂(px, py) = (−s, −s); ∂θ/∂(px, py) = (3, −3) / 18.
        assert!((h[(0, 2)] + s).abs() < 1e-15 && (h[(0, 0)] + s).abs() < 1e-15);
        assert!((h[(1, 2)] - 1.0 / 6.0).abs() < 1e-15);
        assert!((h[(1, 0)] + 1.0 / 6.0).abs() < 1e-15);
        assert_eq!((h[(0, 1)], h[(1, 1)]), (0.0, 0.0));
        assert_eq!(rb.position_indices(), (2, 0));
    }

    /// The analytic Jacobian against central differences at varied geometry,
    /// including across the ±π bearing cut (differenced through `residual`).
    #[test]
    fn jacobian_matches_central_differences() {
        let rb = RangeBearing::<f64, 5>::new(1, 3, Matrix2::identity())
            .unwrap()
            .with_sensor(Vector2::new(0.5, -0.25));
        let points = [
            Vector5::new(0.0, 3.0, 7.0, 1.0, 0.0),
            Vector5::new(0.0, -2.0, 0.0, 1e-9 - 0.25, 0.0),
            Vector5::new(0.0, -100.0, 0.0, 40.0, 0.0),
            Vector5::new(0.0, 0.6, 0.0, -0.2, 0.0),
        ];
        let step = 1e-6;
        for x in points {
            let h = rb.jacobian(&x);
            let scale = rb.predict(&x)[0];
            for j in 0..5 {
                let mut e = Vector5::zeros();
                e[j] = step * scale.max(1.0);
                let d = rb.residual(&rb.predict(&(x + e)), &rb.predict(&(x - e))) / (2.0 * e[j]);
                for i in 0..2 {
                    let tol = 1e-7 * h.row(i).norm().max(1e-12);
                    assert!(
                        (d[i] - h[(i, j)]).abs() < tol,
                        "x {x}, ({i}, {j}): {} vs {}",
                        d[i],
                        h[(i, j)]
                    );
                }
            }
        }
    }

    #[test]
    fn zero_range_is_non_finite_not_a_panic() {
        let rb = RangeBearing::<f64, 2>::new(0, 1, Matrix2::identity()).unwrap();
        let z = rb.predict(&Vector2::zeros());
        assert_eq!(z, Vector2::zeros());
        let h = rb.jacobian(&Vector2::zeros());
        assert!(h.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn residual_wraps_only_the_bearing() {
        let rb = RangeBearing::<f32, 2>::new(0, 1, Matrix2::identity()).unwrap();
        let nu = rb.residual(&Vector2::new(10.0, -3.0), &Vector2::new(2.0, 3.0));
        assert_eq!(nu[0], 8.0);
        let pi = core::f32::consts::PI;
        assert!((nu[1] - (2.0 * pi - 6.0)).abs() < 1e-6, "{}", nu[1]);
    }
}
