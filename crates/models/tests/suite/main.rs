//! The models' integration tests, one binary: one link, and the shared
//! filter code instantiated once instead of once per file.

mod filters;
mod noise;
