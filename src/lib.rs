//! # kestrel
//!
//! A generic, allocation-free state-estimation framework for integrated
//! navigation. This umbrella crate re-exports the member crates:
//!
//! - the framework itself ([`kestrel_core`], re-exported at the top level):
//!   model traits, the covariance / UKF / square-root UKF forms, the
//!   noise-adapter hook;
//! - [`models`]: reusable process and measurement models;
//! - [`adaptive`]: noise adapters;
//! - [`nav`]: strapdown navigation and its aiding models.
//!
//! ```
//! use kestrel::{Ekf, nalgebra::{Matrix2, Vector2}};
//! let kf = Ekf::new(Vector2::new(0.0, 1.0), Matrix2::identity()).unwrap();
//! assert_eq!(kf.state()[1], 1.0);
//! ```
#![no_std]
#![deny(missing_docs)]

pub use kestrel_adaptive as adaptive;
pub use kestrel_core::*;
pub use kestrel_models as models;
pub use kestrel_nav as nav;
