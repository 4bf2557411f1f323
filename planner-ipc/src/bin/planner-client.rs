//! `planner-client`: see [`planner_ipc::cli::client`].

fn main() -> anyhow::Result<()> {
    planner_ipc::cli::client::main()
}
