//! One module per subcommand.

pub mod bench;
pub mod maps;
pub mod optimize;
pub mod plan;
pub mod sim;
pub mod render_demo;
