//! A filter kind in a configuration file: `kind = "…"` and its parameters,
//! the same keys in a `process` configuration's `[filter]` table and in a
//! scenario file's `[[filters]]` entries.
//!
//! [`FilterKind`] is the one definition: its names, parameters, defaults
//! and the comments writers put beside them
//! ([`FilterKind::from_params`], [`FilterKind::params`]); this module reads
//! a table into it and checks each parameter against the range the filter
//! itself accepts, so a file accepts exactly what the filter accepts.

use std::collections::BTreeMap;

use kestrel::adapter::{NoiseAdapter, PriorAdapter};
use kestrel::FilterError;

use crate::config::check::{bad, join, Res};
use crate::experiment::{build_filter, BuildError, Describe, FilterLoop, OdometerProcessing};
use crate::scenario::{FadeBlock, FilterKind};

/// The keys of a table as written (a `[[filters]]` entry, or what a
/// `[filter]` table holds beside its own keys).
pub(crate) type Keys = BTreeMap<String, toml::Value>;

/// Which kinds a file may name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kinds {
    /// The kinds the loosely coupled engine runs (a `process`
    /// configuration): not the federated filters, which run their own loop.
    Engine,
    /// Every kind (a scenario file).
    All,
}

/// The parameters of one kind, read from a table: every read names its key
/// and records it, so the keys a kind reads are the keys it takes.
pub struct ParamReader<'a> {
    keys: &'a Keys,
    prefix: &'a str,
    read: Vec<&'static str>,
}

impl ParamReader<'_> {
    /// The number under `key`, or `default` when the key is absent.
    ///
    /// # Errors
    /// The key and "expected a number" for another type.
    pub fn number(&mut self, key: &'static str, default: f64) -> Result<f64, (String, String)> {
        self.read.push(key);
        match self.keys.get(key) {
            None => Ok(default),
            Some(toml::Value::Float(x)) => Ok(*x),
            Some(toml::Value::Integer(i)) => Ok(*i as f64),
            Some(v) => Err(self.wrong(key, "a number", v)),
        }
    }

    /// The number under `key` or its earlier spelling `old` (not both), or
    /// `default` when both are absent.
    ///
    /// # Errors
    /// As [`number`](Self::number), and when both keys are given.
    pub fn number_or(
        &mut self,
        key: &'static str,
        old: &'static str,
        default: f64,
    ) -> Result<f64, (String, String)> {
        if self.keys.contains_key(key) && self.keys.contains_key(old) {
            return Err((
                join(self.prefix, old),
                format!("give `{key}` or `{old}`, not both"),
            ));
        }
        let key = if self.keys.contains_key(old) {
            old
        } else {
            key
        };
        self.number(key, default)
    }

    /// The R window length under `key`: 10, 20 or 50 innovations (the
    /// compile-time lengths), `default` when absent.
    ///
    /// # Errors
    /// The key and the lengths allowed.
    pub fn window(
        &mut self,
        key: &'static str,
        default: Option<usize>,
    ) -> Result<Option<usize>, (String, String)> {
        self.read.push(key);
        match self.keys.get(key) {
            None => Ok(default),
            Some(toml::Value::Integer(w)) if [10, 20, 50].contains(w) => Ok(Some(*w as usize)),
            Some(toml::Value::Integer(w)) => Err((
                join(self.prefix, key),
                format!("expected 10, 20 or 50, found {w}"),
            )),
            Some(v) => Err(self.wrong(key, "an integer", v)),
        }
    }

    /// The block of states a fade scales under `key`
    /// ([`FadeBlock::All`] when absent).
    ///
    /// # Errors
    /// The key and the names allowed.
    pub fn fade_states(&mut self, key: &'static str) -> Result<FadeBlock, (String, String)> {
        self.read.push(key);
        match self.keys.get(key) {
            None => Ok(FadeBlock::All),
            Some(toml::Value::String(s)) => FadeBlock::from_name(s).ok_or_else(|| {
                (
                    join(self.prefix, key),
                    format!(
                        "unknown value `{s}`, expected one of `all`, `velocity-position`, \
                         `attitude-velocity-position`"
                    ),
                )
            }),
            Some(v) => Err(self.wrong(key, "a quoted string", v)),
        }
    }

    fn wrong(&self, key: &str, expected: &str, found: &toml::Value) -> (String, String) {
        (
            join(self.prefix, key),
            format!("expected {expected}, found {}", type_name(found)),
        )
    }
}

