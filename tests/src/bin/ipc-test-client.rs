//! `planner-client` linked into this package, so that cross-process tests here can find it
//! with `env!("CARGO_BIN_EXE_ipc-test-client")` under a plain `cargo test --workspace`.

fn main() -> anyhow::Result<()> {
    planner_ipc::cli::client::main()
}
