//! The open GINS text formats: one epoch per line, whitespace-separated
//! columns, blank lines and `#` comments ignored.
//!
//! | file | columns |
//! |---|---|
//! | IMU ([`ImuReader`], [`ImuWriter`]) | GNSS seconds of week; Δθ x y z (rad); Δv x y z (m/s); body axes forward-right-down; optional 8th column odometer speed (m/s) |
//! | GNSS ([`GnssReader`], [`GnssWriter`]) | seconds of week; latitude, longitude (deg); ellipsoidal height (m); position σ north, east, down (m); optionally velocity north, east, down (m/s) and its σ (m/s) |
//! | navigation result / truth ([`NavReader`], [`NavWriter`]) | GNSS week; seconds of week; latitude, longitude (deg); height (m); velocity north, east, down (m/s); roll, pitch, yaw (deg) |
//!
//! Readers stream: they hold one line at a time in a reused buffer, so
//! memory does not depend on the length of the file. Every malformed line
//! is an [`InputError`](crate::InputError) naming the file, the line, the
//! column (field number, 1-based) and what was expected. Writers print
//! every number as Rust's shortest round-trip decimal, so a file written
//! and read again gives back bit-identical times, increments, heights,
//! velocities and σ. Angles are stored in degrees: the writer picks the
//! degrees that convert back to the same radians whenever such a double
//! exists (about nine doubles in ten), otherwise the radians come back
//! within one unit in the last place (1e-16 rad, under a nanometre).
//!
//! Time rules: IMU, GNSS and navigation times must increase; seconds of
//! week that fall back by more than half a week are a week rollover and
//! continue (604 800 s added). Gaps are not the readers' business: `kestrel
//! process` bridges IMU dropouts or refuses them by its timing rule
//! (`[imu] max_gap`, `long_gap`), and GNSS outages are normal.

mod angle;
mod gnss;
mod imu;
pub mod imu_format;
mod line;
mod nav;
mod odometer;
pub mod physical;
mod rtklib;
mod stream;
mod tail;

pub use angle::{degrees_exact, degrees_to_radians, invert_exact};
pub use gnss::{GnssReader, GnssWriter};
pub use imu::{ImuReader, ImuRecord, ImuWriter};
pub use line::{Delimiter, Fields, MAX_LINE_BYTES};
pub use nav::WEEK_SECONDS;
pub use nav::{nav_line, NavReader, NavRecord, NavWriter};
pub use odometer::{OdometerReader, SpeedRecord};
pub use rtklib::RtklibReader;
pub use tail::last_time;
