//! The KF-GINS YAML configuration, read key by key into the `process`
//! configuration's own types.

use std::path::Path;

use yaml_rust2::Yaml;

use super::yaml::{list, Reader};
use super::Imported;
use crate::config::filter::Keys;
use crate::config::names::{EarthName, ErrorModelName};
use crate::config::process::schema::{
    Exact, File, Filter, Gnss, ImuColumns, ImuFile, ImuTable, Initial, Output, P0Table,
};
use crate::config::units::{DEG_PER_H, UG};
use crate::config::vec3::V3;
use crate::config::write::commented_toml;
use crate::{Error, InputError};
use kestrel_io::gins::physical;

/// The keys of a KF-GINS configuration this importer knows.
const KEYS: &[&str] = &[
    "imupath",
    "gnsspath",
    "outputpath",
    "imudatalen",
    "imudatarate",
    "starttime",
    "endtime",
    "initpos",
    "initvel",
    "initatt",
    "initgyrbias",
    "initaccbias",
    "initgyrscale",
    "initaccscale",
    "initposstd",
    "initvelstd",
    "initattstd",
    "initbgstd",
    "initbastd",
    "initsgstd",
    "initsastd",
    "imunoise",
    "antlever",
];

/// The keys of KF-GINS's `imunoise` mapping.
const NOISE_KEYS: &[&str] = &["arw", "vrw", "gbstd", "abstd", "gsstd", "asstd", "corrtime"];

/// mGal to SI (m/s²).
fn mgal(x: f64) -> f64 {
    x * 1e-5
}

/// `m` mGal in µg, the value that converts to exactly `m` mGal in SI.
fn ug_of(m: f64) -> f64 {
    UG.exact(mgal(m))
}

/// The comments beside the written keys: each KF-GINS key and value.
type Comments = Vec<(String, String)>;

