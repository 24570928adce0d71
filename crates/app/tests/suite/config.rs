//! The processing configuration: the shipped example, and the parameter
//! ranges against the filters'.

use std::path::Path;

use kestrel_app::scenario::FilterKind;

#[test]
fn the_shipped_example_configuration_is_valid() {
    use kestrel_app::config::process::{load, GnssNoise};
    use kestrel_app::config::units::{DEG_PER_H, DEG_PER_SQRT_H, M_S_PER_SQRT_H, UG};
    let deg_per_h = |x| DEG_PER_H.si(x);
    let deg_per_sqrt_h = |x| DEG_PER_SQRT_H.si(x);
    let m_s_per_sqrt_h = |x| M_S_PER_SQRT_H.si(x);
    let ug = |x| UG.si(x);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/process-example.toml");
    let s = load(&path).unwrap();
    assert_eq!((s.week, s.start.time), (2300, 356_400.0));
    assert_eq!(s.start.pos.lat, 30.5278f64.to_radians());
    assert_eq!(s.kind, FilterKind::IctErekf { significance: 0.05 });
    assert_eq!(s.imu.gyro_arw, deg_per_sqrt_h(0.2));
    assert_eq!(s.imu.accel_vrw, m_s_per_sqrt_h(0.1));
    assert_eq!(s.p0.gyro_bias.x, deg_per_h(10.0));
    assert_eq!(s.p0.accel_bias.z, ug(500.0));
    assert_eq!(s.imu.gyro_markov_tau, f64::INFINITY);
    assert_eq!(s.lever_arm.z, -0.8);
    assert!(matches!(s.gnss_noise, GnssNoise::Fixed { .. }));
    assert!(s.odometer.is_none());
    assert_eq!(s.output_interval, 0.0);
}

/// Every filter parameter the configuration takes has exactly the range its
/// filter accepts: a value is refused by the file if and only if building
/// the filter with it fails.
#[test]
fn filter_parameter_ranges_equal_the_filters_ranges() {
    use kestrel_app::config::process::parse;
    use kestrel_app::experiment::build_filter;
    let base = "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
                [initial.std]\nattitude = [1, 1, 1]\nvelocity = [1, 1, 1]\nposition = [1, 1, 1]\n";
    let values = [
        "-1.0", "0.0", "0.005", "0.01", "0.05", "0.15", "0.2", "0.97", "1.0", "1.5", "100.0",
        "inf", "nan",
    ];
    let params = [
        ("ict-erekf", "significance"),
        ("improved-adaptive", "significance"),
        ("improved-adaptive", "forgetting"),
        ("improved-adaptive", "reserve"),
        ("improved-adaptive", "lambda_max"),
        ("sage-husa-fading", "forgetting"),
        ("sage-husa-fading", "reserve"),
        ("sage-husa-fading", "lambda_max"),
        ("fading", "rho"),
        ("fading", "softening"),
        ("fading", "lambda_max"),
    ];
    let mut refused = 0;
    for (kind, key) in params {
        for v in values {
            let text = format!("{base}[filter]\nkind = \"{kind}\"\n{key} = {v}\n");
            let parsed = parse(&text, "p.toml".as_ref());
            // The same kind with the parameter set directly in the library.
            let x: f64 = v.parse().unwrap();
            let direct = with_param(kind, key, x);
            let built = build_filter::<6, _>(&direct, Probe).is_ok();
            assert_eq!(parsed.is_ok(), built, "{kind} {key} = {v}");
            if let Err(e) = parsed {
                refused += 1;
                let e = e.to_string();
                assert!(
                    e.starts_with("p.toml:11:")
                        && e.contains(&format!(": key `filter.{key}`: expected ")),
                    "{e}"
                );
            }
        }
    }
    // Some values of every parameter are refused, most are accepted.
    assert!(refused > 30 && refused < 100, "{refused}");
}

