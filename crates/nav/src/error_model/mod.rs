//! Error-state models of the inertial navigation errors.
//!
//! Error definitions (shared by every model and the feedback):
//! - φ (NED, rad): `C_b^n(computed) = (I − [φ×]) C_b^n(true)`;
//! - δv (NED, m/s): `v(computed) − v(true)`;
//! - δr (NED, m): displacement from the true to the computed position;
//! - sensor errors: `measured = true + error`, estimated and fed back.
//!
//! Models are built per propagation interval from the navigation solution
//! and the (mean) specific force: continuous `F` from [`nav_error_dynamics`]
//! and the sensor errors placed by an [`InertialLayout`], discretised by
//! [`discretise`] (second-order `Φ`, trapezoidal `Q_d`). In
//! closed loop the error state is reset to zero after each feedback, so the
//! filter's `propagate(x) = Φ x` acts on zero and only the covariance moves.

mod discrete;
mod dynamics;
mod forcing;
mod inertial;
pub mod ins15;
pub mod ins18;
pub mod ins21;

pub use discrete::{discretise, ErrorStateModel};
pub use dynamics::nav_error_dynamics;
pub use forcing::ForcingMean;
pub use inertial::InertialLayout;
pub use ins15::Ins15Model;
pub use ins18::Ins18Model;
pub use ins21::Ins21Model;
