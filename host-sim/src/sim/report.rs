//! Pictures and JSON of a mission.

use super::mission::{MissionResult, MissionSpec};
use super::world::Kind;
use crate::render::{Disc, Layer, MapPicture, Marker, Series, Shape, Style, convergence_plot};
use planner_core::geometry::{Cell, Point};
use planner_core::grid::GridRef;
use planner_mapfile::MapFrame;
use std::path::Path;

/// Colour of people.
const PERSON: [u8; 3] = [204, 121, 167];
/// Colour of other robots.
const ROBOT: [u8; 3] = [230, 159, 0];

/// What the pictures show of the map besides its cells: unknown space and the world frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct MapLook<'a> {
    /// Unknown space (drawn in its own colour).
    pub unknown: Option<GridRef<'a>>,
    /// The declared world frame (scale bar and axes in metres).
    pub world: Option<MapFrame>,
}

/// Writes `trajectory.{png,svg}` (map, global paths, driven trajectory, obstacles) and, when
/// the first plan has a history, `convergence.{png,svg}` into `dir`.
pub fn save_pictures(
    spec: &MissionSpec,
    result: &MissionResult,
    stations: &[(Cell, &'static str)],
    look: MapLook<'_>,
    dir: &Path,
) -> anyhow::Result<()> {
    let unit = if look.world.is_some() { "m" } else { "cells" };
    let title = format!(
        "{}: {} global path, DWA trajectory ({}, {} replans)",
        spec.name,
        spec.algo.name().to_uppercase(),
        result.outcome,
        result.replans
    );
    let mut pic = MapPicture::new(spec.grid.view(), &title);
    pic.unknown = look.unknown;
    pic.world = look.world;
    let labels: Vec<String> = result
        .plans
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if i == 0 {
                format!("global path (length {:.2} {unit})", p.length)
            } else if i == 1 {
                "replanned paths".to_string()
            } else {
                String::new()
            }
        })
        .collect();
    for (i, p) in result.plans.iter().enumerate() {
        if p.points.is_empty() {
            continue;
        }
        let style = if i == 0 {
            Style::solid([0, 114, 178], 3.0)
        } else {
            Style::dashed([0, 158, 115], 2.0)
        };
        pic.layers.push(Layer::new(&labels[i], &p.points, style));
    }
    let trails: Vec<(&str, &[Point], [u8; 3])> = {
        let mut seen_person = false;
        let mut seen_robot = false;
        result
            .agents
            .iter()
            .filter(|a| a.trail.len() > 1)
            .map(|a| {
                let (label, color) = match a.kind {
                    Kind::Person if !seen_person => {
                        seen_person = true;
                        ("person trails", PERSON)
                    }
                    Kind::Person => ("", PERSON),
                    _ if !seen_robot => {
                        seen_robot = true;
                        ("other robots' trails", ROBOT)
                    }
                    _ => ("", ROBOT),
                };
                (label, a.trail.as_slice(), color)
            })
            .collect()
    };
    for (label, points, color) in &trails {
        pic.layers
            .push(Layer::new(label, points, Style::dashed(*color, 1.0)));
    }
    let driven = format!(
        "driven trajectory (length {:.2} {unit})",
        result.driven_length
    );
    pic.layers.push(Layer::new(
        &driven,
        &result.trajectory,
        Style::solid([0, 0, 0], 2.0),
    ));
    for a in &result.agents {
        let (label, color) = match a.kind {
            Kind::Person => ("person (end of run)", PERSON),
            Kind::Robot => ("other robot (end of run)", ROBOT),
            Kind::Parked => ("parked robot", [90, 90, 90]),
        };
        pic.discs.push(Disc {
            label,
            at: a.pos,
            radius_cells: a.radius,
            color,
        });
    }
    for (cell, label) in stations {
        pic.markers.push(Marker {
            label,
            at: cell.center(),
            shape: if label.starts_with("pick") {
                Shape::Triangle
            } else {
                Shape::Square
            },
            color: if label.starts_with("pick") {
                [86, 180, 233]
            } else {
                [0, 158, 115]
            },
            radius_cells: 0.35,
        });
    }
    pic.start = result.trajectory.first().copied();
    pic.goal = Some(spec.goal.center());
    pic.save_png(&dir.join("trajectory.png"))?;
    pic.save_svg(&dir.join("trajectory.svg"))?;
    if let Some(first) = result.plans.first().filter(|p| !p.history.is_empty()) {
        let label = format!("{} (first plan)", spec.algo.name().to_uppercase());
        convergence_plot(
            &format!("{}: convergence of the global planner", spec.name),
            "iteration",
            "best cost found (cells; before pruning and smoothing)",
            &[Series::new(&label, &first.history)],
            Some(&dir.join("convergence.png")),
            Some(&dir.join("convergence.svg")),
        )?;
    }
    Ok(())
}

/// One line of summary.
pub fn summary(r: &MissionResult) -> String {
    format!(
        "{}: {}, success {}, collisions {} static / {} dynamic ({} while moving), time {:.1} s, driven {:.2} vs planned {:.2} m, RMS cross-track {:.3} m, min clearance {:.3} m static / {} dynamic, replans {}, stuck {}, oscillations {}",
        r.name,
        r.outcome,
        r.success,
        r.collisions_static,
        r.collisions_dynamic,
        r.contacts_moving,
        r.time_to_goal.unwrap_or(r.sim_time),
        r.driven_length,
        r.planned_length,
        r.rms_cross_track,
        r.min_clearance_static,
        r.min_clearance_dynamic
            .map_or_else(|| "—".to_string(), |c| format!("{c:.3} m")),
        r.replans,
        r.stuck_events,
        r.oscillation_events
    )
}