/// Reads a KF-GINS configuration (`text` of the file at `path`).
///
/// # Errors
/// [`Error::Input`] naming the file and the key: YAML syntax, a missing
/// or unknown key, a wrong type, or what kestrel cannot express.
///
/// ```
/// let yaml = "imupath: imu.txt\ngnsspath: gnss.txt\noutputpath: out\nimudatalen: 7\n\
///     imudatarate: 200\nstarttime: 456300\nendtime: -1\ninitpos: [30.4, 114.4, 20.9]\n\
///     initvel: [0, 0, 0]\ninitatt: [0.85, -2.03, 185.7]\ninitgyrbias: [0, 0, 0]\n\
///     initaccbias: [0, 0, 0]\ninitgyrscale: [0, 0, 0]\ninitaccscale: [0, 0, 0]\n\
///     initposstd: [0.005, 0.004, 0.008]\ninitvelstd: [0.003, 0.004, 0.004]\n\
///     initattstd: [0.003, 0.003, 0.023]\nimunoise:\n  arw: [0.003, 0.003, 0.003]\n\
///     vrw: [0.03, 0.03, 0.03]\n  gbstd: [0.027, 0.027, 0.027]\n  abstd: [15.0, 15.0, 15.0]\n\
///     gsstd: [300.0, 300.0, 300.0]\n  asstd: [300.0, 300.0, 300.0]\n  corrtime: 4.0\n\
///     antlever: [0.136, -0.301, -0.184]\n";
/// let yaml = yaml.replace("\nvrw", "\n  vrw").replace("\ngsstd", "\n  gsstd");
/// let i = kestrel_app::import::kf_gins(&yaml, "kf-gins.yaml".as_ref(), None).unwrap();
/// assert!(i.toml.contains("accel_markov_sigma = 15.29574319466892"));
/// assert!(i.toml.contains("gyro_markov_tau = 14400.0"));
/// assert_eq!(i.warnings.len(), 2);
/// assert!(i.command.starts_with("kestrel process --imu imu.txt --gnss gnss.txt"));
/// ```
pub fn kf_gins(text: &str, path: &Path, out: Option<&Path>) -> Result<Imported, Error> {
    let docs = super::yaml::load(text, path)?;
    let Some(Yaml::Hash(root)) = docs.first() else {
        return Err(
            InputError::file(path, "expected a KF-GINS configuration (a YAML mapping)").into(),
        );
    };
    let r = Reader { path, root };
    known_keys(&r, "", KEYS)?;
    let imudatalen = supported(&r)?;
    let noise = match root.get(&Yaml::String("imunoise".into())) {
        Some(Yaml::Hash(h)) => Reader { path, root: h },
        _ => {
            return Err(r.err(
                "imunoise",
                "expected a mapping (arw, vrw, gbstd, abstd, gsstd, asstd, corrtime)",
            ));
        }
    };
    known_keys(&noise, "imunoise", NOISE_KEYS)?;
    let mut comments = Comments::new();
    let initial = initial(&r, &noise, &mut comments)?;
    let warnings = not_imported(&r, &noise, path)?;
    let imu = imu(&noise, &mut comments)?;
    let file = File {
        earth: EarthName::Wgs84,
        initial,
        imu,
        filter: filter(&r, &mut comments)?,
        gnss: Gnss::default(),
        odometer: None,
        nhc: None,
        zupt: None,
        alignment: None,
        output: Output::default(),
        imu_file: (imudatalen > 7.0).then(|| {
            comments.push((
                "imu_file.columns".into(),
                format!("imudatalen {imudatalen}: only the first 7 columns are IMU data"),
            ));
            ImuFile {
                columns: Some(ImuColumns {
                    time: 1,
                    week: None,
                    gyro: [2, 3, 4],
                    accel: [5, 6, 7],
                    odometer: None,
                }),
                ..ImuFile::default()
            }
        }),
        gnss_file: None,
        truth_file: None,
    };
    comments.push((
        "gnss.noise".into(),
        "the σ on each line of the GNSS file, as KF-GINS".into(),
    ));
    let command = command(&r, out)?;
    let _ = r.number("imudatarate")?;
    let mut header = vec![
        format!(
            "kestrel process configuration imported from the KF-GINS file {}",
            path.display()
        ),
        "Every value is converted exactly (mGal → µg, h → s); the KF-GINS key and".into(),
        "value are in the comment beside it.".into(),
    ];
    header.extend(warnings.iter().map(|w| format!("NOT IMPORTED — {w}")));
    header.push(format!("Run with:  {command}"));
    let toml = commented_toml(&file, &header, &comments).map_err(Error::Failed)?;
    // Whatever the YAML-level checks miss, `process` would refuse when it
    // reads the file: read it here, so an import never writes a
    // configuration `process` will not take.
    crate::config::process::parse(&toml, Path::new("the converted configuration")).map_err(
        |e| {
            InputError::file(
                path,
                format!("cannot be imported: a value converts outside kestrel's range ({e})"),
            )
        },
    )?;
    Ok(Imported {
        toml,
        warnings,
        command,
    })
}

/// Every key of `r` is one of `known` (`table` names the mapping).
fn known_keys(r: &Reader<'_>, table: &str, known: &[&str]) -> Result<(), Error> {
    for key in r.root.keys() {
        let name = key.as_str().unwrap_or("?");
        if !known.contains(&name) {
            return Err(if table.is_empty() {
                r.err(
                    name,
                    "not a KF-GINS key kestrel knows; remove it or convert it by hand",
                )
            } else {
                r.err_in(table, name, "not a KF-GINS noise key kestrel knows")
            });
        }
    }
    Ok(())
}

