//! `kestrel import kf-gins FILE.yaml`: a KF-GINS configuration as the
//! equivalent, commented `process` configuration.
//!
//! KF-GINS (i2Nav, Wuhan University) states its initial accelerometer bias
//! and bias noise in mGal, correlation times in hours and scale factors in
//! ppm; kestrel's configuration takes µg and seconds. Every value is
//! converted so that kestrel's own conversion to SI gives exactly the SI
//! value KF-GINS uses (1 mGal = 1e-5 m/s² = 10 / 9.806 65 µg ≈ 1.0197 µg —
//! taking mGal for µg is a 2 % error). What kestrel cannot express yet is
//! refused with the reason, or — for KF-GINS's scale-factor states, which
//! kestrel's error models do not have — left out with a warning in the
//! file and on stderr.

use std::fmt::Write as _;
use std::path::Path;

use yaml_rust2::{Yaml, YamlLoader};

use crate::config::units::{DEG_PER_H, UG};
use crate::{Error, InputError};
use kestrel_io::gins::invert_exact;

/// The TOML and the warnings of an import.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// The `process` configuration, commented.
    pub toml: String,
    /// What was left out, one line each.
    pub warnings: Vec<String>,
    /// The `kestrel process` command for the files the YAML names.
    pub command: String,
}

/// Imports the KF-GINS configuration `file`: [`kf_gins`] on its text, and
/// the TOML written to `out` when given (an existing `out` is replaced only
/// with `force`; `out` must not be the input).
///
/// # Errors
/// [`Error`] naming the file and key of what cannot be imported, or the
/// output that cannot be written.
pub fn import_kf_gins(file: &Path, out: Option<&Path>, force: bool) -> Result<Imported, Error> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| InputError::file(file, format!("cannot read the file: {e}")))?;
    let imported = kf_gins(&text, file, out)?;
    if let Some(out) = out {
        if std::fs::symlink_metadata(out).is_ok() && !force {
            return Err(Error::Failed(format!(
                "refusing to overwrite {}: it exists (pass --force to replace it)",
                out.display()
            )));
        }
        if out == file {
            return Err(Error::Failed(format!(
                "refusing to write {}: it is the input",
                out.display()
            )));
        }
        std::fs::write(out, &imported.toml).map_err(|e| Error::io(out, e))?;
    }
    Ok(imported)
}

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

