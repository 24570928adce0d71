//! A simulated measurement with the ground truth only a simulation knows.

/// A measurement as a sensor delivers it, plus whether the simulation
/// injected a fault or outlier into it (ground truth for evaluating
/// detectors; a real receiver would not know).
///
/// ```
/// use kestrel_nav::{measurement::OdometerReading};
/// use kestrel_sim::Simulated;
/// let r = Simulated { value: OdometerReading::new(0.1, 30.0), faulty: true };
/// assert_eq!(r.value.speed, 30.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Simulated<M> {
    /// The measurement.
    pub value: M,
    /// Whether a fault (odometer) or outlier (GNSS) was injected.
    pub faulty: bool,
}
