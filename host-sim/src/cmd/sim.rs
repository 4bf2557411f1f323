//! The simulator commands: `demo`, `run`, `scenarios`, `soak`.
//!
//! ```text
//! host-sim demo [--out DIR] [--planner ipc|inproc|zenoh]
//! host-sim run [--map FILE.map|FILE.yaml | layout options] --algo NAME [--robots K] [--people K] [--seed S]
//!              [--start X,Y --goal X,Y [--frame cells|world]] [--robot-radius M] [--max-speed M/S]
//!              [--max-accel M/S2] [--unknown blocked|free] [--out DIR]
//! ```
//!
//! `run` on a ROS map works in its world frame: `--frame world` takes the start and goal in
//! metres, the robot (default 0.25 m, 1.0 m/s, 0.5 m/s^2) is sized in metres, the map is
//! inflated by its radius for the global planner, and the report and pictures are in
//! metres. Exit status ([`crate::exit`]): 0 when the mission arrived without contact, 2 for
//! bad input (map, start, goal, options; each endpoint error named as `plan` names it), 3
//! when it did not arrive or collided.
//!
//! ```text
//! host-sim scenarios [--case NAME] [--algo NAME] [--out DIR] [--json]
//! host-sim soak [--missions N] [--seed S] [--algo NAME] [--out DIR]
//! ```

use super::bench::{fmt, print_table, progress, write_json};
use crate::exit::{MissionFailed, bad};
use crate::sim::mission::{self, MissionResult, MissionSpec, Outcome};
use crate::sim::planner::{
    GlobalPlanRequest, GlobalPlanner, InProcess, PlanFailure, PlannerChoice,
};
use crate::sim::report::MapLook;
use crate::sim::robot::Robot;
use crate::sim::safety::SafetyArgs;
use crate::sim::scenarios::{self, mission_params};
use crate::sim::site::Site;
use crate::sim::{kinematics::DiffDrive, report};
use crate::warehouse_gen;
use anyhow::{Context, bail};
use planner_core::dwa::{DwaConfig, DwaState};
use planner_core::geometry::Cell;
use planner_core::grid::{GridBuf, GridRef, words_for};
use planner_core::maps::{MapKind, lei2024_warehouse};
use planner_core::planner::PlannerKind;
use planner_ipc::jsonl::Endpoint;
use planner_mapfile::{Frame, MapFrame, MapOptions};
use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde_json::json;
use std::path::{Path, PathBuf};

fn parse_planner(s: &str) -> Result<PlannerKind, String> {
    s.parse().map_err(|_| format!("unknown planner {s:?}"))
}

/// Arguments of `host-sim demo`.
#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Output directory.
    #[arg(long, default_value = "bench-out/demo")]
    pub out: PathBuf,
    /// Global planner: ipc (planner-server over iceoryx2, started if none runs), inproc
    /// (planner-core in this process) or zenoh (planner-server over Zenoh at
    /// tcp/127.0.0.1:7447, started if none answers; feature `zenoh`).
    #[arg(long, value_enum, default_value_t = PlannerChoice::Ipc)]
    pub planner: PlannerChoice,
    /// Seed of the planner and of the people and robots.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Static margin and protective field.
    #[command(flatten)]
    pub safety: SafetyArgs,
}