/// mGal to SI (m/s²).
fn mgal(x: f64) -> f64 {
    x * 1e-5
}

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
    let docs = YamlLoader::load_from_str(text).map_err(|e| {
        InputError::at(
            path,
            e.marker().line(),
            e.marker().col() + 1,
            e.info().to_owned(),
        )
    })?;
    let Some(Yaml::Hash(root)) = docs.first() else {
        return Err(
            InputError::file(path, "expected a KF-GINS configuration (a YAML mapping)").into(),
        );
    };
    let r = Reader { path, root };
    for key in root.keys() {
        let name = key.as_str().unwrap_or("?");
        if !KEYS.contains(&name) {
            return Err(r.err(
                name,
                "not a KF-GINS key kestrel knows; remove it or convert it by hand",
            ));
        }
    }
    let mut warnings = Vec::new();
    let mut t = String::new();
    let _ = writeln!(
        t,
        "# kestrel process configuration imported from the KF-GINS file {}",
        path.display()
    );
    let _ = writeln!(
        t,
        "# Every value is converted exactly (mGal → µg, h → s); the KF-GINS key and"
    );
    let _ = writeln!(t, "# value are in the comment beside it.\n");

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
    let _ = writeln!(t, "[initial]");
    let _ = writeln!(
        t,
        "time = {:?}                # starttime",
        r.number("starttime")?
    );
    let _ = writeln!(
        t,
        "position = {}   # initpos (deg, deg, m)",
        list(&r.vec3("initpos")?)
    );
    let _ = writeln!(
        t,
        "velocity = {}   # initvel (m/s, NED)",
        list(&r.vec3("initvel")?)
    );
    let _ = writeln!(
        t,
        "attitude = {}   # initatt (deg, roll pitch yaw)\n",
        list(&r.vec3("initatt")?)
    );

    let noise = match root.get(&Yaml::String("imunoise".into())) {
        Some(Yaml::Hash(h)) => Reader { path, root: h },
        _ => {
            return Err(r.err(
                "imunoise",
                "expected a mapping (arw, vrw, gbstd, abstd, gsstd, asstd, corrtime)",
            ))
        }
    };
    for key in noise.root.keys() {
        let name = key.as_str().unwrap_or("?");
        if !["arw", "vrw", "gbstd", "abstd", "gsstd", "asstd", "corrtime"].contains(&name) {
            return Err(noise.err_in("imunoise", name, "not a KF-GINS noise key kestrel knows"));
        }
    }
    let gbstd = noise.same("imunoise", "gbstd")?;
    let abstd = noise.same("imunoise", "abstd")?;
    let bg = match root.get(&Yaml::String("initbgstd".into())) {
        Some(_) => r.vec3("initbgstd")?,
        None => [gbstd; 3],
    };
    let ba = match root.get(&Yaml::String("initbastd".into())) {
        Some(_) => r.vec3("initbastd")?,
        None => [abstd; 3],
    };
    let ug_of = |m: f64| invert_exact(mgal(m), mgal(m) / UG.si(1.0), UG.to_si);
    let _ = writeln!(t, "[initial.std]");
    let _ = writeln!(
        t,
        "position = {}   # initposstd (m)",
        list(&r.vec3("initposstd")?)
    );
    let _ = writeln!(
        t,
        "velocity = {}   # initvelstd (m/s)",
        list(&r.vec3("initvelstd")?)
    );
    let _ = writeln!(
        t,
        "attitude = {}   # initattstd (deg)",
        list(&r.vec3("initattstd")?)
    );
    let _ = writeln!(
        t,
        "gyro_bias = {}   # initbgstd (or imunoise.gbstd) {} deg/h",
        list(&bg),
        list(&bg)
    );
    let _ = writeln!(
        t,
        "accel_bias = {}   # initbastd (or imunoise.abstd) {} mGal\n",
        list(&ba.map(ug_of)),
        list(&ba)
    );
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
        if root.get(&Yaml::String(key.into())).is_some() && r.vec3(key)?.iter().any(|v| *v != 0.0) {
            warnings.push(format!(
                "{}: {key} not imported: kestrel has no scale-factor states yet",
                path.display()
            ));
        }
    }
    let corr = noise.number_in("imunoise", "corrtime")?;
    if corr.is_nan() || corr <= 0.0 {
        return Err(noise.err_in(
            "imunoise",
            "corrtime",
            format!("expected a time > 0 h, found {corr}"),
        ));
    }
    let tau = corr * 3600.0;
    let _ = writeln!(t, "[imu]");
    let _ = writeln!(
        t,
        "gyro_arw = {:?}   # imunoise.arw (deg/√h)",
        noise.same("imunoise", "arw")?
    );
    let _ = writeln!(
        t,
        "accel_vrw = {:?}   # imunoise.vrw (m/s/√h)",
        noise.same("imunoise", "vrw")?
    );
    let _ = writeln!(
        t,
        "gyro_markov_sigma = {:?}   # imunoise.gbstd (deg/h)",
        invert_exact(DEG_PER_H.si(gbstd), gbstd, DEG_PER_H.to_si)
    );
    let _ = writeln!(
        t,
        "gyro_markov_tau = {tau:?}   # imunoise.corrtime {corr} h"
    );
    let _ = writeln!(
        t,
        "accel_markov_sigma = {:?}   # imunoise.abstd {abstd} mGal",
        ug_of(abstd)
    );
    let _ = writeln!(
        t,
        "accel_markov_tau = {tau:?}   # imunoise.corrtime {corr} h\n"
    );
    let _ = writeln!(t, "[filter]");
    let _ = writeln!(t, "kind = \"ekf\"");
    let _ = writeln!(
        t,
        "error_model = \"ins15\"   # KF-GINS's 21 states without the 6 scale factors"
    );
    let _ = writeln!(
        t,
        "covariance_interval = 0.0   # KF-GINS propagates P at every IMU sample"
    );
    let _ = writeln!(
        t,
        "lever_arm = {}   # antlever (m, forward right down)\n",
        list(&r.vec3("antlever")?)
    );
    let _ = writeln!(t, "[gnss]");
    let _ = writeln!(
        t,
        "noise = \"file\"   # the σ on each line of the GNSS file, as KF-GINS"
    );
    if imudatalen > 7.0 {
        let _ = writeln!(
            t,
            "\n# imudatalen {imudatalen}: only the first 7 columns are IMU data"
        );
        let _ = writeln!(t, "[imu_file]");
        let _ = writeln!(
            t,
            "columns = {{ time = 1, gyro = [2, 3, 4], accel = [5, 6, 7] }}"
        );
    }
    for w in &warnings {
        let _ = writeln!(t, "\n# NOT IMPORTED — {w}");
    }
    // KF-GINS opens its paths from where it runs; so does this command.
    let config = match out {
        Some(p) => p.display().to_string(),
        None => "process.toml".to_owned(),
    };
    let command = format!(
        "kestrel process --imu {} --gnss {} --config {config} --out {}",
        r.string("imupath")?,
        r.string("gnsspath")?,
        r.string("outputpath")?
    );
    let _ = writeln!(t, "\n# Run with:\n#   {command}");
    let _ = r.number("imudatarate")?;
    Ok(Imported {
        toml: t,
        warnings,
        command,
    })
}

