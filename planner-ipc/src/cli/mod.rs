//! The binaries' code, in the library so that test crates can link the same programs
//! into their own binaries (`CARGO_BIN_EXE_*` only names binaries of the same package).

pub mod client;
pub mod server;
