//! A per-axis quantity: one number for all three axes or an array of three.

use std::fmt;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;

/// Three values (north, east, down or x, y, z); a single number in the file
/// means the same value on every axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct V3(pub [f64; 3]);

impl<'de> Deserialize<'de> for V3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(V3Visitor)
    }
}

struct V3Visitor;

impl<'de> Visitor<'de> for V3Visitor {
    type Value = V3;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number or an array of 3 numbers")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<V3, E> {
        Ok(V3([v; 3]))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<V3, E> {
        Ok(V3([v as f64; 3]))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<V3, E> {
        Ok(V3([v as f64; 3]))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<V3, A::Error> {
        let mut out = [0.0; 3];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq
                .next_element::<f64>()?
                .ok_or_else(|| de::Error::invalid_length(i, &self))?;
        }
        if seq.next_element::<f64>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok(V3(out))
    }
}

impl serde::Serialize for V3 {
    /// One number when the three are equal, else the array.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let [x, y, z] = self.0;
        if x.to_bits() == y.to_bits() && y.to_bits() == z.to_bits() {
            s.serialize_f64(x)
        } else {
            self.0.serialize(s)
        }
    }
}
