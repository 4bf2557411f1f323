//! ROS `map_server` maps: a YAML file naming an image (PGM or PNG) with its metadata.
//!
//! ```yaml
//! image: shelf.pgm          # relative to the YAML file
//! resolution: 0.05          # metres per pixel (= per cell)
//! origin: [-1.0, -2.0, 0.0] # world pose of the LOWER-LEFT pixel: x, y, yaw
//! negate: 0                 # 0/1 or false/true
//! occupied_thresh: 0.65
//! free_thresh: 0.196
//! mode: trinary             # trinary (default), scale or raw
//! ```
//!
//! Pixels become cells one to one. Image row 0 is the **top** of the map, which is also
//! row 0 of the planner's grid (y down), so the grid is the image as displayed; the world
//! frame of ROS has y up, so [`RosMeta::cell_to_world`] flips rows: the centre of cell
//! `(x, y)` is at `origin + ((x + 0.5) res, (height - 1 - y + 0.5) res)` (yaw ignored, as
//! map_server's consumers mostly do).
//!
//! Occupancy of a pixel with shade `s` (mean of the colour channels, 0..255):
//! `p = (255 - s) / 255`, or `s / 255` when `negate`. `trinary` and `scale`: `p >
//! occupied_thresh` is occupied, `p < free_thresh` is free, anything between is unknown (for
//! `scale` it would be a graded cost: this binary grid keeps it unknown). A fully
//! transparent pixel (alpha 0) is unknown. `raw`: the shade is the occupancy in percent, 0 to
//! 100, anything above 100 unknown; free below `free_thresh * 100`. Unknown and occupied
//! cells are both blocked for planning.

use crate::maps::HostGrid;
use serde::Deserialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// Why a ROS map could not be loaded.
#[derive(Debug)]
pub enum RosMapError {
    /// A file could not be read.
    Io(PathBuf, std::io::Error),
    /// The YAML is malformed or lacks a required field.
    Yaml(String),
    /// `resolution` is not a positive finite number.
    BadResolution,
    /// `origin` is not three finite numbers.
    BadOrigin,
    /// Thresholds outside `0..=1` or `free_thresh >= occupied_thresh`.
    BadThresholds,
    /// `mode` is not trinary, scale or raw.
    BadMode(String),
    /// `negate` is not 0, 1, true or false.
    BadNegate(String),
    /// The image could not be decoded.
    Image(String),
    /// The image is empty or larger than the host grid (1024 x 1024).
    BadSize(u32, u32),
}

impl fmt::Display for RosMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RosMapError::Io(p, e) => write!(f, "cannot read {}: {e}", p.display()),
            RosMapError::Yaml(e) => write!(f, "malformed map YAML: {e}"),
            RosMapError::BadResolution => f.write_str("resolution must be a positive number"),
            RosMapError::BadOrigin => f.write_str("origin must be [x, y, yaw] numbers"),
            RosMapError::BadThresholds => {
                f.write_str("need 0 <= free_thresh < occupied_thresh <= 1")
            }
            RosMapError::BadMode(m) => write!(f, "mode {m:?}: expected trinary, scale or raw"),
            RosMapError::BadNegate(v) => write!(f, "negate {v}: expected 0, 1, true or false"),
            RosMapError::Image(e) => write!(f, "cannot decode map image: {e}"),
            RosMapError::BadSize(w, h) => write!(f, "image of {w} x {h} pixels not supported"),
        }
    }
}

impl std::error::Error for RosMapError {}

/// `mode` of a map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Occupied / free / unknown by thresholds (the default).
    Trinary,
    /// Like trinary here (graded values count as unknown).
    Scale,
    /// Pixel values are occupancy percentages.
    Raw,
}

/// The metadata of a map.
#[derive(Clone, Debug, PartialEq)]
pub struct RosMeta {
    /// The image file (resolved against the YAML's folder).
    pub image: PathBuf,
    /// Metres per cell.
    pub resolution: f64,
    /// World pose of the lower-left pixel's corner: x, y, yaw.
    pub origin: [f64; 3],
    /// Whether white means occupied.
    pub negate: bool,
    /// Occupied above this probability.
    pub occupied_thresh: f64,
    /// Free below this probability.
    pub free_thresh: f64,
    /// Interpretation of the pixels.
    pub mode: Mode,
    /// Image height in pixels (rows), for the y flip.
    pub height: usize,
}

