//! The named choices both files share, as serde enums: a name a file
//! cannot use is an error at its line and column listing the names it can.

use kestrel::nav::Ellipsoid;
use serde::Deserialize;

use crate::scenario::ErrorModelKind;

/// The Earth ellipsoids a file can name (`earth = "…"`).
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum EarthName {
    /// WGS-84 (GPS).
    #[default]
    Wgs84,
    /// GRS-80.
    Grs80,
    /// Krasovsky 1940 (paper 000).
    Krasovsky,
}

impl EarthName {
    /// The ellipsoid.
    ///
    /// ```
    /// use kestrel_app::config::names::EarthName;
    /// assert_eq!(EarthName::Krasovsky.ellipsoid().a, 6_378_245.0);
    /// ```
    pub fn ellipsoid(self) -> Ellipsoid {
        match self {
            Self::Wgs84 => Ellipsoid::wgs84(),
            Self::Grs80 => Ellipsoid::grs80(),
            Self::Krasovsky => Ellipsoid::krasovsky(),
        }
    }

    /// The name of `e` if it is one of these ellipsoids.
    pub fn of(e: &Ellipsoid) -> Option<Self> {
        [Self::Wgs84, Self::Grs80, Self::Krasovsky]
            .into_iter()
            .find(|n| n.ellipsoid() == *e)
    }

    /// The name as files write it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wgs84 => "wgs84",
            Self::Grs80 => "grs80",
            Self::Krasovsky => "krasovsky",
        }
    }
}

/// The error-state models a file can name (`error_model = "…"`); the
/// correlation time of the 21- and 16-state models' scale factors is a key
/// of its own.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ErrorModelName {
    /// 15 states.
    #[default]
    Ins15,
    /// 18 states (+ Gauss-Markov gyro drift).
    Ins18,
    /// 21 states (+ gyro and accelerometer scale factors).
    Ins21,
    /// 16 states (+ odometer scale factor).
    Odometer16,
}

impl ErrorModelName {
    /// The model with the scale factors' correlation time `scale_tau` (s;
    /// unused by the 15- and 18-state models).
    pub fn model(self, scale_tau: f64) -> ErrorModelKind {
        match self {
            Self::Ins15 => ErrorModelKind::Ins15,
            Self::Ins18 => ErrorModelKind::Ins18,
            Self::Ins21 => ErrorModelKind::Ins21 { scale_tau },
            Self::Odometer16 => ErrorModelKind::Odometer16 { scale_tau },
        }
    }

    /// The name of `model`.
    pub fn of(model: &ErrorModelKind) -> Self {
        match model {
            ErrorModelKind::Ins15 => Self::Ins15,
            ErrorModelKind::Ins18 => Self::Ins18,
            ErrorModelKind::Ins21 { .. } => Self::Ins21,
            ErrorModelKind::Odometer16 { .. } => Self::Odometer16,
        }
    }

    /// The name as files write it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Ins15 => "ins15",
            Self::Ins18 => "ins18",
            Self::Ins21 => "ins21",
            Self::Odometer16 => "odometer16",
        }
    }
}
