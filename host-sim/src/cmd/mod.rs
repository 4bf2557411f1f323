//! One module per subcommand.

pub mod optimize;
pub mod plan;