/// Arguments of `host-sim run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Moving AI `.map` or ROS map_server `.yaml`; without it a warehouse is generated
    /// from the layout options.
    #[arg(long)]
    pub map: Option<PathBuf>,
    /// Global planner algorithm.
    #[arg(long, value_parser = parse_planner, default_value = "tclhho")]
    pub algo: PlannerKind,
    /// Other robots moving about.
    #[arg(long, default_value_t = 0)]
    pub robots: usize,
    /// People walking about.
    #[arg(long, default_value_t = 0)]
    pub people: usize,
    /// Seed (planner, movers, random start and goal).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Start `X,Y`: a cell, or metres with `--frame world` (default: a random free cell of
    /// the inflated map's largest region).
    #[arg(long, requires = "goal", allow_hyphen_values = true)]
    pub start: Option<String>,
    /// Goal `X,Y`: a cell, or metres with `--frame world` (default: a random free cell in
    /// the start's region).
    #[arg(long, requires = "start", allow_hyphen_values = true)]
    pub goal: Option<String>,
    /// What `--start` and `--goal` are in: cells, or metres in the map frame of a ROS map
    /// (its YAML's origin and resolution, y up).
    #[arg(long, value_enum, default_value_t = Frame::Cells)]
    pub frame: Frame,
    /// Robot radius (m; default 0.25 on a ROS map): sizes the simulated robot and inflates
    /// the map for the global planner. On a map without a world frame the robot is 0.3
    /// cell and the map is not inflated.
    #[arg(long)]
    pub robot_radius: Option<f32>,
    /// Robot speed limit (m/s, or cells/s on a map without a world frame).
    #[arg(long, default_value_t = Robot::AMR.max_speed)]
    pub max_speed: f32,
    /// Robot acceleration limit (m/s^2, or cells/s^2 on a map without a world frame).
    #[arg(long, default_value_t = Robot::AMR.max_accel)]
    pub max_accel: f32,
    /// Static margin and protective field.
    #[command(flatten)]
    pub safety: SafetyArgs,
    /// Output directory.
    #[arg(long, default_value = "bench-out/run")]
    pub out: PathBuf,
    /// Global planner: ipc (planner-server over iceoryx2, started if none runs), inproc, or
    /// zenoh (over Zenoh at tcp/127.0.0.1:7447, started if none answers; feature `zenoh`).
    #[arg(long, value_enum, default_value_t = PlannerChoice::Ipc)]
    pub planner: PlannerChoice,
    /// Layout of the generated warehouse (without `--map`).
    #[command(flatten)]
    pub layout: warehouse_gen::WarehouseParams,
    /// Size limit and unknown space of the loaded or generated map.
    #[command(flatten)]
    pub limits: MapOptions,
}

/// Arguments of `host-sim scenarios`.
#[derive(clap::Args, Debug)]
pub struct ScenariosArgs {
    /// Run only this case.
    #[arg(long)]
    pub case: Option<String>,
    /// Global planner algorithm.
    #[arg(long, value_parser = parse_planner, default_value = "tclhho")]
    pub algo: PlannerKind,
    /// Output directory (one folder of pictures per case).
    #[arg(long, default_value = "bench-out/scenarios")]
    pub out: PathBuf,
    /// Skip the pictures.
    #[arg(long)]
    pub no_pictures: bool,
    /// Print one JSON object a case instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Global planner: inproc (planner-core in this process) or ipc (over iceoryx2).
    #[arg(long, value_enum, default_value_t = PlannerChoice::Inproc)]
    pub planner: PlannerChoice,
    /// Static margin and protective field.
    #[command(flatten)]
    pub safety: SafetyArgs,
}

/// Arguments of `host-sim soak`.
#[derive(clap::Args, Debug)]
pub struct SoakArgs {
    /// Missions to run.
    #[arg(long, default_value_t = 1000)]
    pub missions: usize,
    /// First seed (mission `i` uses `seed + i`).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Global planner algorithm.
    #[arg(long, value_parser = parse_planner, default_value = "tclhho")]
    pub algo: PlannerKind,
    /// Output directory (report.json).
    #[arg(long, default_value = "bench-out/soak")]
    pub out: PathBuf,
    /// Global planner: inproc (planner-core in this process) or ipc (over iceoryx2).
    #[arg(long, value_enum, default_value_t = PlannerChoice::Inproc)]
    pub planner: PlannerChoice,
    /// Required success rate (exit status 3 below it, as for contacts and margins).
    #[arg(long, default_value_t = 0.995)]
    pub min_success: f64,
    /// Static margin and protective field.
    #[command(flatten)]
    pub safety: SafetyArgs,
}

