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
//! - `nav` (feature `nav`): strapdown navigation and its aiding models;
//! - `sim` (feature `sim`): simulated trajectories and sensors.
//!
//! Every feature is on by default. With `default-features = false` the
//! crate is `no_std`: the filters, models and adapters only (features
//! `autodiff` and `rand` add automatic Jacobians and sampling, with std).
//!
//! ```
//! use kestrel::{Ekf, nalgebra::{Matrix2, Vector2}};
//! let kf = Ekf::new(Vector2::new(0.0, 1.0), Matrix2::identity()).unwrap();
//! assert_eq!(kf.state()[1], 1.0);
//! ```
#![cfg_attr(
    not(any(
        feature = "nav",
        feature = "sim",
        feature = "autodiff",
        feature = "rand"
    )),
    no_std
)]
#![deny(missing_docs)]

pub use kestrel_adaptive as adaptive;
pub use kestrel_core::*;
pub use kestrel_models as models;
#[cfg(feature = "nav")]
pub use kestrel_nav as nav;
#[cfg(feature = "sim")]
pub use kestrel_sim as sim;