/// `kind` with its defaults and `key = x`.
fn with_param(kind: &str, key: &str, x: f64) -> FilterKind {
    use kestrel_app::scenario::FadeBlock;
    let p = |k: &str, d: f64| if k == key { x } else { d };
    match kind {
        "ict-erekf" => FilterKind::IctErekf {
            significance: p("significance", 0.05),
        },
        "improved-adaptive" => FilterKind::ImprovedAdaptive {
            forgetting: p("forgetting", 0.97),
            reserve: p("reserve", 1.0),
            lambda_max: p("lambda_max", 10.0),
            significance: p("significance", 0.05),
            fade_states: FadeBlock::All,
        },
        "sage-husa-fading" => FilterKind::SageHusaFading {
            forgetting: p("forgetting", 0.97),
            reserve: p("reserve", 1.0),
            lambda_max: p("lambda_max", 10.0),
            fade_states: FadeBlock::All,
        },
        _ => FilterKind::StrongTrackingFading {
            rho: p("rho", 0.95),
            softening: p("softening", 1.0),
            lambda_max: p("lambda_max", f64::INFINITY),
            fade_states: FadeBlock::All,
        },
    }
}

/// A filter loop that only builds the filter.
struct Probe;

impl kestrel_app::experiment::FilterLoop<6> for Probe {
    type Output = ();
    fn odometer_model(&self) -> bool {
        false
    }
    fn gnss<A>(self, _: A, _: kestrel_app::scenario::FadeBlock)
    where
        A: kestrel::adapter::PriorAdapter<f64>
            + kestrel::adapter::NoiseAdapter<f64, 6, Report: kestrel_app::experiment::Describe>,
    {
    }
    fn odometer<P: kestrel_app::experiment::OdometerProcessing>(self, _: P) {}
}

