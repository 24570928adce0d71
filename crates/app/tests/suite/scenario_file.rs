//! Scenario files: the shipped examples reproduce the built-in scenarios
//! exactly, and every class of bad input is reported with its file, place
//! and expectation.

use std::path::{Path, PathBuf};

use kestrel_app::config::scenario::{load, parse, to_toml};
use kestrel_app::scenario::by_name;
use kestrel_app::scenario::FilterKind;
use kestrel_app::Error as CliError;

/// The shipped example files (without `.toml`).
const EXAMPLES: [&str; 6] = [
    "paper-000",
    "paper-001",
    "paper-002",
    "paper-003",
    "paper-004",
    "custom-example",
];

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

/// The leading comment block of a file, up to the first blank line (kept
/// when regenerating).
fn header(text: &str) -> String {
    text.lines()
        .take_while(|l| l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect()
}

/// Rewrites `scenarios/paper-00X.toml` from the built-in scenarios, keeping
/// each file's header: `cargo test -p kestrel-cli --test scenario_file -- --ignored`.
#[test]
#[ignore]
fn regenerate_paper_files() {
    for n in ["000", "001", "002", "003", "004"] {
        let path = scenarios_dir().join(format!("paper-{n}.toml"));
        let old = std::fs::read_to_string(&path).unwrap_or_default();
        let body = to_toml(&by_name(n).unwrap());
        std::fs::write(&path, format!("{}{body}", header(&old))).unwrap();
    }
}

/// `paper-00X.toml` reads back as exactly the built-in scenario.
fn paper_file_equals_builtin(n: &str) {
    let path = scenarios_dir().join(format!("paper-{n}.toml"));
    let f = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let b = by_name(n).unwrap();
    let at = path.display();
    // Part by part first, so a failure names the table that drifted.
    assert_eq!(f.name, b.name, "{at}: [scenario] name");
    assert_eq!(f.description, b.description, "{at}: [scenario] description");
    assert_eq!(f.seed, b.seed, "{at}: [scenario] seed");
    assert_eq!(f.earth, b.earth, "{at}: [scenario] earth");
    assert_eq!(f.trajectory, b.trajectory, "{at}: [trajectory]");
    assert_eq!(f.imu_rate, b.imu_rate, "{at}: [imu] rate_hz");
    assert_eq!(f.imu_errors, b.imu_errors, "{at}: [imu]");
    assert_eq!(f.gnss, b.gnss, "{at}: [gnss]");
    assert_eq!(f.odometer, b.odometer, "{at}: [odometer]");
    assert_eq!(f.attitude, b.attitude, "{at}: [attitude]");
    assert_eq!(f.initial_errors, b.initial_errors, "{at}: [initial_errors]");
    assert_eq!(f.filter, b.filter, "{at}: [filter]");
    assert_eq!(f.filters, b.filters, "{at}: [[filters]]");
    assert_eq!(f, b, "{at}");
}

#[test]
fn paper_000_file_equals_builtin() {
    paper_file_equals_builtin("000");
}

#[test]
fn paper_001_file_equals_builtin() {
    paper_file_equals_builtin("001");
}

#[test]
fn paper_002_file_equals_builtin() {
    paper_file_equals_builtin("002");
}

#[test]
fn paper_003_file_equals_builtin() {
    paper_file_equals_builtin("003");
}

#[test]
fn paper_004_file_equals_builtin() {
    paper_file_equals_builtin("004");
}

/// The custom example reads, keeps its hand-written values, and writing and
/// reading it again changes nothing.
#[test]
fn custom_example_reads_and_round_trips() {
    let path = scenarios_dir().join("custom-example.toml");
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.earth, kestrel::nav::Ellipsoid::grs80());
    assert_eq!(s.filters.len(), 7);
    assert_eq!(s.trajectory.segments.len(), 10);
    // 1°/h = π/180/3600 rad/s; 0.5 mg = 0.5e-3 g₀.
    assert_eq!(s.imu_errors.gyro_bias.x, 1f64.to_radians() / 3600.0);
    assert_eq!(s.imu_errors.accel_bias.x, 0.5e-3 * 9.80665);
    assert_eq!(s.gnss.as_ref().unwrap().outages[0].end, 220.0);
    let again = parse(&to_toml(&s), Path::new("again.toml")).unwrap();
    assert_eq!(again, s);
}

