//! Subcommands.

pub mod optimize;
