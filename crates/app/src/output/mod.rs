//! CSV output of per-epoch errors.
//!
//! One row per aiding epoch, columns named with their units (see
//! [`epoch_columns`]). Numbers are written in the shortest form that
//! parses back to the same `f64` (`0.1`, `2.0`, `1e-300`); non-finite
//! values as `NaN`, `inf`, `-inf`; `rejected` and `inflated` as integers.

mod epochs;

use std::path::Path;

use crate::experiment::{EpochRecord, PositionAxes};

pub use epochs::{epoch_columns, EpochCsvWriter, UPDATE_COLUMN};

use crate::Error;

/// Writes `records` of one filter as CSV with a header to `path`.
///
/// # Errors
/// [`Error::Io`] if the file cannot be written.
///
/// ```
/// use kestrel_app::output::write_epochs_csv;
/// use kestrel_app::experiment::{Adaptation, EpochRecord, PositionAxes};
/// use kestrel::nav::nalgebra::Vector3;
/// let r = EpochRecord { time: 1.0, position: Vector3::new(1.0, 2.0, 3.0),
///     velocity: Vector3::zeros(), attitude: Vector3::zeros(), adaptation: Adaptation::default(), position_nees: None };
/// let path = std::env::temp_dir().join("kestrel-doc-epochs.csv");
/// write_epochs_csv(&path, PositionAxes::EastNorthUp, &[r]).unwrap();
/// let text = std::fs::read_to_string(&path).unwrap();
/// assert!(text.starts_with("time_s,pos_east_m,pos_north_m,pos_up_m,"));
/// assert!(text.lines().nth(1).unwrap().starts_with("1.0,2.0,1.0,-3.0,"));
/// ```
pub fn write_epochs_csv(
    path: &Path,
    axes: PositionAxes,
    records: &[EpochRecord],
) -> Result<(), Error> {
    let io = |e| Error::io(path, e);
    let file = std::fs::File::create(path).map_err(io)?;
    let mut w = EpochCsvWriter::new(std::io::BufWriter::new(file), axes).map_err(io)?;
    for r in records {
        w.write(r).map_err(io)?;
    }
    w.finish().map_err(io)
}
