//! The Rauch–Tung–Striebel (RTS) fixed-interval smoother for covariance-form
//! filters on linear or linearised models.
//!
//! A forward pass of the filter records, per epoch, the transition `Φ` into
//! the epoch, the prior `(x⁻, P⁻)` after the predict and the posterior
//! `(x⁺, P⁺)` after the epoch's updates ([`RtsEpoch`]). The backward pass
//! ([`rts_step`]) then runs from the last epoch to the first:
//!
//! ```text
//! C_k   = P⁺_k Φᵀ_{k+1} (P⁻_{k+1})⁻¹
//! xˢ_k  = x⁺_k ⊞ C_k (xˢ_{k+1} ⊟ x⁻_{k+1})
//! Pˢ_k  = A P⁺_k Aᵀ + C_k (Q̃_{k+1} + Pˢ_{k+1}) C_kᵀ,   A = I − C_k Φ_{k+1},
//!         Q̃_{k+1} = P⁻_{k+1} − Φ_{k+1} P⁺_k Φᵀ_{k+1}
//! ```
//!
//! The covariance is the algebraically equal "Joseph-like" arrangement of the
//! textbook `Pˢ_k = P⁺_k + C_k (Pˢ_{k+1} − P⁻_{k+1}) C_kᵀ`: a sum of
//! congruences of positive semi-definite matrices instead of a difference,
//! so rounding cannot make it indefinite where the textbook form subtracts
//! two nearly equal covariances (a long coast). `Q̃` is the process noise the
//! filter actually added, so a fading factor applied to the prior (which
//! inflates `P⁻`) is taken into account without recording it.
//!
//! Storage is the caller's: [`RtsRecord`] fills a slice of epochs and
//! smooths into a second slice, with no allocation; a long run can stream
//! its epochs elsewhere (a file) and call [`rts_step`] itself, epoch by
//! epoch, backwards.
//!
//! Sources: H. E. Rauch, F. Tung, C. T. Striebel, "Maximum likelihood
//! estimates of linear dynamic systems", *AIAA Journal* 3(8): 1445–1450,
//! 1965; the arrangement of the covariance recursion as in S. Särkkä,
//! *Bayesian Filtering and Smoothing*, Cambridge University Press, 2013,
//! §8.2 (Theorem 8.2), rewritten as above.
//!
//! ```
//! use kestrel_core::smoother::{RtsEpoch, RtsRecord, Smoothed};
//! use kestrel_core::{Ekf, LinearizedMeasurement, LinearizedProcess, MeasurementModel,
//!     ProcessModel, nalgebra::{Matrix1, Vector1}};
//!
//! /// A random walk, observed directly.
//! struct Walk;
//! impl ProcessModel<f64, 1> for Walk {
//!     fn propagate(&self, x: &Vector1<f64>, _dt: f64) -> Vector1<f64> { *x }
//!     fn noise(&self, _x: &Vector1<f64>, dt: f64) -> Matrix1<f64> { Matrix1::new(dt) }
//! }
//! impl LinearizedProcess<f64, 1> for Walk {
//!     fn transition(&self, _x: &Vector1<f64>, _dt: f64) -> Matrix1<f64> { Matrix1::new(1.0) }
//! }
//! struct Direct;
//! impl MeasurementModel<f64, 1, 1> for Direct {
//!     fn predict(&self, x: &Vector1<f64>) -> Vector1<f64> { *x }
//!     fn noise(&self) -> Matrix1<f64> { Matrix1::new(1.0) }
//! }
//! impl LinearizedMeasurement<f64, 1, 1> for Direct {
//!     fn jacobian(&self, _x: &Vector1<f64>) -> Matrix1<f64> { Matrix1::new(1.0) }
//! }
//!
//! let mut filter = Ekf::new(Vector1::new(0.0), Matrix1::new(1.0))?;
//! let mut storage = [RtsEpoch::default(); 3];
//! let mut record = RtsRecord::new(&mut storage);
//! record.start(&filter)?;
//! for z in [1.0, 2.0] {
//!     record.predict(&mut filter, &Walk, 1.0)?;
//!     filter.update(&Direct, &Vector1::new(z))?;
//!     record.observe(&filter)?;
//! }
//! let mut smoothed = [Smoothed::default(); 3];
//! record.smooth(&mut smoothed)?;
//! // The last epoch is the filter's own estimate; earlier ones see later data.
//! assert_eq!(smoothed[2].state, *filter.state());
//! assert!(smoothed[1].covariance[0] < record.epochs()[1].posterior_covariance[0]);
//! # Ok::<(), kestrel_core::smoother::SmootherError>(())
//! ```

mod epoch;
mod error;
mod record;
mod step;

pub use epoch::{RtsEpoch, Smoothed};
pub use error::SmootherError;
pub use record::RtsRecord;
pub use step::rts_step;