/// What kestrel cannot express is refused with the reason; returns
/// `imudatalen`.
fn supported(r: &Reader<'_>) -> Result<f64, Error> {
    let imudatalen = r.number("imudatalen")?;
    if imudatalen < 7.0 || imudatalen.fract() != 0.0 {
        return Err(r.err(
            "imudatalen",
            format!("expected 7 or more columns, found {imudatalen}"),
        ));
    }
    let endtime = r.number("endtime")?;
    if endtime != -1.0 {
        return Err(r.err(
            "endtime",
            "kestrel processes to the end of the IMU file: cut the file at the end time, \
             or set endtime: -1",
        ));
    }
    for key in ["initgyrbias", "initaccbias", "initgyrscale", "initaccscale"] {
        if r.vec3(key)?.iter().any(|v| *v != 0.0) {
            return Err(r.err(
                key,
                "kestrel starts its bias estimates at zero and has no scale-factor states: \
                 correct the IMU data by these values first, or set them to 0",
            ));
        }
    }
    Ok(imudatalen)
}

/// `[initial]` and `[initial.std]`: the start and P0 (the bias σ from
/// `initbgstd` / `initbastd`, else the noise's `gbstd` / `abstd`).
fn initial(r: &Reader<'_>, noise: &Reader<'_>, c: &mut Comments) -> Result<Initial, Error> {
    let gbstd = noise.same("imunoise", "gbstd")?;
    let abstd = noise.same("imunoise", "abstd")?;
    let bg = match r.root.get(&Yaml::String("initbgstd".into())) {
        Some(_) => r.vec3("initbgstd")?,
        None => [gbstd; 3],
    };
    let ba = match r.root.get(&Yaml::String("initbastd".into())) {
        Some(_) => r.vec3("initbastd")?,
        None => [abstd; 3],
    };
    let mut note = |key: &str, what: String| c.push((key.into(), what));
    note("initial.time", "starttime".into());
    note("initial.position", "initpos (deg, deg, m)".into());
    note("initial.velocity", "initvel (m/s, NED)".into());
    note("initial.attitude", "initatt (deg, roll pitch yaw)".into());
    note("initial.std.position", "initposstd (m)".into());
    note("initial.std.velocity", "initvelstd (m/s)".into());
    note("initial.std.attitude", "initattstd (deg)".into());
    note(
        "initial.std.gyro_bias",
        format!("initbgstd (or imunoise.gbstd) {} deg/h", list(&bg)),
    );
    note(
        "initial.std.accel_bias",
        format!("initbastd (or imunoise.abstd) {} mGal", list(&ba)),
    );
    Ok(Initial {
        week: 0,
        time: r.number("starttime")?,
        position: Some(Exact(r.vec3("initpos")?)),
        velocity: Some(Exact(r.vec3("initvel")?)),
        attitude: Some(Exact(r.vec3("initatt")?)),
        gyro_bias: None,
        accel_bias: None,
        gyro_scale: None,
        accel_scale: None,
        std: P0Table {
            attitude: Some(V3(r.vec3("initattstd")?)),
            velocity: Some(V3(r.vec3("initvelstd")?)),
            position: Some(V3(r.vec3("initposstd")?)),
            gyro_bias: Some(V3(bg)),
            accel_bias: Some(V3(ba.map(ug_of))),
            ..P0Table::default()
        },
    })
}

/// The warnings for KF-GINS's scale-factor states, which kestrel's 15-state
/// import leaves out.
fn not_imported(r: &Reader<'_>, noise: &Reader<'_>, path: &Path) -> Result<Vec<String>, Error> {
    let mut warnings = Vec::new();
    for key in ["gsstd", "asstd"] {
        if noise.same("imunoise", key)? != 0.0 {
            warnings.push(format!(
                "{}: imunoise.{key} not imported: kestrel's error models have no scale-factor \
                 states yet, so the filter runs without them (KF-GINS's 21 states become 15)",
                path.display()
            ));
        }
    }
    for key in ["initsgstd", "initsastd"] {
        if r.root.get(&Yaml::String(key.into())).is_some() && r.vec3(key)?.iter().any(|v| *v != 0.0)
        {
            warnings.push(format!(
                "{}: {key} not imported: kestrel has no scale-factor states yet",
                path.display()
            ));
        }
    }
    Ok(warnings)
}

