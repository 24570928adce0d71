//! # kestrel-models
//!
//! Reusable process and measurement models for kestrel filters, `no_std`
//! and generic over `f32` / `f64`.
#![no_std]
#![deny(missing_docs)]

mod linear;

pub use linear::{LinearMeasurement, LinearProcess};
