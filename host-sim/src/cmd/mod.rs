//! One module per subcommand.

pub mod bench;
pub mod maps;
pub mod optimize;
pub mod plan;
pub mod render_demo;
pub mod serve;
pub mod sim;
pub mod terrain;
