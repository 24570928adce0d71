//! gins (being written).
