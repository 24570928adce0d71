//! The improved adaptive filter of paper 000 (outlier compression, divergence
//! test with fading, Sage-Husa estimate of R) against a plain Kalman filter on
//! a 2-D constant-velocity target whose position sensor is four times noisier
//! than the filter assumes and now and then returns a 30σ outlier.
//! Run with `cargo run --example improved_adaptive`.
use kestrel::adaptive::ImprovedAdaptive;
use kestrel::models::{ConstantVelocity2d, Selection};
use kestrel::nalgebra::{Matrix2, Matrix4, Vector2, Vector4};
use kestrel::{Ekf, FilterError, ProcessModel};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

fn main() -> Result<(), FilterError> {
    let motion = ConstantVelocity2d::new(0.01).unwrap();
    // Position of both axes; the filter believes σ = 1 m, the truth is 2 m.
    let sensor = Selection::<f64, 4, 2>::new([0, 2], Matrix2::identity()).expect("indices below 4");
    let p0 = Matrix4::identity() * 10.0;
    let mut plain = Ekf::new(Vector4::zeros(), p0)?;
    let mut adaptive =
        Ekf::new(Vector4::zeros(), p0)?.with_adapter(ImprovedAdaptive::<f64, 2>::as_published()?);

    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut truth = Vector4::new(0.0, 1.0, 0.0, -0.5);
    let (mut se_plain, mut se_adaptive, mut steps) = (0.0, 0.0, 0);
    for k in 1..=2000 {
        truth = motion.propagate(&truth, 1.0);
        let mut noise = Vector2::new(
            rng.sample::<f64, _>(StandardNormal),
            rng.sample(StandardNormal),
        ) * 2.0;
        if k % 50 == 0 {
            noise.x += 60.0; // an outlier of 30σ
        }
        let z = Vector2::new(truth[0], truth[2]) + noise;
        plain.predict(&motion, 1.0)?;
        plain.update(&sensor, &z)?;
        adaptive.predict(&motion, 1.0)?;
        let report = adaptive.update(&sensor, &z)?;
        let (compression, fading) = report.adapters.tests;
        if k % 400 == 0 || k == 1000 {
            println!(
                "k={k:4}  compression {:.3}  fade {:.2}  R̂ diag ({:.2}, {:.2})",
                compression.factor,
                fading.fade,
                adaptive.adapter().sage_husa.estimate()[(0, 0)],
                adaptive.adapter().sage_husa.estimate()[(1, 1)],
            );
        }
        if k > 200 {
            let err = |x: &Vector4<f64>| (x[0] - truth[0]).powi(2) + (x[2] - truth[2]).powi(2);
            se_plain += err(plain.state());
            se_adaptive += err(adaptive.state());
            steps += 1;
        }
    }
    let rms = |se: f64| (se / f64::from(steps)).sqrt();
    println!(
        "position RMS after step 200: plain {:.3} m, improved adaptive {:.3} m",
        rms(se_plain),
        rms(se_adaptive)
    );
    Ok(())
}