/// An ellipsoid other than the three named ones is written as overrides
/// and read back exactly.
#[test]
fn other_ellipsoids_round_trip() {
    let mut s = by_name("001").unwrap();
    s.earth.a = 6_378_140.0; // IAU 1976
    s.earth.f = 1.0 / 298.257;
    let text = to_toml(&s);
    assert!(text.contains("earth_a_m = 6378140.0"), "{text}");
    assert!(!text.contains("earth_gm_m3_s2"), "{text}");
    assert_eq!(parse(&text, Path::new("iau.toml")).unwrap(), s);
}

/// The tuned scenarios (003's max threshold with windowed R, 004's
/// accelerometer Markov bias) are written and read back exactly.
#[test]
fn tuned_scenarios_round_trip() {
    for name in ["003", "004"] {
        let s = kestrel_app::scenario::tuned(name).unwrap();
        let text = to_toml(&s);
        if name == "003" {
            assert!(text.contains("window = 20"), "{text}");
        }
        assert_eq!(parse(&text, Path::new("tuned.toml")).unwrap(), s, "{name}");
    }
}

/// A small valid scenario; the bad-input tests change one line of it.
const BASE: &str = r#"[scenario]
name = "t"

[trajectory]
vehicle = "ground"
start_lat_deg = 30.0
start_lon_deg = 114.0
start_height_m = 0.0

[[trajectory.segment]]
type = "cruise"
duration_s = 10.0

[imu]
rate_hz = 100.0

[gnss]
rate_hz = 1.0
position_std_m = 3.0
velocity_std_m_s = 0.1

[filter]
error_model = "ins15"
measurement = "gnss-position-velocity"

[filter.r]
position_m = 3.0
velocity_m_s = 0.1

[[filters]]
kind = "standard"

[[filters]]
kind = "sage-husa-fading"
forgetting = 0.97
reserve = 3.0
lambda_max = 1.5

[filter.p0]
attitude_deg = 0.1
velocity_m_s = 0.1
position_m = 3.0
"#;

