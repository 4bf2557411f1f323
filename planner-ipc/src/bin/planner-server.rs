//! `planner-server`: see [`planner_ipc::cli::server`].

fn main() -> anyhow::Result<()> {
    planner_ipc::cli::server::main()
}
