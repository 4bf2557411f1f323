//! Map files into planner grids, the same way for every command that reads one (`host-sim
//! plan`, `run`, `bench`, `planner-client`'s uploads to the planner service):
//!
//! - [`movingai`]: Moving AI `.map` text;
//! - [`ros`]: ROS `map_server` YAML + PGM/PNG (trinary, scale and raw modes, negate,
//!   thresholds), with unknown space kept apart and blocked or free as asked ([`Unknown`]);
//! - [`frame`]: the map's world frame (resolution, origin, y up) and `--frame cells|world`;
//! - [`options`]: `--max-cells` and `--unknown`, [`limit`]: the size limit's parsing and
//!   wording; [`error`]: every failure as a [`MapLoadError`] naming the file.
//!
//! [`load_map`] is the loader: the declared size is checked against the limit before the
//! grid or the image is allocated, into a [`GridBuf`] sized at run time.
//!
//! This is its own crate because both `host-sim` and `planner-ipc` need it and `host-sim`
//! depends on `planner-ipc`: it depends on neither.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod error;
pub mod frame;
pub mod limit;
pub mod movingai;
pub mod options;
pub mod ros;

pub use error::MapLoadError;
pub use frame::{Frame, MapFrame};
pub use limit::DEFAULT_MAX_CELLS;
pub use options::{MapOptions, Unknown};

use planner_core::grid::GridBuf;
use std::path::Path;

/// A loaded map.
#[derive(Debug)]
pub struct LoadedMap {
    /// The grid: occupied cells blocked, unknown cells as `--unknown` says.
    pub grid: GridBuf,
    /// The cells of unknown space (blocked bits), when the map has any (ROS maps).
    pub unknown: Option<GridBuf>,
    /// A short name for titles: the file with its folder (`turtlebot3/map.yaml`), since
    /// ROS maps are mostly called `map.yaml`.
    pub name: String,
    /// Where the map sits in the world: the YAML's resolution and origin, or 1 m a cell
    /// ([`MapFrame::assumed`]) for a Moving AI map.
    pub frame: MapFrame,
}

/// The name of a map file for titles: `folder/file`, or the file alone.
pub fn display_name(path: &Path) -> String {
    let file = path.file_name().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into(),
    );
    match path
        .parent()
        .and_then(Path::file_name)
        .map(|d| d.to_string_lossy())
    {
        Some(dir) if !dir.is_empty() => format!("{dir}/{file}"),
        _ => file,
    }
}