fn pose(cell: Cell, theta: f32) -> DwaState {
    DwaState {
        x: cell.x as f32,
        y: cell.y as f32,
        theta,
        v: 0.0,
        w: 0.0,
    }
}

fn write_outputs(
    spec: &MissionSpec,
    result: &MissionResult,
    stations: &[(Cell, &'static str)],
    look: MapLook<'_>,
    out: &Path,
    extra: serde_json::Value,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    report::save_pictures(spec, result, stations, look, out)?;
    let mut value = serde_json::to_value(result)?;
    if let (Some(obj), serde_json::Value::Object(more)) = (value.as_object_mut(), extra) {
        obj.extend(more);
    }
    write_json(&out.join("report.json"), &value)?;
    Ok(())
}

/// Runs a mission with a progress bar over simulated time.
fn run_with_bar(
    spec: &MissionSpec,
    choice: PlannerChoice,
    out: &Path,
) -> anyhow::Result<MissionResult> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    if let Some(transport) = choice.transport() {
        println!("connecting to planner-server over {transport} (starting one if none runs) ...");
    }
    let mut planner = choice.build(Some(&out.join("planner-server.log")))?;
    if let Some(transport) = choice.transport() {
        // A map the service refuses is the user's to change: bad input, with the way out.
        let grid = spec.plan_grid.as_ref().unwrap_or(&spec.grid);
        if let Err(PlanFailure::MapTooLarge(why)) = planner.set_map(grid.view()) {
            return Err(bad(format!(
                "MapTooLarge: {why}; --planner inproc plans any map within --max-cells"
            )));
        }
        println!("global planner: {} over {transport}", spec.algo.name());
    }
    let bar = progress(100, "driving");
    let result = mission::run_with_progress(spec, &mut *planner, &mut |t, limit| {
        bar.set_position((100.0 * t / limit).min(100.0) as u64);
        bar.set_message(format!("driving, t = {t:.0} s"));
    });
    bar.finish_and_clear();
    Ok(result)
}

/// The service does not send the planner's per-iteration history: when the first plan came
/// over a transport (iceoryx2, Zenoh), the same request (same seed) is planned again in this process for the
/// convergence plot, and the JSON says whether both gave the same path length.
fn convergence_in_process(
    spec: &MissionSpec,
    result: &mut MissionResult,
) -> anyhow::Result<serde_json::Value> {
    let Some(first) = result.plans.first_mut() else {
        return Ok(json!(null));
    };
    if !first.history.is_empty() {
        return Ok(json!({"source": "global planner"}));
    }
    let Some(start) = spec.start.position().cell(spec.grid.view()) else {
        return Ok(json!(null));
    };
    let mut local = InProcess::new();
    local
        .set_map(spec.plan_grid.as_ref().unwrap_or(&spec.grid).view())
        .map_err(anyhow::Error::msg)?;
    let p = local
        .plan(&GlobalPlanRequest {
            start,
            goal: spec.goal,
            algo: spec.algo,
            params: spec.params,
            seed: spec.seed,
        })
        .map_err(anyhow::Error::msg)?;
    let same = (p.length - first.length).abs() <= 1e-3 * first.length.max(1.0);
    first.history = p.history;
    Ok(json!({
        "source": "same request planned again in this process (the service sends no history)",
        "in_process_length": p.length,
        "service_length": first.length,
        "same_length": same,
    }))
}

/// `host-sim demo`.
pub fn demo(args: &DemoArgs) -> anyhow::Result<()> {
    let safety = args.safety.safety().map_err(|e| bad(e.to_string()))?;
    let map = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Warehouse, 40)
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let grid = GridBuf::from_view(map.grid.view());
    let spec = MissionSpec {
        name: "demo: Lei2024Warehouse's 40x40 warehouse".into(),
        grid,
        plan_grid: None,
        metres_per_cell: 1.0,
        start: pose(map.start, 0.0),
        goal: map.goal,
        algo: "tclhho".parse().map_err(anyhow::Error::msg)?,
        params: mission_params(),
        seed: args.seed,
        agents: Vec::new(),
        people: 3,
        robots: 2,
        dwa: safety.apply(DwaConfig::default(), 1.0),
        drive: DiffDrive::default(),
        time_limit: None,
        record: true,
    };
    println!(
        "demo: Lei2024Warehouse's 40x40 warehouse, TCLHHO global planner ({}), DWA, 3 people and 2 robots moving",
        args.planner.name()
    );
    let mut result = run_with_bar(&spec, args.planner, &args.out)?;
    let convergence = convergence_in_process(&spec, &mut result)?;
    write_outputs(
        &spec,
        &result,
        &[],
        MapLook::default(),
        &args.out,
        json!({"algo": "tclhho", "planner": args.planner.name(), "seed": args.seed,
               "convergence": convergence}),
    )?;
    println!("{}", report::summary(&result));
    println!(
        "wrote {0}/trajectory.png, {0}/trajectory.svg, {0}/convergence.png, {0}/convergence.svg, {0}/report.json",
        args.out.display()
    );
    if !result.success {
        return Err(
            MissionFailed(format!("demo mission did not succeed: {}", result.outcome)).into(),
        );
    }
    Ok(())
}