/// A TOML value's type for messages.
fn type_name(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "a string",
        toml::Value::Integer(_) => "an integer",
        toml::Value::Float(_) => "a number",
        toml::Value::Boolean(_) => "a boolean",
        toml::Value::Datetime(_) => "a date",
        toml::Value::Array(_) => "an array",
        toml::Value::Table(_) => "a table",
    }
}

/// The filter kind of the table `keys` at key path `prefix`: `kind`
/// (`default` when absent, else required) and its parameters, each checked.
///
/// # Errors
/// [`Bad`](crate::config::check::Bad) naming the key: an unknown or
/// unsupported kind, a key the kind does not take, a wrong type, a value
/// the filter refuses.
pub(crate) fn read_kind(
    keys: &Keys,
    prefix: &str,
    default: Option<&str>,
    kinds: Kinds,
) -> Res<FilterKind> {
    let kind_key = join(prefix, "kind");
    let name = match keys.get("kind") {
        Some(toml::Value::String(s)) => s.as_str(),
        Some(v) => {
            return Err(bad(
                kind_key,
                format!("expected a quoted string, found {}", type_name(v)),
            ));
        }
        None => default.ok_or_else(|| bad(prefix, "missing key `kind`"))?,
    };
    let Some(canonical) = FilterKind::canonical_name(name) else {
        return Err(bad(
            kind_key,
            format!(
                "unknown value `{name}`, expected one of `{}`",
                FilterKind::NAMES.join("`, `")
            ),
        ));
    };
    let mut reader = ParamReader {
        keys,
        prefix,
        read: Vec::new(),
    };
    let kind = FilterKind::from_params(canonical, &mut reader).map_err(|(k, m)| bad(k, m))?;
    if kinds == Kinds::Engine && kind.is_federated() {
        return Err(bad(
            kind_key,
            format!("`{canonical}` runs in scenario files only (the federated filters run their own loop)"),
        ));
    }
    if let Some(foreign) = keys
        .keys()
        .find(|k| *k != "kind" && !reader.read.contains(&k.as_str()))
    {
        let takes = if reader.read.is_empty() {
            "no parameters".to_string()
        } else {
            format!("`{}`", reader.read.join("`, `"))
        };
        return Err(bad(
            join(prefix, foreign),
            format!("does not apply to kind = \"{canonical}\", which takes {takes}"),
        ));
    }
    check(&kind, prefix)?;
    Ok(kind)
}

/// Builds the filter of `kind` once, turning a parameter it refuses into
/// an error naming the key, the filter's own range and the value.
fn check(kind: &FilterKind, prefix: &str) -> Res<()> {
    if let Some((key, valid, value)) = kind.out_of_range() {
        return Err(bad(
            join(prefix, key),
            format!("expected {valid}, found {value}"),
        ));
    }
    let odometer = kind.is_odometer();
    let Err(BuildError::Invalid(FilterError::InvalidParameter { name, valid })) =
        build_filter::<6, _>(kind, Probe { odometer })
    else {
        return Ok(());
    };
    let key = match name {
        "max_fade" => "lambda_max",
        other => other,
    };
    let value = kind
        .params()
        .into_iter()
        .find_map(|p| (p.key == key).then_some(p.value))
        .map_or_else(String::new, |v| format!(", found {v}"));
    Err(bad(join(prefix, key), format!("expected {valid}{value}")))
}

/// A filter loop that only builds the filter (to check its parameters).
struct Probe {
    odometer: bool,
}

impl FilterLoop<6> for Probe {
    type Output = ();

    fn odometer_model(&self) -> bool {
        self.odometer
    }

    fn gnss<A>(self, _: A, _: FadeBlock)
    where
        A: PriorAdapter<f64> + NoiseAdapter<f64, 6, Report: Describe>,
    {
    }

    fn odometer<P: OdometerProcessing>(self, _: P) {}
}
