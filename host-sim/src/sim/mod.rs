//! The simulator: a differential-drive robot driven by the DWA local planner along global
//! paths, among static shelves and dynamic obstacles (people, other robots), with replanning
//! through a [`planner::GlobalPlanner`].
//!
//! - [`ipc`]: the global planner over iceoryx2 (client of `planner-server`);
//! - `zenoh` (feature `zenoh`): the global planner over Zenoh (client of `planner-server
//!   --transport zenoh`, on any host);
//! - [`kinematics`]: differential drive with limits;
//! - [`robot`]: the robot in metres, and in the cells of a map;
//! - [`safety`]: its static margin and protective field;
//! - [`world`]: people and robots moving along aisles (scripted and random);
//! - [`mission`]: one mission and its measurements;
//! - [`pathfit`]: global paths pushed off the walls before DWA follows them;
//! - [`site`]: the map a mission runs on, inflated for its robot, and its start and goal;
//! - [`scenarios`]: the hard cases (`host-sim scenarios`, `tests/scenarios.rs`);
//! - [`report`]: pictures and JSON.

pub mod ipc;
pub mod kinematics;
pub mod mission;
pub mod pathfit;
pub mod planner;
pub mod report;
pub mod robot;
pub mod safety;
pub mod scenarios;
pub mod site;
pub mod world;
#[cfg(feature = "zenoh")]
pub mod zenoh;