/// The datasheet units of the noise densities and the bias models, the
/// ground-vehicle tables and the 21-state keys, converted to SI; and the
/// combinations that make no sense refused with the key.
#[test]
fn datasheet_units_bias_models_and_constraints() {
    use kestrel_app::config::process::parse;
    use kestrel_app::config::units::{DEG_PER_H, UG};
    let deg_per_h = |x| DEG_PER_H.si(x);
    let ug = |x| UG.si(x);
    use kestrel_app::scenario::ErrorModelKind;
    let base = "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
                gyro_scale = [100, 0, -50]\n\
                [initial.std]\nattitude = [1, 1, 1]\nvelocity = [1, 1, 1]\nposition = [1, 1, 1]\n";
    // 0.01 °/s/√Hz = 0.01 °/√s = 0.6 °/√h; 6 °/h/√h = 0.1 °/h/√s.
    let text = format!(
        "{base}gyro_scale = [300, 300, 300]\naccel_scale = [200, 200, 200]\n\
         [imu]\ngyro_arw_deg_per_s_per_sqrt_hz = 0.01\ngyro_bias_rw = 6.0\naccel_bias_rw = 60.0\n\
         scale_tau = 3600\n\
         [filter]\nerror_model = \"ins21\"\n\
         [nhc]\nrate = 5\nstd = [0.2, 0.3]\nmounting = [1.0, -2.0]\n\
         [zupt]\naccel_std = 0.05\ngyro_std = 0.2\nrate = 10\nvelocity_std = 0.01\n"
    );
    let s = parse(&text, "p.toml".as_ref()).unwrap();
    assert!((s.imu.gyro_arw - 0.01f64.to_radians()).abs() < 1e-18);
    assert!((s.imu.gyro_bias_rw - deg_per_h(6.0) / 60.0).abs() < 1e-20);
    assert!((s.imu.accel_bias_rw - ug(60.0) / 60.0).abs() < 1e-20);
    assert_eq!(s.error_model, ErrorModelKind::Ins21 { scale_tau: 3600.0 });
    assert!((s.imu.gyro_scale - 300e-6).abs() < 1e-15);
    assert!((s.p0.accel_scale.y - 200e-6).abs() < 1e-15);
    assert!((s.initial_imu.gyro_scale.z + 50e-6).abs() < 1e-18);
    let n = s.nhc.unwrap();
    assert_eq!((n.rate, n.std), (5.0, [0.2, 0.3]));
    assert!((n.mounting[1] + 2f64.to_radians()).abs() < 1e-15);
    let z = s.zupt.unwrap();
    assert_eq!((z.window, z.max_speed, z.angular_rate_std), (1.0, 0.5, 0.0));
    assert!((z.gyro_std - 0.2f64.to_radians()).abs() < 1e-15);

    let refused = [
        (
            "[imu]\ngyro_arw = 0.1\ngyro_arw_deg_per_s_per_sqrt_hz = 0.01\n",
            "imu.gyro_arw_deg_per_s_per_sqrt_hz",
            "give `gyro_arw` or `gyro_arw_deg_per_s_per_sqrt_hz`, not both",
        ),
        (
            "[imu]\ngyro_markov_sigma = 1\ngyro_markov_tau = 100\ngyro_bias_rw = 1\n",
            "imu.gyro_bias_rw",
            "one bias model per sensor: a Gauss-Markov process (`*_markov_sigma`) or a random \
             walk, not both",
        ),
        (
            "[zupt]\naccel_std = 0.05\ngyro_std = 0.2\nrate = 10\nvelocity_std = 0.01\nmax_speed = 0\n",
            "zupt.max_speed",
            "expected a finite value > 0, found 0",
        ),
        (
            "[zupt]\naccel_std = 0.05\ngyro_std = 0.2\nrate = 1e308\nvelocity_std = 0.01\n",
            "zupt.rate",
            "expected an update rate in [0, 10000] Hz, found 1e308",
        ),
        (
            "[zupt]\nwindow = 1e308\naccel_std = 0.05\ngyro_std = 0.2\nrate = 10\nvelocity_std = 0.01\n",
            "zupt.window",
            "expected a duration in [0, 3600] s, found 1e308",
        ),
        (
            "[alignment]\nstatic_time = 1e308\nyaw = \"gnss-course\"\n",
            "alignment.static_time",
            "expected a duration in [0, 86400] s, found 1e308",
        ),
        (
            "[nhc]\nrate = nan\nstd = [0.1, 0.1]\n",
            "nhc.rate",
            "expected a finite value > 0, found NaN",
        ),
        (
            "[nhc]\nrate = 10\nstd = [0.1, 0.0]\n",
            "nhc.std[1]",
            "expected a standard deviation > 0 whose square in SI units is a normal double \
             (neither 0 nor infinite), found 0",
        ),
    ];
    for (extra, key, message) in refused {
        let text = format!("{base}{extra}");
        let e = parse(&text, "p.toml".as_ref()).unwrap_err().to_string();
        assert_located(&e, &text, key, message);
    }
}

/// `e` is `p.toml:LINE:COLUMN: key `key`: message` with the line that of
/// `key` (its last part, or its table's header when the key is absent).
fn assert_located(e: &str, text: &str, key: &str, message: &str) {
    let parts: Vec<&str> = e.splitn(4, ':').collect();
    assert_eq!(parts.len(), 4, "{e}");
    assert_eq!(parts[0], "p.toml", "{e}");
    assert_eq!(parts[3], format!(" key `{key}`: {message}"), "{e}");
    let line: usize = parts[1].parse().expect(e);
    let _column: usize = parts[2].parse().expect(e);
    let leaf = key.rsplit('.').next().unwrap().split('[').next().unwrap();
    let table = key.split('.').next().unwrap();
    let at = text.lines().nth(line - 1).unwrap_or("");
    assert!(
        at.contains(leaf) || at.contains(table),
        "{e}: line {line} is `{at}`"
    );
}

