//! Exit statuses of `host-sim`, one meaning each, so that scripts can tell a mission that
//! failed from input that could not be used:
//!
//! | status | meaning |
//! |---|---|
//! | 0 | done: every mission arrived (simulator), every query answered (`plan`) |
//! | 1 | anything else went wrong (an output file, the planner service, a bug) |
//! | 2 | bad input: a map, start, goal, query file or option that cannot be used ([`BadInput`], a [`MapLoadError`](planner_mapfile::MapLoadError), or a command-line error) |
//! | 3 | a mission did not arrive, collided, or a scenario or soak missed its target ([`MissionFailed`]) |

use std::fmt;

/// Exit status of bad input (clap's own for command-line errors).
pub const BAD_INPUT: u8 = 2;
/// Exit status of a failed mission.
pub const MISSION_FAILED: u8 = 3;

/// Input that cannot be used, with what is wrong with it.
#[derive(Debug)]
pub struct BadInput(pub String);

impl fmt::Display for BadInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// A mission (or scenario, or soak) that did not do what it had to.
#[derive(Debug)]
pub struct MissionFailed(pub String);

impl fmt::Display for MissionFailed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MissionFailed {}

/// Bad input as an `anyhow` error.
pub fn bad(text: impl Into<String>) -> anyhow::Error {
    BadInput(text.into()).into()
}

/// The exit status of an error: what its chain holds decides.
pub fn status(e: &anyhow::Error) -> u8 {
    let is = |f: &dyn Fn(&(dyn std::error::Error + 'static)) -> bool| e.chain().any(f);
    if is(&|c| c.is::<MissionFailed>()) {
        MISSION_FAILED
    } else if is(&|c| c.is::<BadInput>() || c.is::<planner_mapfile::MapLoadError>()) {
        BAD_INPUT
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn each_kind_of_failure_has_its_status() {
        assert_eq!(status(&bad("no")), BAD_INPUT);
        let wrapped = Err::<(), _>(bad("inner")).context("outer").unwrap_err();
        assert_eq!(status(&wrapped), BAD_INPUT);
        let map = planner_mapfile::load_map(
            std::path::Path::new("/nonexistent/m.map"),
            &Default::default(),
        )
        .unwrap_err();
        assert_eq!(status(&map.into()), BAD_INPUT);
        assert_eq!(status(&MissionFailed("x".into()).into()), MISSION_FAILED);
        assert_eq!(status(&anyhow::anyhow!("disk full")), 1);
    }
}
