//! Log formats for kestrel: readers and writers of the files integrated
//! navigation is done on, with every problem an [`InputError`] naming the
//! file, line and column.
//!
//! - [`gins`]: the open GINS text formats (IMU increments, GNSS fixes,
//!   navigation results, odometer speeds), RTKLIB `.pos`, and configurable
//!   IMU columns, units, axes and time bases.
//! - [`input`]: opening an input once, tallied (bytes, SHA-256) as it is
//!   read, so nothing is read twice and pipes work.
//! - [`error`]: the errors of reading and writing.
//!
//! Processing a log (configuration, alignment, filtering, smoothing,
//! evaluation) is `kestrel-app`'s; this crate only reads and writes.
//!
//! Reading the GNSS fixes of a file (a line: seconds of week, latitude and
//! longitude in degrees, height, σ north east down):
//!
//! ```
//! use kestrel_io::gins::GnssReader;
//! let text = "# sow lat lon h sn se sd\n100.0 30.5 114.3 20.0 1.0 1.0 2.0\n";
//! let mut r = GnssReader::new(text.as_bytes(), "gnss.txt".as_ref());
//! let fix = r.next().unwrap().map_err(kestrel_io::Error::from)?;
//! assert_eq!(fix.time, 100.0);
//! assert_eq!(fix.pos_std.z, 2.0);
//! assert!(r.next().is_none());
//! # Ok::<(), kestrel_io::Error>(())
//! ```

#![deny(missing_docs)]

pub mod error;
pub mod gins;
pub mod input;

pub use error::{Error, InputError, Location};