/// The max-threshold baseline takes an optional R window (the fuzzy
/// filter's lengths only), named in the error when refused.
#[test]
fn max_threshold_takes_an_optional_r_window() {
    use kestrel_app::config::process::parse;
    let base = "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
                [initial.std]\nattitude = [1, 1, 1]\nvelocity = [1, 1, 1]\nposition = [1, 1, 1]\n\
                [odometer]\nrate = 10.0\nspeed_std = 0.1\nnhc_std = 0.1\nscale_tau = 3600.0\nscale_sigma = 0.001\nmounting = [0.0, 0.0]\nlever_arm = [0.0, 0.0, 0.0]\n\
                [filter]\nerror_model = \"odometer16\"\nkind = \"max-threshold\"\nthreshold = 0.5\n";
    let kind = |extra: &str| parse(&format!("{base}{extra}"), "p.toml".as_ref()).map(|s| s.kind);
    assert_eq!(
        kind("").unwrap(),
        FilterKind::MaxThreshold {
            threshold: 0.5,
            r_window: None
        }
    );
    assert_eq!(
        kind("window = 20\n").unwrap(),
        FilterKind::MaxThreshold {
            threshold: 0.5,
            r_window: Some(20)
        }
    );
    let e = kind("window = 30\n").unwrap_err().to_string();
    assert_eq!(
        e,
        "p.toml:21:10: key `filter.window`: expected 10, 20 or 50, found 30"
    );
}

/// P0 is one table in both files: `[initial.std]` of a `process`
/// configuration and `[filter.p0]` of a scenario file take the same keys
/// (each quantity in any of its units, the bare key in the unit the
/// `process` documentation states) and give the same SI values, and both
/// refuse a missing or zero attitude, velocity or position σ.
#[test]
fn the_initial_uncertainty_is_one_table_in_both_files() {
    use kestrel_app::config::process::parse;
    let process = |std: &str| {
        parse(
            &format!(
                "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
                 [initial.std]\n{std}"
            ),
            "p.toml".as_ref(),
        )
        .map(|s| s.p0)
    };
    let scenario = |p0: &str| {
        let text = format!(
            "[scenario]\nname = \"t\"\n[trajectory]\nvehicle = \"ground\"\n\
             start_lat_deg = 30.0\nstart_lon_deg = 114.0\nstart_height_m = 0.0\n\
             [[trajectory.segment]]\ntype = \"cruise\"\nduration_s = 10.0\n\
             [imu]\nrate_hz = 100.0\n[gnss]\nrate_hz = 1.0\nposition_std_m = 3.0\n\
             [filter]\nerror_model = \"ins15\"\nmeasurement = \"gnss-position-velocity\"\n\
             [filter.r]\nposition_m = 3.0\nvelocity_m_s = 0.1\n[[filters]]\nkind = \"ekf\"\n\
             [filter.p0]\n{p0}"
        );
        kestrel_app::config::scenario::parse(&text, "s.toml".as_ref()).map(|s| s.filter.p0)
    };
    // The bare keys and the unit-explicit ones, mixed, in both files.
    let keys = "attitude_arcmin = [6.0, 6.0, 60.0]\nvelocity = 0.1\nposition_m = [1, 1, 2]\n\
                gyro_bias = 10.0\naccel_bias_mg = 0.5\n";
    let a = process(keys).unwrap();
    let b = scenario(keys).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.attitude.z, 1.0_f64.to_radians());
    assert_eq!(
        a.gyro_bias.x,
        kestrel_app::config::units::DEG_PER_H.si(10.0)
    );
    // Missing or zero attitude, velocity or position σ: refused in both.
    for bad in [
        "velocity = 0.1\nposition = 1.0\n",
        "attitude = 0.0\nvelocity = 0.1\nposition = 1.0\n",
    ] {
        let e = process(bad).unwrap_err().to_string();
        assert!(e.contains("key `initial.std.attitude"), "{e}");
        let e = scenario(bad).unwrap_err().to_string();
        assert!(e.contains("key `filter.p0.attitude"), "{e}");
    }
    // One quantity in two units is refused with both keys named.
    let e = process("attitude = 1.0\nattitude_deg = 1.0\nvelocity = 0.1\nposition = 1.0\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("give `attitude` or `attitude_deg`, not both"),
        "{e}"
    );
}

