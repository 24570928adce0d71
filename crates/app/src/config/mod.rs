//! The one configuration model of kestrel's files: the `process`
//! configuration ([`process`]) and the scenario file ([`scenario`]) read
//! the quantities they share through the same types and checks:
//!
//! - [`units`]: every datasheet unit and its conversion to SI;
//! - the filter kind's keys ([`FilterKind`](crate::scenario::FilterKind)'s
//!   names and parameters), the initial uncertainty (P0) and the IMU model
//!   tables, read by both files;
//! - one way of reporting a problem: the file, the line and column, the
//!   key path (`filters[1].reserve`) and what was expected.
//!
//! Both files are TOML read with serde; a value the types cannot hold is an
//! error at its line and column, a value out of range is an error naming
//! its key. Writers ([`scenario::to_toml`], `simulate`'s and the importers'
//! `process` configurations) write every key with a comment, each value in
//! a unit that reads back to the same bits.

pub(crate) mod check;
pub mod filter;
pub(crate) mod imu;
pub(crate) mod locate;
pub mod names;
pub(crate) mod p0;
pub mod process;
pub mod read;
pub mod scenario;
pub mod units;
pub(crate) mod vec3;
pub(crate) mod write;