/// Loads a map file: `.yaml`/`.yml` is a ROS `map_server` map (its image is read from the
/// path the YAML names), anything else Moving AI `.map` text. A map of more than
/// `options.max_cells` cells is [`MapLoadError::TooLarge`], found from the declared size
/// before the grid or the image is allocated.
pub fn load_map(path: &Path, options: &MapOptions) -> Result<LoadedMap, MapLoadError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let (grid, unknown, frame) = match ext.as_deref() {
        Some("yaml") | Some("yml") => {
            let m = ros::load_with(path, options.max_cells, options.unknown).map_err(|error| {
                match error {
                    ros::RosMapError::TooLarge { width, height, .. } => MapLoadError::TooLarge {
                        source: path.display().to_string(),
                        width: width as usize,
                        height: height as usize,
                        max_cells: options.max_cells,
                    },
                    error => MapLoadError::Ros {
                        path: path.into(),
                        error,
                    },
                }
            })?;
            let frame = MapFrame {
                resolution: m.meta.resolution,
                origin: [m.meta.origin[0], m.meta.origin[1]],
                width: m.grid.width(),
                height: m.grid.height(),
                declared: true,
            };
            (m.grid, m.unknown, frame)
        }
        _ => {
            let grid = movingai::load(path, options)?;
            let frame = MapFrame::assumed(grid.width(), grid.height());
            (grid, None, frame)
        }
    };
    Ok(LoadedMap {
        grid,
        unknown,
        name: display_name(path),
        frame,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("planner-mapfile-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn loads_both_formats_into_the_same_grid() {
        let dir = temp_dir("both");
        std::fs::write(
            dir.join("m.map"),
            "type octile\nheight 2\nwidth 3\nmap\n.@.\n...\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("m.yaml"),
            "image: m.pgm\nresolution: 0.05\norigin: [-1, 2, 0]\n",
        )
        .unwrap();
        let mut pgm = b"P5\n3 2\n255\n".to_vec();
        pgm.extend_from_slice(&[254, 0, 254, 254, 254, 254]);
        std::fs::write(dir.join("m.pgm"), pgm).unwrap();
        let o = MapOptions::default();
        let a = load_map(&dir.join("m.map"), &o).unwrap();
        let b = load_map(&dir.join("m.yaml"), &o).unwrap();
        assert_eq!(a.grid, b.grid);
        let folder = dir.file_name().unwrap().to_string_lossy().into_owned();
        assert_eq!(a.name, format!("{folder}/m.map"));
        assert_eq!(a.frame, MapFrame::assumed(3, 2));
        assert_eq!(
            b.frame,
            MapFrame {
                resolution: 0.05,
                origin: [-1.0, 2.0],
                width: 3,
                height: 2,
                declared: true
            }
        );
        assert!(a.unknown.is_none() && b.unknown.is_none());
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn unknown_space_is_kept_apart_and_blocked_or_free_as_asked() {
        let dir = temp_dir("unknown");
        std::fs::write(
            dir.join("m.yaml"),
            "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n",
        )
        .unwrap();
        // Free, occupied, unknown (ROS grey 205) / free, unknown, free.
        let mut pgm = b"P5\n3 2\n255\n".to_vec();
        pgm.extend_from_slice(&[254, 0, 205, 254, 205, 254]);
        std::fs::write(dir.join("m.pgm"), pgm).unwrap();
        let cells = |g: &GridBuf| -> Vec<bool> {
            (0..2)
                .flat_map(|y| (0..3).map(move |x| (x, y)))
                .map(|(x, y)| g.view().is_blocked(x, y))
                .collect()
        };
        let blocked = load_map(&dir.join("m.yaml"), &MapOptions::default()).unwrap();
        assert_eq!(
            cells(&blocked.grid),
            [false, true, true, false, true, false]
        );
        let unknown = blocked.unknown.as_ref().unwrap();
        assert_eq!(cells(unknown), [false, false, true, false, true, false]);
        let free = MapOptions {
            unknown: Unknown::Free,
            ..MapOptions::default()
        };
        let open = load_map(&dir.join("m.yaml"), &free).unwrap();
        assert_eq!(cells(&open.grid), [false, true, false, false, false, false]);
        assert_eq!(open.unknown.as_ref(), Some(unknown));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn errors_name_the_file_and_the_limit() {
        let dir = temp_dir("errors");
        std::fs::write(
            dir.join("m.yaml"),
            "image: m.pgm\nresolution: 1\norigin: [0, 0, 0]\n",
        )
        .unwrap();
        let mut pgm = b"P5\n30 20\n255\n".to_vec();
        pgm.extend_from_slice(&[254; 600]);
        std::fs::write(dir.join("m.pgm"), &pgm).unwrap();
        let small = MapOptions {
            max_cells: 599,
            ..MapOptions::default()
        };
        let e = load_map(&dir.join("m.yaml"), &small).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(
                e,
                MapLoadError::TooLarge {
                    width: 30,
                    height: 20,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(
            text.contains("m.yaml") && text.contains("--max-cells"),
            "{text}"
        );
        // A truncated image names the YAML and the image, and says it is truncated.
        std::fs::write(dir.join("m.pgm"), &pgm[..300]).unwrap();
        let e = load_map(&dir.join("m.yaml"), &MapOptions::default()).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("m.yaml") && text.contains("m.pgm") && text.contains("truncated"),
            "{text}"
        );
        // A missing image too.
        std::fs::remove_file(dir.join("m.pgm")).unwrap();
        let e = load_map(&dir.join("m.yaml"), &MapOptions::default()).unwrap_err();
        assert!(e.to_string().contains("m.pgm"), "{e}");
        // A missing map file.
        let e = load_map(&dir.join("none.map"), &MapOptions::default()).unwrap_err();
        assert!(e.to_string().contains("none.map"), "{e}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn display_names_keep_the_folder() {
        assert_eq!(
            display_name(Path::new("tests/data/ros/turtlebot3/map.yaml")),
            "turtlebot3/map.yaml"
        );
        assert_eq!(display_name(Path::new("map.yaml")), "map.yaml");
    }
}