/// The IMU model is one table in both files: `[imu]` of a `process`
/// configuration and `[filter.imu]` of a scenario file take the same keys
/// (any of a quantity's units; the `process` documentation's bare keys) and
/// give the same model, bias random walks included; each file refuses the
/// other's keys that do not apply to it with the reason.
#[test]
fn the_imu_model_is_one_table_in_both_files() {
    use kestrel_app::config::process::parse;
    let process = |imu: &str| {
        parse(
            &format!(
                "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
                 [initial.std]\nattitude = 1\nvelocity = 1\nposition = 1\n[imu]\n{imu}"
            ),
            "p.toml".as_ref(),
        )
        .map(|s| s.imu)
    };
    let scenario = |imu: &str| {
        let text = format!(
            "[scenario]\nname = \"t\"\n[trajectory]\nvehicle = \"ground\"\n\
             start_lat_deg = 30.0\nstart_lon_deg = 114.0\nstart_height_m = 0.0\n\
             [[trajectory.segment]]\ntype = \"cruise\"\nduration_s = 10.0\n\
             [imu]\nrate_hz = 100.0\n[gnss]\nrate_hz = 1.0\nposition_std_m = 3.0\n\
             [filter]\nerror_model = \"ins15\"\nmeasurement = \"gnss-position-velocity\"\n\
             [filter.p0]\nattitude_deg = 1\nvelocity_m_s = 1\nposition_m = 1\n\
             [filter.r]\nposition_m = 3.0\nvelocity_m_s = 0.1\n[[filters]]\nkind = \"ekf\"\n\
             [filter.imu]\n{imu}"
        );
        kestrel_app::config::scenario::parse(&text, "s.toml".as_ref()).map(|s| s.filter.imu_model)
    };
    let keys = "gyro_arw_deg_per_sqrt_h = 0.1\naccel_vrw = 0.06\ngyro_markov_sigma = 0.5\n\
                gyro_markov_tau_s = 3600\naccel_bias_rw = 20\n";
    let a = process(keys).unwrap();
    assert_eq!(a, scenario(keys).unwrap());
    assert_eq!(
        a.gyro_arw,
        kestrel::nav::ImuSpec::perfect()
            .with_gyro_arw_deg_per_sqrt_h(0.1)
            .gyro_arw
    );
    assert_eq!(
        a.accel_bias_rw,
        kestrel_app::config::units::UG.si(20.0) / 60.0
    );
    // Per-file refusals, naming the key.
    let e = process("gyro_bias_deg_per_h = 1\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("key `imu.gyro_bias_deg_per_h`: not used by `process`"),
        "{e}"
    );
    let e = scenario("max_gap = 1\n").unwrap_err().to_string();
    assert!(
        e.contains("key `filter.imu.max_gap`: does not apply"),
        "{e}"
    );
    // A model differs from axis to axis only in the simulated IMU.
    let e = process("gyro_arw = [0.1, 0.1, 0.2]\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("the same on every axis"), "{e}");
}

/// Values a `process` configuration used to accept and the run failed on
/// later without naming the key, or ran on silently (impossible values):
/// each refused at load with the key, the range and the value.
#[test]
fn impossible_values_are_refused_at_load_with_the_key_and_the_range() {
    use kestrel_app::config::process::parse;
    let base = "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
                [initial.std]\nattitude = [1, 1, 1]\nvelocity = [1, 1, 1]\nposition = [1, 1, 1]\n";
    let zupt = "[zupt]\naccel_std = 0.05\ngyro_std = 0.2\nrate = 10\nvelocity_std = 0.01\n";
    let refused: Vec<(String, &str, &str)> =
        vec![
        (
            "[imu]\ngyro_markov_sigma = 1\ngyro_markov_tau = 1e-300\n".into(),
            "imu.gyro_markov_tau",
            "expected a time ≥ 0.001 s (or inf; a shorter correlation is white noise), \
             found 1e-300",
        ),
        (
            "[imu]\naccel_markov_sigma = 1\naccel_markov_tau = 1e-300\n".into(),
            "imu.accel_markov_tau",
            "expected a time ≥ 0.001 s (or inf; a shorter correlation is white noise), \
             found 1e-300",
        ),
        (
            "[imu]\nscale_tau = 1e-300\n[filter]\nerror_model = \"ins21\"\n".into(),
            "imu.scale_tau",
            "expected a time ≥ 0.001 s (or inf; a shorter correlation is white noise), \
             found 1e-300",
        ),
        (
            "[imu]\ngyro_arw = 1e100\n".into(),
            "imu.gyro_arw",
            "expected at most 100 in magnitude (100 °/√h, beyond any gyro's noise), found 1e100",
        ),
        (
            "[filter]\nlever_arm = [0, 1e308, 0]\n".into(),
            "filter.lever_arm[1]",
            "expected a lever arm in [-100, 100] m, found 1e308",
        ),
        (
            "[nhc]\nrate = 5\nstd = [0.1, 0.1]\nlever_arm = [1000, 0, 0]\n".into(),
            "nhc.lever_arm[0]",
            "expected a lever arm in [-100, 100] m, found 1000",
        ),
        (
            format!("{}accel_std = 1e300\n", zupt.replace("accel_std = 0.05\n", "")),
            "zupt.accel_std",
            "expected a standstill threshold in [0, 2] m/s², found 1e300",
        ),
        (
            format!("{}gyro_std = 1e300\n", zupt.replace("gyro_std = 0.2\n", "")),
            "zupt.gyro_std",
            "expected a standstill threshold in [0, 20] deg/s, found 1e300",
        ),
        (
            format!("{zupt}max_speed = 1e300\n"),
            "zupt.max_speed",
            "expected a standstill speed in [0, 2] m/s, found 1e300",
        ),
        (
            "[alignment]\nstatic_time = 60\nyaw = \"gnss-course\"\nmin_speed = 1e-300\n".into(),
            "alignment.min_speed",
            "expected a speed at which the GNSS course gives the heading in [1, 1000] m/s, \
             found 1e-300",
        ),
    ];
    for (extra, key, message) in &refused {
        let text = format!("{base}{extra}");
        let e = parse(&text, "p.toml".as_ref()).unwrap_err().to_string();
        assert_located(&e, &text, key, message);
    }
    // The week is a key of [initial], before [initial.std].
    let text = base.replace("time = 0\n", "time = 0\nweek = 4294967295\n");
    let e = parse(&text, "p.toml".as_ref()).unwrap_err().to_string();
    assert_located(
        &e,
        &text,
        "initial.week",
        "expected a GPS week in [0, 9999] (the full week number, not modulo 1024), \
         found 4294967295",
    );
    let text = base.replace("position = [1, 1, 1]", "position = [1e200, 1, 1]");
    let e = parse(&text, "p.toml".as_ref()).unwrap_err().to_string();
    assert!(e.contains("initial.std.position"), "{e}");
    // The bounds themselves are accepted.
    let ok = format!(
        "{base}[filter]\nlever_arm = [100, -100, 0]\n\
         [zupt]\naccel_std = 2\ngyro_std = 20\nrate = 10\nvelocity_std = 0.01\nmax_speed = 2\n"
    );
    parse(&ok, "p.toml".as_ref()).unwrap();
}
