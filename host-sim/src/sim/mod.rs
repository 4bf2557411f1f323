//! The simulator: a differential-drive robot driven by the DWA local planner along global
//! paths, among static shelves and dynamic obstacles (people, other robots), with replanning
//! through a [`planner::GlobalPlanner`].
//!
//! - [`ipc`]: the global planner over iceoryx2 (client of `planner-server`);
//! - [`kinematics`]: differential drive with limits;
//! - [`world`]: people and robots moving along aisles (scripted and random);
//! - [`mission`]: one mission and its measurements;
//! - [`pathfit`]: global paths pushed off the walls before DWA follows them;
//! - [`scenarios`]: the hard cases (`host-sim scenarios`, `tests/scenarios.rs`);
//! - [`report`]: pictures and JSON.

pub mod ipc;
pub mod kinematics;
pub mod mission;
pub mod pathfit;
pub mod planner;
pub mod report;
pub mod scenarios;
pub mod world;
