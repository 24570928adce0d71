//! # kestrel-nav
//!
//! Strapdown inertial navigation and its GNSS / odometer aiding on kestrel
//! filters. It will hold the Earth model, the mechanisation, the error-state
//! models and the simulation; it is empty for now.
#![deny(missing_docs)]