/// `[imu]`: the noise densities and the biases' Gauss-Markov model.
fn imu(noise: &Reader<'_>, c: &mut Comments) -> Result<ImuTable, Error> {
    let corr = noise.number_in("imunoise", "corrtime")?;
    let tau = corr * 3600.0;
    let min_h = physical::CORRELATION_TIME_MIN / 3600.0;
    // Infinity (a bias held constant) is `inf` in kestrel's file; a finite
    // time whose seconds overflow is a unit mistake, not a constant.
    if !(tau >= physical::CORRELATION_TIME_MIN && (tau.is_finite() || corr.is_infinite())) {
        return Err(noise.err_in(
            "imunoise",
            "corrtime",
            format!(
                "expected a time in hours ≥ {min_h:.4e} (1 ms) whose seconds are finite, found {}",
                physical::show(corr)
            ),
        ));
    }
    let gbstd = noise.same("imunoise", "gbstd")?;
    let abstd = noise.same("imunoise", "abstd")?;
    c.push(("imu.gyro_arw".into(), "imunoise.arw (deg/√h)".into()));
    c.push(("imu.accel_vrw".into(), "imunoise.vrw (m/s/√h)".into()));
    c.push((
        "imu.gyro_markov_sigma".into(),
        "imunoise.gbstd (deg/h)".into(),
    ));
    c.push((
        "imu.gyro_markov_tau".into(),
        format!("imunoise.corrtime {corr} h"),
    ));
    c.push((
        "imu.accel_markov_sigma".into(),
        format!("imunoise.abstd {abstd} mGal"),
    ));
    c.push((
        "imu.accel_markov_tau".into(),
        format!("imunoise.corrtime {corr} h"),
    ));
    let one = |x: f64| Some(V3([x; 3]));
    Ok(ImuTable {
        gyro_arw: one(noise.same("imunoise", "arw")?),
        accel_vrw: one(noise.same("imunoise", "vrw")?),
        gyro_markov_sigma: one(DEG_PER_H.exact(DEG_PER_H.si(gbstd))),
        gyro_markov_tau: one(tau),
        accel_markov_sigma: one(ug_of(abstd)),
        accel_markov_tau: one(tau),
        ..ImuTable::default()
    })
}

/// `[filter]`: the plain EKF on the 15-state model, P propagated at every
/// sample as KF-GINS does.
fn filter(r: &Reader<'_>, c: &mut Comments) -> Result<Filter, Error> {
    c.push((
        "filter.error_model".into(),
        "KF-GINS's 21 states without the 6 scale factors".into(),
    ));
    c.push((
        "filter.covariance_interval".into(),
        "KF-GINS propagates P at every IMU sample".into(),
    ));
    c.push((
        "filter.lever_arm".into(),
        "antlever (m, forward right down)".into(),
    ));
    let mut kind = Keys::new();
    kind.insert("kind".into(), toml::Value::String("ekf".into()));
    Ok(Filter {
        error_model: ErrorModelName::Ins15,
        covariance_interval: Some(0.0),
        lever_arm: Exact(r.vec3("antlever")?),
        kind,
    })
}

/// The `kestrel process` command for the files the YAML names (KF-GINS
/// opens its paths from where it runs; so does this command), every path
/// quoted for a POSIX shell so pasting it runs that one command.
fn command(r: &Reader<'_>, out: Option<&Path>) -> Result<String, Error> {
    let config = match out {
        Some(p) => p.to_string_lossy().into_owned(),
        None => "process.toml".to_owned(),
    };
    let imu = r.path("imupath")?;
    let gnss = r.path("gnsspath")?;
    let output = r.path("outputpath")?;
    let words = [
        "kestrel", "process", "--imu", &imu, "--gnss", &gnss, "--config", &config, "--out", &output,
    ];
    shlex::try_join(words).map_err(|_| {
        Error::Failed(format!(
            "{config}: the output path has a NUL byte and cannot be written in a command"
        ))
    })
}
