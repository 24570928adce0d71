//! Shared set-up of the aiding tests: a simulated drive, stored once as
//! exact truth and IMU increments, and seeded sensors and initial errors
//! per Monte-Carlo run.
#![allow(dead_code)]

pub mod tactical;

use kestrel_nav::engine::InitialUncertainty;
use kestrel_nav::nalgebra::{SMatrix, Vector3};
use kestrel_nav::{Ellipsoid, Geodetic, ImuIncrement, NavError, NavState};
use kestrel_sim::{Motion, Segment, Trajectory, TrajectorySpec, Vehicle};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// One truth epoch: the state at the end of the increment, the exact
/// increment and the motion (body rate over NED for lever arms, vehicle
/// axes for the odometer).
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub truth: NavState,
    pub imu: ImuIncrement,
    pub motion: Motion,
}

/// The exact samples of `spec` at `rate` Hz.
pub fn record(spec: &TrajectorySpec, earth: Ellipsoid, rate: f64) -> (NavState, Vec<Sample>) {
    let traj = Trajectory::new(spec, earth).expect("valid trajectory");
    let start = traj.initial_state();
    let mut stream = traj.stream(rate).expect("valid rate");
    let mut out = Vec::new();
    while let Some((truth, imu)) = stream.next() {
        out.push(Sample {
            truth,
            imu,
            motion: *stream.motion(),
        });
    }
    (start, out)
}

/// A drive with turns both ways, speed changes and a road grade, at about
/// 10–20 m/s, `minutes` long: a 270-second block of manoeuvres repeated as
/// far as it fits, then straight on.
pub fn drive(start: Geodetic, minutes: usize) -> TrajectorySpec {
    // (segment, its length in s: turns last |angle| / rate + the 1 s edge)
    let block = [
        (Segment::Cruise { duration: 30.0 }, 30.0),
        (Segment::turn_rate_deg(6.0, 90.0), 16.0),
        (
            Segment::Accelerate {
                accel: 1.0,
                duration: 8.0,
            },
            8.0,
        ),
        (Segment::Cruise { duration: 40.0 }, 40.0),
        (Segment::turn_rate_deg(8.0, -135.0), 17.875),
        (Segment::climb_pitch_deg(2.0, 30.0), 30.0),
        (Segment::turn_rate_deg(5.0, 45.0), 10.0),
        (
            Segment::Accelerate {
                accel: -1.0,
                duration: 8.0,
            },
            8.0,
        ),
        (Segment::Cruise { duration: 30.0 }, 30.0),
        (Segment::turn_rate_deg(6.0, 180.0), 31.0),
        (Segment::Cruise { duration: 30.0 }, 30.0),
        (Segment::turn_rate_deg(6.0, -90.0), 16.0),
    ];
    let end = (minutes * 60) as f64;
    let mut spec = TrajectorySpec::new(Vehicle::Ground, start, 0.0, 10.0);
    let mut t = 0.0;
    for (segment, length) in block.iter().cycle() {
        if t + length > end - 1.0 {
            break;
        }
        spec = spec.then(segment.clone());
        t += length;
    }
    spec.then(Segment::CruiseUntil { time: end })
}

/// A seeded normal generator.
pub struct Normal(ChaCha8Rng);

impl Normal {
    pub fn new(seed: u64) -> Self {
        Self(ChaCha8Rng::seed_from_u64(seed))
    }
    pub fn next(&mut self) -> f64 {
        StandardNormal.sample(&mut self.0)
    }
    pub fn vec3(&mut self, std: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.next() * std.x,
            self.next() * std.y,
            self.next() * std.z,
        )
    }
}

/// `truth` with navigation errors drawn from `u`.
pub fn perturb(
    earth: &Ellipsoid,
    truth: &NavState,
    u: &InitialUncertainty,
    rng: &mut Normal,
) -> NavState {
    let err = NavError {
        phi: rng.vec3(&u.att),
        dv: rng.vec3(&u.vel),
        dr: rng.vec3(&u.pos),
    };
    err.apply(earth, truth)
}

/// `eᵀ P⁻¹ e` for a 3-vector and its 3×3 covariance block.
pub fn nees3(e: &Vector3<f64>, p: &SMatrix<f64, 3, 3>) -> f64 {
    let inv = p.try_inverse().expect("positive definite block");
    (e.transpose() * inv * e)[0]
}

/// The navigation errors of `nav` and their NEES per block (attitude,
/// velocity, position) against the error-state covariance `p`.
pub fn nav_nees<const N: usize>(
    earth: &Ellipsoid,
    nav: &NavState,
    truth: &NavState,
    p: &SMatrix<f64, N, N>,
) -> [f64; 3] {
    let e = NavError::between(earth, nav, truth);
    [
        nees3(&e.phi, &p.fixed_view::<3, 3>(0, 0).into_owned()),
        nees3(&e.dv, &p.fixed_view::<3, 3>(3, 3).into_owned()),
        nees3(&e.dr, &p.fixed_view::<3, 3>(6, 6).into_owned()),
    ]
}