impl RosMeta {
    /// World coordinates (metres, y up) of the centre of cell `(x, y)` (y down).
    pub fn cell_to_world(&self, x: usize, y: usize) -> (f64, f64) {
        (
            self.origin[0] + (x as f64 + 0.5) * self.resolution,
            self.origin[1] + ((self.height - 1 - y) as f64 + 0.5) * self.resolution,
        )
    }

    /// The cell holding a world point, if it is on or right of and above the origin.
    pub fn world_to_cell(&self, wx: f64, wy: f64) -> Option<(usize, usize)> {
        let cx = ((wx - self.origin[0]) / self.resolution).floor();
        let row_up = ((wy - self.origin[1]) / self.resolution).floor();
        if !(cx >= 0.0 && row_up >= 0.0 && (row_up as usize) < self.height) {
            return None;
        }
        Some((cx as usize, self.height - 1 - row_up as usize))
    }
}

/// A loaded map.
pub struct RosMap {
    /// The grid.
    pub grid: Box<HostGrid>,
    /// Its metadata.
    pub meta: RosMeta,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Negate {
    Bool(bool),
    Int(i64),
    Text(String),
}

#[derive(Deserialize)]
struct RawYaml {
    image: String,
    resolution: f64,
    origin: Vec<f64>,
    #[serde(default)]
    negate: Option<Negate>,
    #[serde(default = "default_occ")]
    occupied_thresh: f64,
    #[serde(default = "default_free")]
    free_thresh: f64,
    #[serde(default)]
    mode: Option<String>,
}

fn default_occ() -> f64 {
    0.65
}
fn default_free() -> f64 {
    0.196
}

/// Parses the YAML text; `dir` resolves a relative image path.
pub fn parse_yaml(text: &str, dir: &Path) -> Result<RosMeta, RosMapError> {
    let raw: RawYaml =
        serde_saphyr::from_str(text).map_err(|e| RosMapError::Yaml(e.to_string()))?;
    if !(raw.resolution.is_finite() && raw.resolution > 0.0) {
        return Err(RosMapError::BadResolution);
    }
    if raw.origin.len() != 3 || raw.origin.iter().any(|v| !v.is_finite()) {
        return Err(RosMapError::BadOrigin);
    }
    let negate = match raw.negate {
        None => false,
        Some(Negate::Bool(b)) => b,
        Some(Negate::Int(0)) => false,
        Some(Negate::Int(1)) => true,
        Some(Negate::Int(i)) => return Err(RosMapError::BadNegate(i.to_string())),
        Some(Negate::Text(t)) => return Err(RosMapError::BadNegate(t)),
    };
    let (occ, free) = (raw.occupied_thresh, raw.free_thresh);
    if !(occ.is_finite()
        && free.is_finite()
        && (0.0..=1.0).contains(&occ)
        && (0.0..=1.0).contains(&free)
        && free < occ)
    {
        return Err(RosMapError::BadThresholds);
    }
    let mode = match raw.mode.as_deref().map(str::to_ascii_lowercase).as_deref() {
        None | Some("trinary") => Mode::Trinary,
        Some("scale") => Mode::Scale,
        Some("raw") => Mode::Raw,
        Some(other) => return Err(RosMapError::BadMode(other.to_string())),
    };
    let image = PathBuf::from(&raw.image);
    let image = if image.is_absolute() {
        image
    } else {
        dir.join(image)
    };
    Ok(RosMeta {
        image,
        resolution: raw.resolution,
        origin: [raw.origin[0], raw.origin[1], raw.origin[2]],
        negate,
        occupied_thresh: occ,
        free_thresh: free,
        mode,
        height: 0,
    })
}

/// Whether a pixel (shade 0..255, alpha 0..255) is blocked under `meta`.
pub fn pixel_blocked(meta: &RosMeta, shade: u8, alpha: u8) -> bool {
    match meta.mode {
        Mode::Raw => {
            let p = shade as f64;
            p > 100.0 || p >= meta.free_thresh * 100.0
        }
        Mode::Trinary | Mode::Scale => {
            if alpha == 0 {
                return true; // unknown
            }
            let s = shade as f64;
            let p = if meta.negate { s } else { 255.0 - s } / 255.0;
            // Occupied (p > occupied_thresh) and unknown (in between) are both blocked.
            p >= meta.free_thresh
        }
    }
}

/// Loads a YAML file and its image.
pub fn load(path: &Path) -> Result<RosMap, RosMapError> {
    let text = std::fs::read_to_string(path).map_err(|e| RosMapError::Io(path.into(), e))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut meta = parse_yaml(&text, dir)?;
    let bytes = std::fs::read(&meta.image).map_err(|e| RosMapError::Io(meta.image.clone(), e))?;
    let img = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| RosMapError::Image(e.to_string()))?
        .decode()
        .map_err(|e| RosMapError::Image(e.to_string()))?
        .to_luma_alpha8();
    let (w, h) = img.dimensions();
    if w == 0 || h == 0 || w > 1024 || h > 1024 {
        return Err(RosMapError::BadSize(w, h));
    }
    meta.height = h as usize;
    let mut grid =
        Box::new(HostGrid::new(w as usize, h as usize).map_err(|_| RosMapError::BadSize(w, h))?);
    for (x, y, px) in img.enumerate_pixels() {
        if pixel_blocked(&meta, px.0[0], px.0[1]) {
            grid.set_blocked(x as usize, y as usize, true)
                .map_err(|_| RosMapError::BadSize(w, h))?;
        }
    }
    Ok(RosMap { grid, meta })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(text: &str) -> Result<RosMeta, RosMapError> {
        parse_yaml(text, Path::new("/maps"))
    }