/// A random free cell, or one of `choices` (when not empty) with probability 1/2.
fn random_free(grid: GridRef<'_>, rng: &mut Xoshiro256PlusPlus, choices: &[Cell]) -> Option<Cell> {
    if !choices.is_empty() && rng.next_u32().is_multiple_of(2) {
        return Some(choices[(rng.next_u64() % choices.len() as u64) as usize]);
    }
    for _ in 0..10_000 {
        let i = (rng.next_u64() % grid.cells() as u64) as usize;
        let c = grid.cell(i);
        if grid.is_free(c) {
            return Some(c);
        }
    }
    None
}

/// Start and goal at least `min_gap` apart, both free.
fn random_pair(
    grid: GridRef<'_>,
    rng: &mut Xoshiro256PlusPlus,
    stations: &[Cell],
    min_gap: f32,
) -> anyhow::Result<(Cell, Cell)> {
    for _ in 0..1000 {
        let (Some(a), Some(b)) = (
            random_free(grid, rng, stations),
            random_free(grid, rng, stations),
        ) else {
            break;
        };
        if a.center().distance(b.center()) >= min_gap {
            return Ok((a, b));
        }
    }
    bail!("no free start and goal far enough apart")
}

/// `host-sim run`.
pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let (site, name, stations) = run_site(args)?;
    let declared = site.frame.declared;
    let mpc = site.frame.resolution as f32;
    let robot = Robot {
        radius: args
            .robot_radius
            .unwrap_or(if declared { Robot::AMR.radius } else { 0.3 }),
        max_speed: args.max_speed,
        max_accel: args.max_accel,
    };
    robot.check().map_err(|e| bad(e.to_string()))?;
    let safety = args.safety.safety().map_err(|e| bad(e.to_string()))?;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(args.seed);
    let k = 1.0 / mpc;
    let (dwa, drive) = if declared {
        (safety.apply(robot.dwa(k), k), robot.drive(k))
    } else {
        // A cell counts as a metre: the defaults, with the robot's figures.
        (safety.apply(robot.dwa(1.0), 1.0), robot.drive(1.0))
    };
    let (start, goal) = match (&args.start, &args.goal) {
        (Some(s), Some(g)) => {
            let resolve = |text: &str, which: &str| -> anyhow::Result<Cell> {
                let end = super::plan::endpoint(text, args.frame, &which.to_ascii_lowercase())?;
                let cell = end
                    .resolve(&site.frame, which)
                    .map_err(|e| bad(crate::sim::site::BadEndpoint(e).to_string()))?;
                let checked = site.check(which, cell).map_err(|e| bad(e.to_string()))?;
                if let Endpoint::World(_) = end {
                    println!("{which}: ({text}) m is cell ({}, {})", checked.x, checked.y);
                }
                Ok(checked)
            };
            (resolve(s, "Start")?, resolve(g, "Goal")?)
        }
        _ => {
            let cells: Vec<Cell> = stations.iter().map(|s| s.0).collect();
            let gap = 8.0_f32.max(2.0 / mpc);
            // Random ends keep the margin too (on the planning map: beyond the footprint
            // where it is inflated by the radius).
            let footprint = if site.inflated.is_some() {
                0.0
            } else {
                dwa.radius
            };
            let keep = footprint + dwa.margin;
            site.random_pair(&mut rng, &cells, gap, keep).ok_or_else(|| {
                bad(format!(
                    "{name}: no two free cells {gap} cells apart in one region of the inflated map"
                ))
            })?
        }
    };
    let theta = (rng.next_u32() % 8) as f32 * std::f32::consts::FRAC_PI_4;
    let spec = MissionSpec {
        name: name.clone(),
        grid: site.grid.clone(),
        plan_grid: site.inflated.clone(),
        metres_per_cell: mpc,
        start: pose(start, theta),
        goal,
        algo: args.algo,
        params: mission_params(),
        seed: args.seed,
        agents: Vec::new(),
        people: args.people,
        robots: args.robots,
        dwa,
        drive,
        time_limit: None,
        record: true,
    };
    let unit = if declared { "m" } else { "cells" };
    let at = |c: Cell| -> String {
        if declared {
            let [x, y] = site.frame.to_world(c.x as f64, c.y as f64);
            format!(
                "({}, {}) m",
                planner_mapfile::frame::metres(x),
                planner_mapfile::frame::metres(y)
            )
        } else {
            format!("({}, {})", c.x, c.y)
        }
    };
    println!(
        "run: {} ({} x {} cells{}), {} from {} to {}, robot radius {} {unit}{}, {} people, {} robots",
        spec.name,
        spec.grid.width(),
        spec.grid.height(),
        if declared {
            format!(
                ", {} m a cell",
                planner_mapfile::frame::metres(site.frame.resolution)
            )
        } else {
            String::new()
        },
        args.algo.name(),
        at(start),
        at(goal),
        robot.radius,
        site.radius_text
            .as_ref()
            .map_or(String::new(), |r| format!(" (map inflated by {r})")),
        args.people,
        args.robots
    );
    let mut result = run_with_bar(&spec, args.planner, &args.out)?;
    let convergence = convergence_in_process(&spec, &mut result)?;
    // Cell centres in metres, to the micrometre (no binary noise in the report).
    let world = |c: Cell| {
        declared.then(|| {
            site.frame
                .to_world(c.x as f64, c.y as f64)
                .map(|v| (v * 1e6).round() / 1e6)
        })
    };
    write_outputs(
        &spec,
        &result,
        &stations,
        MapLook {
            unknown: site.unknown.as_ref().map(GridBuf::view),
            world: declared.then_some(site.frame),
        },
        &args.out,
        json!({"algo": args.algo.name(), "planner": args.planner.name(), "seed": args.seed,
               "units": if declared { "m" } else { "cells (1 m each)" },
               "metres_per_cell": site.frame.resolution, "robot": robot,
               "start": [start.x, start.y], "goal": [goal.x, goal.y],
               "start_m": world(start), "goal_m": world(goal), "convergence": convergence}),
    )?;
    println!("{}", report::summary(&result));
    println!("wrote pictures and report.json to {}", args.out.display());
    if !result.success {
        return Err(MissionFailed(format!(
            "the mission did not succeed: {}, {} static and {} dynamic collisions",
            result.outcome, result.collisions_static, result.collisions_dynamic
        ))
        .into());
    }
    Ok(())
}