/// The error message for `BASE` with `from` replaced by `to`.
fn error_with(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "{from}");
    let text = BASE.replacen(from, to, 1);
    match parse(&text, Path::new("bad.toml")) {
        Ok(_) => panic!("accepted `{to}`"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn base_is_valid() {
    let s = parse(BASE, Path::new("base.toml")).unwrap();
    assert_eq!(s.filters.len(), 2);
    assert_eq!(s.imu_rate, 100.0);
}

/// Checks each `(from, to, message)`: `BASE` with `from` replaced by `to`
/// fails with exactly `message` (file:line:column: key: what is expected).
fn assert_errors(cases: &[(&str, &str, &str)]) {
    for &(from, to, expected) in cases {
        assert_eq!(
            error_with(from, to),
            expected,
            "replacing `{from}` by `{to}`"
        );
    }
}

#[test]
fn unknown_key_names_line_column_and_the_expected_keys() {
    assert_errors(&[(
        "rate_hz = 1.0",
        "rate = 1.0",
        "bad.toml:18:1: key `gnss.rate`: unknown key `rate`, expected one of `rate_hz`, \
         `position_std_m`, `velocity_std_m_s`, `lever_arm_m`, `reported_std`, \
         `noise_window`, `outlier`, `outage`",
    )]);
}

#[test]
fn wrong_type_names_line_column_and_the_expected_type() {
    assert_errors(&[
        (
            "rate_hz = 1.0",
            "rate_hz = \"fast\"",
            "bad.toml:18:11: key `gnss.rate_hz`: invalid type: string \"fast\", expected a number",
        ),
        (
            "position_std_m = 3.0",
            "position_std_m = [3.0, 3.0]",
            "bad.toml:19:18: key `gnss.position_std_m`: invalid length 2, expected a number \
             or an array of 3 numbers",
        ),
        (
            "kind = \"standard\"",
            "kind = \"kalman\"",
            "bad.toml:31:8: key `filters[0].kind`: unknown value `kalman`, expected one of \
             `ekf`, `sage-husa-fading`, `improved-adaptive`, `federated-ukf`, \
             `federated-sr-ukf`, `ict-erekf`, `chi-square-gate`, `max-threshold`, `fuzzy-adaptive`, \
             `strong-tracking-fading`",
        ),
    ]);
}

#[test]
fn missing_key_names_its_table() {
    assert_errors(&[(
        "rate_hz = 1.0\n",
        "",
        "bad.toml:17:1: key `gnss`: missing key `rate_hz`",
    )]);
}

#[test]
fn out_of_range_values_name_key_path_and_allowed_range() {
    assert_errors(&[
        // A negative standard deviation, pointing at the element.
        (
            "position_std_m = 3.0",
            "position_std_m = [3.0, -1.0, 3.0]",
            "bad.toml:19:24: key `gnss.position_std_m[1]`: expected a finite number ≥ 0, found -1",
        ),
        (
            "rate_hz = 100.0",
            "rate_hz = 0.0",
            "bad.toml:15:11: key `imu.rate_hz`: expected a finite number > 0, found 0",
        ),
        (
            "forgetting = 0.97",
            "forgetting = 1.2",
            "bad.toml:35:14: key `filters[1].forgetting`: expected 0 < b ≤ 1, found 1.2",
        ),
        (
            "reserve = 3.0",
            "reserve = 0.5",
            "bad.toml:36:11: key `filters[1].reserve`: expected finite and at least 1, found 0.5",
        ),
        (
            "kind = \"standard\"",
            "kind = \"ict-erekf\"\nsignificance = 0.5",
            "bad.toml:32:16: key `filters[0].significance`: expected 0.01 ≤ significance ≤ 0.15 \
             (the range the test is built for), found 0.5",
        ),
        (
            "kind = \"standard\"",
            "kind = \"fuzzy-adaptive\"\nwindow = 30",
            "bad.toml:32:10: key `filters[0].window`: expected 10, 20 or 50, found 30",
        ),
        (
            "kind = \"standard\"",
            "kind = \"max-threshold\"\nthreshold_m_s = 1.0\nwindow = 30",
            "bad.toml:33:10: key `filters[0].window`: expected 10, 20 or 50, found 30",
        ),
        (
            "duration_s = 10.0",
            "duration_s = 0.0",
            "bad.toml:12:14: key `trajectory.segment[0].duration_s`: expected a finite number > 0, \
             found 0",
        ),
        (
            "velocity_std_m_s = 0.1\n",
            "velocity_std_m_s = 0.1\n\n[[gnss.outage]]\nstart_s = 50.0\nend_s = 40.0\n",
            "bad.toml:24:9: key `gnss.outage[0].end_s`: expected a time after start_s = 50, found 40",
        ),
    ]);
}

#[test]
fn keys_that_do_not_fit_the_kind_are_rejected() {
    assert_errors(&[
        (
            "kind = \"standard\"",
            "kind = \"standard\"\nreserve = 3.0",
            "bad.toml:32:11: key `filters[0].reserve`: does not apply to kind = \"ekf\", \
             which takes no parameters",
        ),
        (
            "duration_s = 10.0",
            "duration_s = 10.0\nangle_deg = 5.0",
            "bad.toml:13:13: key `trajectory.segment[0].angle_deg`: does not apply to a \
             `cruise` segment, which takes `duration_s`",
        ),
        (
            "rate_hz = 100.0",
            "rate_hz = 100.0\naccel_bias_ug = 10.0\naccel_bias_mg = 0.01",
            "bad.toml:17:17: key `imu.accel_bias_mg`: give `accel_bias_ug` or `accel_bias_mg`, \
             not both",
        ),
    ]);
}

#[test]
fn syntax_error_names_line_and_column() {
    assert_errors(&[(
        "[gnss]",
        "[gnss",
        "bad.toml:17:6: unclosed table, expected `]`",
    )]);
}

#[test]
fn missing_file_is_named() {
    let path = scenarios_dir().join("no-such-scenario.toml");
    let e = load(&path).unwrap_err();
    assert!(matches!(e, CliError::Input(_)));
    let message = e.to_string();
    assert!(
        message.starts_with(&format!("{}: cannot read the file: ", path.display())),
        "{message}"
    );
}

/// Damaged files (every line removed in turn, every truncation on a line
/// boundary) give an error or a scenario, never a panic.
#[test]
fn damaged_files_never_panic() {
    let text = std::fs::read_to_string(scenarios_dir().join("paper-000.toml")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    for i in 0..lines.len() {
        let without: Vec<&str> = [&lines[..i], &lines[i + 1..]].concat();
        let _ = parse(&without.join("\n"), Path::new("x.toml"));
        let _ = parse(&lines[..i].join("\n"), Path::new("x.toml"));
    }
}

/// A filter parameter left out takes its documented default, in scenario
/// files as in `process` configurations (one definition,
/// `FilterKind::from_params`).
#[test]
fn missing_filter_parameters_take_their_defaults() {
    let text = BASE.replacen("lambda_max = 1.5\n", "", 1);
    let s = parse(&text, Path::new("base.toml")).unwrap();
    let FilterKind::SageHusaFading { lambda_max, .. } = s.filters[1] else {
        panic!("{:?}", s.filters[1]);
    };
    assert_eq!(lambda_max, 10.0);
    let base = parse(BASE, Path::new("base.toml")).unwrap();
    assert_ne!(base.filters[1], s.filters[1]);
}

#[test]
fn missing_parameters_and_unflyable_segments_are_named() {
    assert_errors(&[
        (
            "duration_s = 10.0\n",
            "duration_s = 10.0\n\n[[trajectory.segment]]\ntype = \"turn\"\nangle_deg = 5.0\n",
            "bad.toml:14:1: key `trajectory.segment[1]`: a `turn` segment needs exactly one of \
             `rate_deg_s`, `radius_m`",
        ),
        // Only the trajectory compiler sees this: the clock is already past 5 s.
        (
            "duration_s = 10.0\n",
            "duration_s = 10.0\n\n[[trajectory.segment]]\ntype = \"cruise_until\"\ntime_s = 5.0\n",
            "bad.toml:14:1: key `trajectory.segment[1]`: this segment cannot be flown: the end \
             time has already passed",
        ),
        (
            "name = \"t\"",
            "name = \"t\"\nearth = \"mars\"",
            "bad.toml:3:9: key `scenario.earth`: unknown value `mars`, expected one of `wgs84`, \
             `grs80`, `krasovsky`",
        ),
    ]);
}

/// `text` with every number outside strings and comments scaled by a
/// random factor in [0.8, 1) per line (shrinking keeps factors
/// like ρ ≤ 1 and γ ≥ 1 mostly valid) and rounded to 3 significant
/// digits; times (`…_s` keys), `seed` and `window` are left alone.
fn perturb(text: &str, rng: &mut impl rand::RngExt) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let (body, comment) = line.split_once(" #").unwrap_or((line, ""));
        let key = body.split('=').next().unwrap_or("").trim();
        let timed = key.ends_with("_s") && !key.ends_with("_m_s");
        let keep = body.trim_start().starts_with('#')
            || !body.contains('=')
            || body.contains('"') && key != "parts"
            || timed
            || key == "seed"
            || key == "window";
        if keep {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        let factor: f64 = rng.random_range(0.8..1.0);
        let (k, v) = body.split_once('=').unwrap();
        let chars: Vec<char> = v.chars().collect();
        let mut value = String::new();
        let mut i = 0;
        while i < chars.len() {
            let starts = chars[i].is_ascii_digit()
                || chars[i] == '-' && chars.get(i + 1).is_some_and(char::is_ascii_digit);
            let after_word = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
            if starts && !after_word {
                let start = i;
                i += 1;
                while i < chars.len() && (chars[i].is_ascii_digit() || ".eE+-".contains(chars[i])) {
                    i += 1;
                }
                let x: f64 = chars[start..i].iter().collect::<String>().parse().unwrap();
                value.push_str(&format!("{:.2e}", x * factor));
            } else {
                value.push(chars[i]);
                i += 1;
            }
        }
        out.push_str(&format!("{k}={value} #{comment}\n"));
    }
    out
}

/// Writing a scenario and reading it back is exact for any decimal inputs
/// in any unit: perturbed example files read, are written, and read again
/// as the same scenario.
#[test]
fn write_then_read_is_exact_for_perturbed_files() {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut checked = 0;
    for name in EXAMPLES {
        let text = std::fs::read_to_string(scenarios_dir().join(format!("{name}.toml"))).unwrap();
        for _ in 0..10 {
            let changed = perturb(&text, &mut rng);
            // A perturbation may leave the valid range (e.g. a latitude past
            // 90°); those are covered by the error tests.
            let Ok(s) = parse(&changed, Path::new("perturbed.toml")) else {
                continue;
            };
            let again = parse(&to_toml(&s), Path::new("written.toml")).unwrap();
            assert_eq!(again, s, "{name}");
            checked += 1;
        }
    }
    assert!(checked >= 45, "only {checked} perturbed files were valid");
}

/// Every key of the shipped examples carries a comment.
#[test]
fn every_key_in_the_examples_is_commented() {
    for name in EXAMPLES {
        let text = std::fs::read_to_string(scenarios_dir().join(format!("{name}.toml"))).unwrap();
        for (i, line) in text.lines().enumerate() {
            let key_line = !line.starts_with('#') && line.contains(" = ");
            assert!(
                !key_line || line.contains(" # "),
                "{name}.toml:{}: no comment: {line}",
                i + 1
            );
        }
    }
}

/// Extreme numbers in any value (zero, negative, huge, tiny, infinite,
/// NaN) give an error or a scenario, never a panic.
#[test]
fn extreme_values_never_panic() {
    let text = std::fs::read_to_string(scenarios_dir().join("custom-example.toml")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let Some((key, rest)) = line.split_once(" = ") else {
            continue;
        };
        if line.starts_with('#') || rest.starts_with('"') {
            continue;
        }
        for extreme in [
            "0.0",
            "-1.0",
            "1e300",
            "1e-300",
            "inf",
            "-inf",
            "nan",
            "[1e300, 0.0, -1e300]",
        ] {
            let mut changed = lines.clone();
            let replaced = format!("{key} = {extreme}");
            changed[i] = &replaced;
            let _ = parse(&changed.join("\n"), Path::new("x.toml"));
        }
    }
}

/// Values a scenario file used to accept and every run then failed on
/// (`run` still exiting 0), or ran on silently: each refused at load with
/// the key, the range and the value. `forgetting = 1` (documented as
/// valid) is accepted.
#[test]
fn values_every_run_would_fail_on_are_refused_at_load() {
    let cases = [
        (
            "name = \"t\"",
            "name = \"t\"\nearth_gm_m3_s2 = 1e-300",
            "scenario.earth_gm_m3_s2",
            "expected a value within 1 % of WGS-84's 3.986004418e14 m³/s², found 1e-300",
        ),
        (
            "name = \"t\"",
            "name = \"t\"\nearth_flattening = 0.5",
            "scenario.earth_flattening",
            "expected a number in [0, 0.01], found 0.5",
        ),
        (
            "kind = \"standard\"",
            "kind = \"federated-ukf\"\nkappa = -100",
            "filters[0].kappa",
            "expected kappa > -15 (the 15 states of the local filter: n + kappa > 0), found -100",
        ),
        (
            "error_model = \"ins15\"",
            "error_model = \"ins18\"",
            "filters[0].kind",
            "`federated-ukf` runs on the 15-state error model only; set \
             filter.error_model = \"ins15\"",
        ),
        (
            "velocity_std_m_s = 0.1\n",
            "velocity_std_m_s = 0.1\nlever_arm_m = [0.0, 1000.0, 0.0]\n",
            "gnss.lever_arm_m[1]",
            "expected a lever arm in [-100, 100] m, found 1000",
        ),
        (
            "[filter.p0]\nattitude_deg = 0.1\nvelocity_m_s = 0.1\nposition_m = 3.0",
            "[filter.p0]\nattitude_deg = 0.1\nvelocity_m_s = 0.1\nposition_m = 1e100",
            "filter.p0.position_m",
            "expected at most 10000000 in magnitude (10 000 km, anywhere on Earth), found 1e100",
        ),
        (
            "rate_hz = 100.0",
            "rate_hz = 100.0\ngyro_arw_deg_per_sqrt_h = 1e100",
            "imu.gyro_arw_deg_per_sqrt_h",
            "expected at most 100 in magnitude (100 °/√h, beyond any gyro's noise), found 1e100",
        ),
    ];
    for (from, to, key, message) in cases {
        let text = if to.contains("ins18") {
            BASE.replacen(from, to, 1).replacen(
                "kind = \"standard\"",
                "kind = \"federated-ukf\"",
                1,
            )
        } else {
            BASE.replacen(from, to, 1)
        };
        assert_ne!(text, BASE, "{from}");
        let e = match parse(&text, Path::new("bad.toml")) {
            Ok(_) => panic!("accepted `{to}`"),
            Err(e) => e.to_string(),
        };
        let tail = format!(": key `{key}`: {message}");
        assert!(e.ends_with(&tail), "`{to}`: {e}\n  expected …{tail}");
    }
    let one = BASE.replacen("forgetting = 0.97", "forgetting = 1.0", 1);
    parse(&one, Path::new("ok.toml")).unwrap();
}
