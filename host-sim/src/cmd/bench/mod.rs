//! `host-sim bench ...`: the benchmarks that reproduce the papers' tables and measure
//! quality and speed. Each prints a table, and writes JSON and CSV (and pictures where the
//! papers have figures) under `--out`.

pub mod clearance_bound;
pub mod lowerbound;
pub mod movingai;
pub mod paper;
#[cfg(feature = "polyanya")]
mod polyanya;
pub mod safety;
pub mod scale;
pub mod speed;

pub use host_sim::stats::mean_std;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::path::Path;

/// Arguments of `host-sim bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    which: Which,
}

#[derive(clap::Subcommand, Debug)]
enum Which {
    /// Lei2024Warehouse's tables 2 and 3 and Liu2020Igwo's table 3.
    Paper(paper::PaperArgs),
    /// Validity, length and time on Moving AI warehouse scenarios.
    Movingai(movingai::MovingaiArgs),
    /// Time per plan against A* in the same process, with and without stagnation stopping.
    Speed(speed::SpeedArgs),
    /// Lower bound on any valid path's length (shortest path touching obstacles) on the
    /// Moving AI warehouse rows.
    Lowerbound(lowerbound::LowerboundArgs),
    /// Generated warehouses from 256 to 4096 cells a side: time per query against A*, length
    /// against the exact any-angle path, peak memory, and a log-log plot.
    Scale(scale::ScaleArgs),
    /// Margins and turns: the exact planners against TCLHHO and IGWO with the blended
    /// objective, on the Moving AI and generated warehouses.
    Safety(safety::SafetyArgs),
}

/// Runs `host-sim bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    match &args.which {
        Which::Paper(a) => paper::run(a),
        Which::Movingai(a) => movingai::run(a),
        Which::Speed(a) => speed::run(a),
        Which::Lowerbound(a) => lowerbound::run(a),
        Which::Scale(a) => scale::run(a),
        Which::Safety(a) => safety::run(a),
    }
}

/// A progress bar on standard error (hidden when it is not a terminal).
pub fn progress(len: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg:>24} [{bar:40}] {pos}/{len} {elapsed_precise} eta {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// Writes `value` as pretty JSON.
pub fn write_json(path: &Path, value: &impl Serialize) -> anyhow::Result<()> {
    use anyhow::Context;
    let text = serde_json::to_string_pretty(value)?;
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// Writes rows of already formatted cells as CSV (cells must not contain commas).
pub fn write_csv(path: &Path, header: &[&str], rows: &[Vec<String>]) -> anyhow::Result<()> {
    use anyhow::Context;
    let mut text = header.join(",");
    text.push('\n');
    for r in rows {
        text.push_str(&r.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// Prints a plain-text table with aligned columns.
pub fn print_table(title: &str, header: &[&str], rows: &[Vec<String>]) {
    let mut widths: Vec<usize> = header.iter().map(|h| h.len()).collect();
    for r in rows {
        for (w, c) in widths.iter_mut().zip(r) {
            *w = (*w).max(c.len());
        }
    }
    println!("\n{title}");
    let line = |cells: Vec<&str>| {
        let parts: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(c, w)| format!("{c:>w$}"))
            .collect();
        println!("| {} |", parts.join(" | "));
    };
    line(header.to_vec());
    println!(
        "|{}|",
        widths
            .iter()
            .map(|w| "-".repeat(w + 2))
            .collect::<Vec<_>>()
            .join("|")
    );
    for r in rows {
        line(r.iter().map(String::as_str).collect());
    }
}

/// `x` with `digits` decimals, or `—` for NaN (the papers' mark for "no valid path").
pub fn fmt(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "—".to_string()
    }
}
