//! # kestrel-core
//!
//! The generic heart of kestrel: model traits, three update forms behind one
//! predict / update API, and the noise-adapter hook, all sized at compile
//! time with nalgebra const generics, generic over `f32` and `f64`,
//! allocation-free and `no_std`.
//!
//! - Describe a system with [`ProcessModel`] / [`MeasurementModel`] (plus
//!   [`LinearizedProcess`] / [`LinearizedMeasurement`] for the covariance
//!   form) and, for angles and other non-vector states, a [`StateSpace`].
//! - Pick a form: [`Ekf`] (covariance form, Joseph update), [`Ukf`]
//!   (unscented), [`SrUkf`] (square-root unscented). They are all
//!   [`Filter`]`<T, N, Form, Adapter>`.
//! - Add noise adapters ([`adapter`]) as a tuple, run in order; `()` is none.
//! - [`smoother`]: the Rauch–Tung–Striebel smoother over a recorded forward
//!   pass of the covariance form, in caller-provided storage.
//! - [`Filter::update`] returns an [`UpdateReport`] (innovation, NIS, what
//!   the adapters did) or a typed [`FilterError`]; on error the filter is
//!   unchanged and never holds NaN. [`Filter::update_detailed`] adds the
//!   innovation covariance and the noise used ([`UpdateDetail`]).
//!
//! ```
//! use kestrel_core::{SrUkf, MeasurementModel, ProcessModel,
//!     nalgebra::{Matrix1, Matrix2, Vector1, Vector2}};
//!
//! /// Position and velocity with white acceleration noise.
//! struct Cv;
//! impl ProcessModel<f64, 2> for Cv {
//!     fn propagate(&self, x: &Vector2<f64>, dt: f64) -> Vector2<f64> {
//!         Vector2::new(x[0] + dt * x[1], x[1])
//!     }
//!     fn noise(&self, _x: &Vector2<f64>, dt: f64) -> Matrix2<f64> {
//!         Matrix2::new(dt.powi(3) / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt) * 0.1
//!     }
//! }
//! /// Position only.
//! struct Position;
//! impl MeasurementModel<f64, 2, 1> for Position {
//!     fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> { Vector1::new(x[0]) }
//!     fn noise(&self) -> Matrix1<f64> { Matrix1::new(0.25) }
//! }
//!
//! let mut f = SrUkf::new(Vector2::zeros(), Matrix2::identity() * 10.0).unwrap();
//! for k in 1..=20 {
//!     f.predict(&Cv, 1.0).unwrap();
//!     f.update(&Position, &Vector1::new(2.0 * k as f64)).unwrap();
//! }
//! assert!((f.state()[1] - 2.0).abs() < 0.05);
//! ```
#![no_std]
#![deny(missing_docs)]

pub mod adapter;
pub mod contract;
mod error;
mod estimator;
mod filter;
pub mod form;
pub mod linalg;
mod model;
pub mod real;
mod report;
pub mod sigma;
pub mod smoother;
mod state_space;

pub use error::{FilterError, Quantity};
pub use estimator::Estimator;
pub use filter::{Ekf, Filter, SrUkf, Ukf};
pub use model::{LinearizedMeasurement, LinearizedProcess, MeasurementModel, ProcessModel};
pub use nalgebra;
pub use real::Real;
pub use report::{UpdateDetail, UpdateOutcome, UpdateReport};
pub use state_space::{Euclidean, StateSpace};

#[doc = include_str!("../REFERENCES.md")]
pub mod references {}
