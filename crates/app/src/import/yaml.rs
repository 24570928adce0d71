//! Typed access to a YAML mapping, each problem naming the file and key.

use std::path::Path;

use yaml_rust2::Yaml;

use crate::{Error, InputError};

/// A TOML array of floats.
pub(super) fn list(v: &[f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

/// Typed access to a YAML mapping with errors naming the key.
pub(super) struct Reader<'a> {
    pub(super) path: &'a Path,
    pub(super) root: &'a yaml_rust2::yaml::Hash,
}

impl Reader<'_> {
    pub(super) fn err(&self, key: &str, msg: impl Into<String>) -> Error {
        InputError::file(self.path, msg).with_key(key).into()
    }

    pub(super) fn err_in(&self, table: &str, key: &str, msg: impl Into<String>) -> Error {
        self.err(&format!("{table}.{key}"), msg)
    }

    pub(super) fn get(&self, key: &str) -> Result<&Yaml, Error> {
        self.root
            .get(&Yaml::String(key.into()))
            .ok_or_else(|| self.err(key, "missing"))
    }

    pub(super) fn as_number(y: &Yaml) -> Option<f64> {
        match y {
            Yaml::Integer(i) => Some(*i as f64),
            Yaml::Real(_) => y.as_f64(),
            _ => None,
        }
        .filter(|v| v.is_finite())
    }

    pub(super) fn number(&self, key: &str) -> Result<f64, Error> {
        Self::as_number(self.get(key)?).ok_or_else(|| self.err(key, "expected a number"))
    }

    pub(super) fn number_in(&self, table: &str, key: &str) -> Result<f64, Error> {
        self.get(key)
            .ok()
            .and_then(Self::as_number)
            .ok_or_else(|| self.err_in(table, key, "expected a number"))
    }

    pub(super) fn string(&self, key: &str) -> Result<String, Error> {
        self.get(key)?
            .as_str()
            .map(str::to_owned)
            .ok_or_else(|| self.err(key, "expected a path"))
    }

    /// A path: a string of no control characters (no file name kestrel
    /// writes into a configuration or a command has a line break).
    pub(super) fn path(&self, key: &str) -> Result<String, Error> {
        let s = self.string(key)?;
        if let Some(c) = s.chars().find(|c| c.is_control()) {
            return Err(self.err(
                key,
                format!(
                    "the path has a control character ({}); rename the file",
                    c.escape_default()
                ),
            ));
        }
        Ok(s)
    }

    pub(super) fn vec3_of(&self, y: &Yaml) -> Option<[f64; 3]> {
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

    pub(super) fn vec3(&self, key: &str) -> Result<[f64; 3], Error> {
        self.vec3_of(self.get(key)?)
            .ok_or_else(|| self.err(key, "expected a list of exactly 3 numbers"))
    }

    /// A per-axis noise value that must be the same on the three axes
    /// (kestrel's IMU model is isotropic).
    pub(super) fn same(&self, table: &str, key: &str) -> Result<f64, Error> {
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

/// The deepest nesting of mappings and sequences a KF-GINS file may have
/// (KF-GINS's own files nest two deep).
pub(super) const MAX_YAML_DEPTH: usize = 16;

/// Reads `text` as YAML after a first pass over its events that refuses
/// anchors' aliases (`*name`: a few hundred bytes of them expand to
/// gigabytes) and nesting deeper than [`MAX_YAML_DEPTH`], before anything
/// is built.
pub(super) fn load(text: &str, path: &Path) -> Result<Vec<Yaml>, Error> {
    use yaml_rust2::parser::{Event, Parser};
    let at = |m: yaml_rust2::scanner::Marker, msg: String| -> Error {
        InputError::at(path, m.line(), m.col() + 1, msg).into()
    };
    let mut parser = Parser::new_from_str(text);
    let mut depth = 0usize;
    loop {
        let (event, mark) = parser
            .next_token()
            .map_err(|e| at(*e.marker(), e.info().to_owned()))?;
        match event {
            Event::StreamEnd => break,
            Event::Alias(_) => {
                return Err(at(
                    mark,
                    "an alias (*name): kestrel does not expand YAML aliases; write the value out"
                        .into(),
                ));
            }
            Event::MappingStart(..) | Event::SequenceStart(..) => {
                depth += 1;
                if depth > MAX_YAML_DEPTH {
                    return Err(at(
                        mark,
                        format!(
                            "nested more than {MAX_YAML_DEPTH} deep, the limit of a KF-GINS file"
                        ),
                    ));
                }
            }
            Event::MappingEnd | Event::SequenceEnd => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    yaml_rust2::YamlLoader::load_from_str(text).map_err(|e| at(*e.marker(), e.info().to_owned()))
}
