//! # kestrel-adaptive
//!
//! Noise adapters for kestrel filters. The hook traits they implement
//! ([`NoiseAdapter`], [`PriorAdapter`]) live in `kestrel-core`; this crate
//! will hold the concrete schemes (Sage-Husa noise estimation, fading memory,
//! strong tracking, χ² / Huber inflation, outlier compression, fuzzy gain)
//! and federated fusion. It is empty for now.
#![no_std]
#![deny(missing_docs)]

pub use kestrel_core::adapter::{NoiseAdapter, PriorAdapter};