    #[test]
    fn parses_fields_and_defaults() {
        let m =
            meta("image: a.pgm\nresolution: 0.05\norigin: [-1.0, 2.5, 0.0]\nnegate: 1\n").unwrap();
        assert_eq!(m.image, PathBuf::from("/maps/a.pgm"));
        assert!(m.negate);
        assert_eq!(m.mode, Mode::Trinary);
        assert_eq!((m.occupied_thresh, m.free_thresh), (0.65, 0.196));
        let m = meta("image: a.png\nresolution: 1\norigin: [0, 0, 0]\nnegate: false\nmode: raw\n")
            .unwrap();
        assert!(!m.negate);
        assert_eq!(m.mode, Mode::Raw);
    }

    #[test]
    fn malformed_yaml_is_typed() {
        let base = "image: a.pgm\norigin: [0, 0, 0]\n";
        assert!(matches!(meta(base), Err(RosMapError::Yaml(_))));
        assert!(matches!(
            meta(&format!("{base}resolution: -1\n")),
            Err(RosMapError::BadResolution)
        ));
        assert!(matches!(
            meta("image: a\nresolution: 1\norigin: [0, 0]\n"),
            Err(RosMapError::BadOrigin)
        ));
        assert!(matches!(
            meta(&format!("{base}resolution: 1\nnegate: 2\n")),
            Err(RosMapError::BadNegate(_))
        ));
        assert!(matches!(
            meta(&format!("{base}resolution: 1\nnegate: maybe\n")),
            Err(RosMapError::BadNegate(_))
        ));
        assert!(matches!(
            meta(&format!("{base}resolution: 1\nmode: fancy\n")),
            Err(RosMapError::BadMode(_))
        ));
        assert!(matches!(
            meta(&format!("{base}resolution: 1\nfree_thresh: 0.9\n")),
            Err(RosMapError::BadThresholds)
        ));
        assert!(matches!(meta("image: [: nope"), Err(RosMapError::Yaml(_))));
    }

    #[test]
    fn thresholds_and_negate() {
        let mut m = meta("image: a\nresolution: 1\norigin: [0, 0, 0]\n").unwrap();
        assert!(!pixel_blocked(&m, 254, 255)); // white: free
        assert!(pixel_blocked(&m, 0, 255)); // black: occupied
        assert!(pixel_blocked(&m, 205, 255)); // ROS grey 205: unknown
        assert!(pixel_blocked(&m, 254, 0)); // transparent: unknown
        m.negate = true;
        assert!(pixel_blocked(&m, 254, 255));
        assert!(!pixel_blocked(&m, 0, 255));
        m.mode = Mode::Raw;
        assert!(!pixel_blocked(&m, 0, 255));
        assert!(pixel_blocked(&m, 100, 255));
        assert!(pixel_blocked(&m, 255, 255));
    }

    #[test]
    fn world_frame_flips_rows() {
        let mut m = meta("image: a\nresolution: 0.5\norigin: [10.0, 20.0, 0]\n").unwrap();
        m.height = 4;
        // Bottom-left cell (0, 3) has its centre a quarter metre from the origin.
        assert_eq!(m.cell_to_world(0, 3), (10.25, 20.25));
        assert_eq!(m.cell_to_world(0, 0), (10.25, 21.75));
        assert_eq!(m.world_to_cell(10.25, 21.75), Some((0, 0)));
        assert_eq!(m.world_to_cell(9.0, 20.0), None);
    }
}