/// A generated warehouse's pick and charging stations, with their legend labels.
type Stations = Vec<(Cell, &'static str)>;

/// The map of `run` (a file or a generated warehouse), inflated for the robot, its name, and
/// the generated warehouse's stations.
fn run_site(args: &RunArgs) -> anyhow::Result<(Site, String, Stations)> {
    let (grid, unknown, frame, name, stations) = match &args.map {
        Some(path) => {
            let m = planner_mapfile::load_map(path, &args.limits)?;
            (m.grid, m.unknown, m.frame, m.name, Vec::new())
        }
        None => {
            let w = warehouse_gen::generate(&args.layout, &args.limits)?;
            let mut st: Vec<(Cell, &'static str)> =
                w.picks.iter().map(|c| (*c, "pick station")).collect();
            st.extend(w.chargers.iter().map(|c| (*c, "charging station")));
            let frame = MapFrame::assumed(w.grid.width(), w.grid.height());
            (w.grid, None, frame, "generated warehouse".to_string(), st)
        }
    };
    let what = || {
        args.map
            .as_ref()
            .map_or("the generated warehouse".to_string(), |p| {
                p.display().to_string()
            })
    };
    if args.frame == Frame::World && !frame.declared {
        return Err(bad(format!(
            "{}: no world frame (cells only); --frame world needs a ROS map YAML with a \
             resolution and an origin",
            what()
        )));
    }
    let inflation = planner_ipc::jsonl::inflation(None, args.robot_radius.map(f64::from), &frame)
        .map_err(|e| bad(format!("{}: {e}", what())))?;
    let inflated = if frame.declared {
        Some(
            grid.inflated(inflation.cells as f32)
                .map_err(anyhow::Error::msg)?,
        )
    } else {
        None
    };
    let radius_text = inflation.text;
    let site = Site {
        grid,
        inflated,
        unknown,
        frame,
        radius_text,
    };
    Ok((site, name, stations))
}

/// `host-sim scenarios`: exit status 1 if any case fails.
pub fn scenarios(args: &ScenariosArgs) -> anyhow::Result<()> {
    let all = scenarios::all();
    let chosen: Vec<_> = all
        .iter()
        .filter(|s| args.case.as_deref().is_none_or(|c| c == s.name))
        .collect();
    if chosen.is_empty() {
        bail!(
            "unknown case; cases: {}",
            all.iter().map(|s| s.name).collect::<Vec<_>>().join(", ")
        );
    }
    let safety = args.safety.safety().map_err(|e| bad(e.to_string()))?;
    let mut rows = Vec::new();
    let mut failed = 0;
    let mut planner = args.planner.build(None)?;
    let planner = &mut planner;
    for sc in chosen {
        let mut spec = sc.mission(args.algo, 1)?;
        spec.dwa = safety.apply(spec.dwa, 1.0);
        let r = mission::run(&spec, &mut **planner);
        let pass = sc.passes(&r.outcome, r.collisions_static + r.collisions_dynamic);
        failed += usize::from(!pass);
        if !args.no_pictures && r.outcome != Outcome::Unreachable {
            report::save_pictures(&spec, &r, &[], MapLook::default(), &args.out.join(sc.name))?;
        }
        if args.json {
            println!(
                "{}",
                json!({"case": sc.name, "pass": pass, "expect": format!("{:?}", sc.expect), "result": r})
            );
        }
        rows.push(vec![
            sc.name.to_string(),
            if pass { "PASS" } else { "FAIL" }.to_string(),
            r.outcome.to_string(),
            (r.collisions_static + r.collisions_dynamic).to_string(),
            r.time_to_goal.map_or("—".into(), |t| format!("{t:.1}")),
            fmt(r.driven_length as f64, 1),
            fmt(r.planned_length as f64, 1),
            fmt(r.rms_cross_track as f64, 2),
            fmt(r.min_clearance_static as f64, 2),
            r.replans.to_string(),
            r.stuck_events.to_string(),
            r.oscillation_events.to_string(),
            sc.what.to_string(),
        ]);
    }
    if !args.json {
        print_table(
            &format!("Scenarios ({}, DWA)", args.algo.name()),
            &[
                "case", "result", "outcome", "coll.", "time s", "driven", "planned", "RMS xte",
                "min clr", "replans", "stuck", "osc.", "what",
            ],
            &rows,
        );
    }
    if failed > 0 {
        bail!("{failed} scenario(s) failed");
    }
    Ok(())
}

/// `host-sim soak`.
pub fn soak(args: &SoakArgs) -> anyhow::Result<()> {
    let safety = args.safety.safety().map_err(|e| bad(e.to_string()))?;
    let bar = progress(args.missions as u64, "soak missions");
    let mut results = Vec::with_capacity(args.missions);
    let mut planner = args.planner.build(None)?;
    for i in 0..args.missions {
        let seed = args.seed + i as u64;
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0xA5A5_5A5A);
        let pick = |rng: &mut Xoshiro256PlusPlus, lo: usize, hi: usize| {
            lo + (rng.next_u64() % (hi - lo + 1) as u64) as usize
        };
        let layout = warehouse_gen::WarehouseParams {
            width: pick(&mut rng, 24, 60),
            height: pick(&mut rng, 20, 48),
            shelf_depth: pick(&mut rng, 1, 2),
            shelf_len: pick(&mut rng, 3, 8),
            aisle: pick(&mut rng, 1, 3),
            cross: pick(&mut rng, 1, 3),
            margin: pick(&mut rng, 1, 3),
            chargers: 3,
        };
        let w = warehouse_gen::generate(&layout, &MapOptions::default())?;
        let mut stations = w.picks.clone();
        stations.extend(&w.chargers);
        let (start, goal) = random_pair(w.grid.view(), &mut rng, &stations, 10.0)?;
        let theta = (rng.next_u32() % 8) as f32 * std::f32::consts::FRAC_PI_4;
        let spec = MissionSpec {
            name: format!("soak-{seed}"),
            grid: w.grid,
            plan_grid: None,
            metres_per_cell: 1.0,
            start: pose(start, theta),
            goal,
            algo: args.algo,
            params: mission_params(),
            seed,
            agents: Vec::new(),
            people: pick(&mut rng, 0, 4),
            robots: pick(&mut rng, 0, 3),
            dwa: safety.apply(DwaConfig::default(), 1.0),
            drive: DiffDrive::default(),
            time_limit: None,
            record: false,
        };
        let r = mission::run(&spec, &mut *planner);
        if !r.success {
            // Run it again with recording on (missions are deterministic) for pictures.
            let again = MissionSpec {
                record: true,
                ..spec.clone()
            };
            let rr = mission::run(&again, &mut *planner);
            let dir = args.out.join("failures").join(&spec.name);
            report::save_pictures(&again, &rr, &[], MapLook::default(), &dir)?;
            bar.println(format!(
                "mission {seed} failed: {}  (layout {layout:?}, start {start:?}, goal {goal:?}, people {}, robots {})",
                report::summary(&r),
                spec.people,
                spec.robots
            ));
        }
        results.push((layout, r));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let n = results.len().max(1) as f64;
    let ok = results.iter().filter(|(_, r)| r.success).count();
    let unreachable = results
        .iter()
        .filter(|(_, r)| r.outcome == Outcome::Unreachable)
        .count();
    let timeouts = results
        .iter()
        .filter(|(_, r)| r.outcome == Outcome::Timeout)
        .count();
    let cs: u32 = results.iter().map(|(_, r)| r.collisions_static).sum();
    let cd: u32 = results.iter().map(|(_, r)| r.collisions_dynamic).sum();
    let cm: u32 = results.iter().map(|(_, r)| r.contacts_moving).sum();
    let min_static = results
        .iter()
        .map(|(_, r)| r.min_clearance_static as f64)
        .fold(f64::INFINITY, f64::min);
    let floor = 0.5 * safety.shelf_margin as f64;
    let arrived: Vec<&MissionResult> = results
        .iter()
        .map(|(_, r)| r)
        .filter(|r| r.outcome == Outcome::Arrived)
        .collect();
    let mean = |f: &dyn Fn(&MissionResult) -> f64| {
        arrived.iter().map(|r| f(r)).sum::<f64>() / arrived.len().max(1) as f64
    };
    let rate = ok as f64 / n;
    let summary = json!({
        "missions": results.len(),
        "algo": args.algo.name(),
        "first_seed": args.seed,
        "success": ok,
        "success_rate": rate,
        "unreachable": unreachable,
        "timeouts": timeouts,
        "collisions_static": cs,
        "collisions_dynamic": cd,
        "contacts_moving": cm,
        "safety": safety,
        "mean_time_to_goal_s": mean(&|r| r.time_to_goal.unwrap_or(0.0) as f64),
        "mean_length_ratio": mean(&|r| r.length_ratio as f64),
        "mean_rms_cross_track": mean(&|r| r.rms_cross_track as f64),
        "min_clearance_static": min_static,
        "missions_below_half_margin": results.iter().filter(|(_, r)| (r.min_clearance_static as f64) < floor).count(),
        "replans": results.iter().map(|(_, r)| r.replans).sum::<u32>(),
        "stuck_events": results.iter().map(|(_, r)| r.stuck_events).sum::<u32>(),
        "oscillation_events": results.iter().map(|(_, r)| r.oscillation_events).sum::<u32>(),
        "failed_seeds": results.iter().filter(|(_, r)| !r.success).map(|(_, r)| r.name.clone()).collect::<Vec<_>>(),
    });
    std::fs::create_dir_all(&args.out)?;
    write_json(&args.out.join("report.json"), &summary)?;
    print_table(
        &format!(
            "Soak: {} missions on generated warehouses ({}, DWA)",
            results.len(),
            args.algo.name()
        ),
        &[
            "success",
            "rate",
            "unreachable",
            "timeouts",
            "coll. static",
            "coll. dynamic",
            "moving",
            "mean time s",
            "driven/planned",
            "RMS xte",
            "min clr static",
            "replans",
            "stuck",
            "osc.",
        ],
        &[vec![
            ok.to_string(),
            format!("{:.1}%", 100.0 * rate),
            unreachable.to_string(),
            timeouts.to_string(),
            cs.to_string(),
            cd.to_string(),
            cm.to_string(),
            fmt(
                summary["mean_time_to_goal_s"].as_f64().unwrap_or(f64::NAN),
                1,
            ),
            fmt(summary["mean_length_ratio"].as_f64().unwrap_or(f64::NAN), 3),
            fmt(
                summary["mean_rms_cross_track"].as_f64().unwrap_or(f64::NAN),
                3,
            ),
            fmt(
                summary["min_clearance_static"].as_f64().unwrap_or(f64::NAN),
                3,
            ),
            summary["replans"].to_string(),
            summary["stuck_events"].to_string(),
            summary["oscillation_events"].to_string(),
        ]],
    );
    println!("report: {}", args.out.join("report.json").display());
    if rate < args.min_success || cs > 0 || cm > 0 || min_static < floor {
        return Err(MissionFailed(format!(
            "soak below target: success {:.1}% (at least {:.1}%), {cs} static collisions, \
             {cm} contacts while moving, min static clearance {min_static:.3} (at least half \
             the margin, {floor:.3})",
            100.0 * rate,
            100.0 * args.min_success
        ))
        .into());
    }
    Ok(())
}