/// A TOML array of floats.
fn list(v: &[f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

/// Typed access to a YAML mapping with errors naming the key.
struct Reader<'a> {
    path: &'a Path,
    root: &'a yaml_rust2::yaml::Hash,
}

impl Reader<'_> {
    fn err(&self, key: &str, msg: impl Into<String>) -> Error {
        InputError::file(self.path, msg).with_key(key).into()
    }

    fn err_in(&self, table: &str, key: &str, msg: impl Into<String>) -> Error {
        self.err(&format!("{table}.{key}"), msg)
    }

    fn get(&self, key: &str) -> Result<&Yaml, Error> {
        self.root
            .get(&Yaml::String(key.into()))
            .ok_or_else(|| self.err(key, "missing"))
    }

    fn as_number(y: &Yaml) -> Option<f64> {
        match y {
            Yaml::Integer(i) => Some(*i as f64),
            Yaml::Real(_) => y.as_f64(),
            _ => None,
        }
        .filter(|v| v.is_finite())
    }

    fn number(&self, key: &str) -> Result<f64, Error> {
        Self::as_number(self.get(key)?).ok_or_else(|| self.err(key, "expected a number"))
    }

    fn number_in(&self, table: &str, key: &str) -> Result<f64, Error> {
        self.get(key)
            .ok()
            .and_then(Self::as_number)
            .ok_or_else(|| self.err_in(table, key, "expected a number"))
    }

    fn string(&self, key: &str) -> Result<String, Error> {
        self.get(key)?
            .as_str()
            .map(str::to_owned)
            .ok_or_else(|| self.err(key, "expected a path"))
    }

    fn vec3_of(&self, y: &Yaml) -> Option<[f64; 3]> {
        let v = y.as_vec()?;
        if v.len() != 3 {
            return None;
        }
        Some([
            Self::as_number(&v[0])?,
            Self::as_number(&v[1])?,
            Self::as_number(&v[2])?,
        ])
    }

    fn vec3(&self, key: &str) -> Result<[f64; 3], Error> {
        self.vec3_of(self.get(key)?)
            .ok_or_else(|| self.err(key, "expected a list of exactly 3 numbers"))
    }

    /// A per-axis noise value that must be the same on the three axes
    /// (kestrel's IMU model is isotropic).
    fn same(&self, table: &str, key: &str) -> Result<f64, Error> {
        let v = self
            .get(key)
            .ok()
            .and_then(|y| self.vec3_of(y))
            .ok_or_else(|| self.err_in(table, key, "expected a list of exactly 3 numbers"))?;
        if v[1] != v[0] || v[2] != v[0] {
            return Err(self.err_in(
                table,
                key,
                format!(
                    "kestrel's IMU noise is the same on the three axes: found {}",
                    list(&v)
                ),
            ));
        }
        Ok(v[0])
    }
}
