//! The simulator's integration tests as one binary: the code the files
//! share is compiled and linked once, not once per file.

mod multipath;
mod sensors;
mod trajectory;
