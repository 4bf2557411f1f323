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
//! `p = (255 - s) / 255`, or `s / 255` when `negate`. `trinary`: `p > occupied_thresh` is
//! occupied, `p < free_thresh` is free, anything between is unknown (nav2_map_server's
//! rule). `scale`: the same thresholds, but a value between them is a graded cost in
//! map_server, which this binary grid counts as occupied; a pixel that is not opaque is
//! unknown. In every mode a fully transparent pixel (alpha 0) is unknown. `raw`: the shade
//! is the occupancy in percent, 0 to 100, anything above 100 unknown; free below
//! `free_thresh * 100`, occupied from there. Occupied cells are blocked for planning;
//! unknown cells are blocked or free as the caller says ([`Unknown`], `--unknown`), and
//! kept apart ([`RosMap::unknown`]) so that pictures can show them in their own colour.
//!
//! The image's declared size is checked against the caller's limit (`--max-cells`) before
//! it is decoded; rows are written into the grid a word at a time.

use crate::options::Unknown;
use planner_core::grid::{GridBuf, MAX_ROW_WORDS};
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
    /// The image could not be decoded (truncated, malformed, not PGM or PNG).
    Image {
        /// The image file (as the YAML names it, resolved).
        image: PathBuf,
        /// The decoder's message.
        detail: String,
    },
    /// The image is empty or has rows of more than [`MAX_ROW_PIXELS`] pixels.
    BadSize(u32, u32),
    /// The image has more pixels than the caller's limit.
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The limit, in cells.
        max_cells: usize,
    },
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
            RosMapError::Image { image, detail } => {
                write!(f, "cannot decode map image {}: {detail}", image.display())
            }
            RosMapError::BadSize(w, h) => write!(
                f,
                "image of {w} x {h} pixels not supported (empty, or rows over {MAX_ROW_PIXELS} pixels)"
            ),
            RosMapError::TooLarge {
                width,
                height,
                max_cells,
            } => write!(
                f,
                "image of {width} x {height} pixels is over the limit of {max_cells} cells"
            ),
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
    /// The grid: occupied cells blocked, unknown cells as the [`Unknown`] policy says.
    pub grid: GridBuf,
    /// The unknown cells (blocked bits), when the image has any.
    pub unknown: Option<GridBuf>,
    /// Its metadata.
    pub meta: RosMeta,
}

/// What a pixel says about its cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Occupancy {
    /// Free space.
    Free,
    /// An obstacle.
    Occupied,
    /// Not mapped.
    Unknown,
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

/// What a pixel (shade 0..255, alpha 0..255) says under `meta` (see the module
/// documentation).
pub fn pixel_state(meta: &RosMeta, shade: u8, alpha: u8) -> Occupancy {
    if alpha == 0 {
        return Occupancy::Unknown;
    }
    match meta.mode {
        Mode::Raw => {
            let p = shade as f64;
            if p > 100.0 {
                Occupancy::Unknown
            } else if p >= meta.free_thresh * 100.0 {
                Occupancy::Occupied
            } else {
                Occupancy::Free
            }
        }
        Mode::Trinary | Mode::Scale => {
            if meta.mode == Mode::Scale && alpha != 255 {
                return Occupancy::Unknown;
            }
            let s = shade as f64;
            let p = if meta.negate { s } else { 255.0 - s } / 255.0;
            if p > meta.occupied_thresh {
                Occupancy::Occupied
            } else if p < meta.free_thresh {
                Occupancy::Free
            } else if meta.mode == Mode::Scale {
                // A graded cost in map_server: not free on a binary grid.
                Occupancy::Occupied
            } else {
                Occupancy::Unknown
            }
        }
    }
}

/// Whether a pixel is blocked under `meta` when unknown space is blocked (the default).
pub fn pixel_blocked(meta: &RosMeta, shade: u8, alpha: u8) -> bool {
    pixel_state(meta, shade, alpha) != Occupancy::Free
}

/// Widest image accepted: the longest grid row that the bulk row writer takes (8192).
pub const MAX_ROW_PIXELS: usize = MAX_ROW_WORDS * 32;

/// Loads a YAML file and its image (read from the path the YAML names), unknown space
/// blocked; an image of more than `max_cells` pixels is [`RosMapError::TooLarge`] before it
/// is decoded.
pub fn load(path: &Path, max_cells: usize) -> Result<RosMap, RosMapError> {
    load_with(path, max_cells, Unknown::Blocked)
}

/// [`load`] with unknown space blocked or free.
pub fn load_with(path: &Path, max_cells: usize, unknown: Unknown) -> Result<RosMap, RosMapError> {
    let text = std::fs::read_to_string(path).map_err(|e| RosMapError::Io(path.into(), e))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let meta = parse_yaml(&text, dir)?;
    let bytes = std::fs::read(&meta.image).map_err(|e| RosMapError::Io(meta.image.clone(), e))?;
    decode(meta, &bytes, max_cells, unknown)
}

/// Parses a map from memory: the YAML text (`dir` resolves its relative image path, which
/// is recorded in the metadata but not read) and the image file's bytes (PGM or PNG), unknown
/// space blocked. This is [`load`] without the file system; every failure is a
/// [`RosMapError`].
pub fn parse(
    yaml: &str,
    dir: &Path,
    image: &[u8],
    max_cells: usize,
) -> Result<RosMap, RosMapError> {
    parse_with(yaml, dir, image, max_cells, Unknown::Blocked)
}

/// [`parse`] with unknown space blocked or free.
pub fn parse_with(
    yaml: &str,
    dir: &Path,
    image: &[u8],
    max_cells: usize,
    unknown: Unknown,
) -> Result<RosMap, RosMapError> {
    decode(parse_yaml(yaml, dir)?, image, max_cells, unknown)
}

/// The decoder's message, saying "truncated" when the data ended early (the decoders say
/// only "failed to fill whole buffer").
fn image_detail(e: &image::ImageError) -> String {
    let text = e.to_string();
    let early = matches!(e, image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof)
        || text.contains("fill whole buffer");
    if early {
        format!("truncated: the pixel data ends early ({text})")
    } else {
        text
    }
}

/// Decodes the image bytes under `meta` into the grid.
fn decode(
    mut meta: RosMeta,
    bytes: &[u8],
    max_cells: usize,
    unknown: Unknown,
) -> Result<RosMap, RosMapError> {
    let file = meta.image.clone();
    let image_error = |e: image::ImageError| RosMapError::Image {
        image: file.clone(),
        detail: image_detail(&e),
    };
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| image_error(e.into()))
    };
    // The declared size first: a header announcing a huge image must not make the decoder
    // allocate it.
    let (w, h) = reader()?.into_dimensions().map_err(image_error)?;
    if w == 0 || h == 0 {
        return Err(RosMapError::BadSize(w, h));
    }
    if (w as usize).saturating_mul(h as usize) > max_cells {
        return Err(RosMapError::TooLarge {
            width: w,
            height: h,
            max_cells,
        });
    }
    if w as usize > MAX_ROW_PIXELS {
        return Err(RosMapError::BadSize(w, h));
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(w);
    limits.max_image_height = Some(h);
    // The pixels at up to 16-bit RGBA (8 bytes), with room for the decoder's buffers.
    limits.max_alloc = Some((w as u64 * h as u64 * 8).saturating_add(16 << 20));
    let mut r = reader()?;
    r.limits(limits);
    let img = r.decode().map_err(image_error)?;
    if (img.width(), img.height()) != (w, h) {
        let (w, h) = (img.width(), img.height());
        return Err(RosMapError::BadSize(w, h));
    }
    meta.height = h as usize;
    let new_grid = || GridBuf::new(w as usize, h as usize).map_err(|_| RosMapError::BadSize(w, h));
    let (mut grid, mut unknown_cells) = (new_grid()?, new_grid()?);
    // The state of each shade, opaque or fully transparent (only alpha 0 differs, and, in
    // scale mode, any alpha below 255).
    let opaque: [Occupancy; 256] = std::array::from_fn(|s| pixel_state(&meta, s as u8, 255));
    let clear: [Occupancy; 256] = std::array::from_fn(|s| pixel_state(&meta, s as u8, 0));
    let blocked = |o: Occupancy| match o {
        Occupancy::Free => false,
        Occupancy::Occupied => true,
        Occupancy::Unknown => unknown == Unknown::Blocked,
    };
    let scale = meta.mode == Mode::Scale;
    let mut any_unknown = false;
    for (target, want_unknown) in [(&mut grid, false), (&mut unknown_cells, true)] {
        let bit = |o: Occupancy| {
            if want_unknown {
                o == Occupancy::Unknown
            } else {
                blocked(o)
            }
        };
        let filled = match &img {
            // Grey PGMs and PNGs (the usual map_server image): no conversion, no copy.
            image::DynamicImage::ImageLuma8(g) => {
                fill(target, g.as_raw(), 1, |p| bit(opaque[p[0] as usize]))
            }
            other => {
                let la = other.to_luma_alpha8();
                fill(target, la.as_raw(), 2, |p| {
                    let state = match p[1] {
                        255 => opaque[p[0] as usize],
                        0 => clear[p[0] as usize],
                        _ if scale => Occupancy::Unknown,
                        _ => opaque[p[0] as usize],
                    };
                    bit(state)
                })
            }
        };
        filled.map_err(|_| RosMapError::BadSize(w, h))?;
        if want_unknown {
            let v = target.view();
            any_unknown = (0..h as isize).any(|y| v.row_run_count(y, 0, w as isize - 1) > 0);
        }
    }
    Ok(RosMap {
        grid,
        unknown: any_unknown.then_some(unknown_cells),
        meta,
    })
}

/// Writes `pixels` (rows of `grid.width()` pixels of `channels` bytes) into `grid`, a whole
/// row of bits at a time.
fn fill(
    grid: &mut GridBuf,
    pixels: &[u8],
    channels: usize,
    blocked: impl Fn(&[u8]) -> bool,
) -> Result<(), planner_core::error::GridError> {
    let stride = grid.width() * channels;
    grid.view_mut().fill_rows(|y, words| {
        let row = pixels.get(y * stride..(y + 1) * stride).unwrap_or(&[]);
        for (x, px) in row.chunks_exact(channels).enumerate() {
            if blocked(px) {
                words[x / 32] |= 1 << (x % 32);
            }
        }
    })
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
    fn states_follow_map_server_per_mode() {
        let mut m = meta("image: a\nresolution: 1\norigin: [0, 0, 0]\n").unwrap();
        // Trinary: p = (255 - s) / 255; above 0.65 occupied, below 0.196 free, else unknown.
        assert_eq!(pixel_state(&m, 254, 255), Occupancy::Free);
        assert_eq!(pixel_state(&m, 0, 255), Occupancy::Occupied);
        assert_eq!(pixel_state(&m, 205, 255), Occupancy::Unknown);
        assert_eq!(pixel_state(&m, 254, 128), Occupancy::Free);
        assert_eq!(pixel_state(&m, 254, 0), Occupancy::Unknown);
        // Scale: between the thresholds is a graded cost (occupied here); not opaque is
        // unknown.
        m.mode = Mode::Scale;
        assert_eq!(pixel_state(&m, 205, 255), Occupancy::Occupied);
        assert_eq!(pixel_state(&m, 254, 128), Occupancy::Unknown);
        assert_eq!(pixel_state(&m, 254, 255), Occupancy::Free);
        // Raw: the value is the occupancy in percent; above 100 unknown.
        m.mode = Mode::Raw;
        assert_eq!(pixel_state(&m, 0, 255), Occupancy::Free);
        assert_eq!(pixel_state(&m, 19, 255), Occupancy::Free);
        assert_eq!(pixel_state(&m, 20, 255), Occupancy::Occupied);
        assert_eq!(pixel_state(&m, 100, 255), Occupancy::Occupied);
        assert_eq!(pixel_state(&m, 101, 255), Occupancy::Unknown);
    }

    const YAML: &str = "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n";
    const LIMIT: usize = 4096 * 4096;

    #[test]
    fn parses_from_bytes() {
        // 3 x 2: white, black, ROS grey / white, white, black.
        let mut pgm = b"P5\n3 2\n255\n".to_vec();
        pgm.extend_from_slice(&[254, 0, 205, 254, 254, 0]);
        let map = parse(YAML, Path::new("/maps"), &pgm, LIMIT).unwrap();
        assert_eq!((map.grid.width(), map.grid.height()), (3, 2));
        assert_eq!(map.meta.height, 2);
        assert_eq!(map.meta.image, PathBuf::from("/maps/m.pgm"));
        let g = map.grid.view();
        let blocked: Vec<bool> = (0..2)
            .flat_map(|y| (0..3).map(move |x| (x, y)))
            .map(|(x, y)| g.is_blocked(x, y))
            .collect();
        assert_eq!(blocked, [false, true, true, false, false, true]);
        // The YAML is checked before the image.
        assert!(matches!(
            parse(
                "image: m\nresolution: 0\norigin: [0, 0, 0]\n",
                Path::new("."),
                &pgm,
                LIMIT
            ),
            Err(RosMapError::BadResolution)
        ));
    }

    #[test]
    fn bad_images_are_typed_name_the_file_and_are_never_allocated() {
        // A header announcing 60000 x 60000 pixels with no data: refused from the header
        // (the decoder would otherwise try to allocate 3.6 GB).
        let huge = b"P5\n60000 60000\n255\n".to_vec();
        assert!(matches!(
            parse(YAML, Path::new("."), &huge, LIMIT),
            Err(RosMapError::TooLarge {
                width: 60000,
                height: 60000,
                max_cells: LIMIT
            })
        ));
        let mut small = b"P5\n5 3\n255\n".to_vec();
        small.extend_from_slice(&[254; 15]);
        assert!(parse(YAML, Path::new("."), &small, 15).is_ok());
        assert!(matches!(
            parse(YAML, Path::new("."), &small, 14),
            Err(RosMapError::TooLarge {
                width: 5,
                height: 3,
                max_cells: 14
            })
        ));
        // Rows longer than the bulk row writer takes.
        let wide = format!("P5\n{} 1\n255\n", MAX_ROW_PIXELS + 1).into_bytes();
        assert!(matches!(
            parse(YAML, Path::new("."), &wide, LIMIT),
            Err(RosMapError::BadSize(..))
        ));
        // Truncated pixel data, a bad header, not an image at all, an empty file, a cut PNG:
        // each an error naming the image file.
        for bytes in [
            &b"P5\n4 4\n255\n\x00\x01"[..],
            &b"P5\n4 x\n255\n"[..],
            &b"hello, world"[..],
            &b""[..],
            &b"\x89PNG\r\n\x1a\n\x00\x00"[..],
        ] {
            let r = parse(YAML, Path::new("/maps"), bytes, LIMIT);
            match r {
                Err(e @ RosMapError::Image { .. }) => {
                    assert!(e.to_string().contains("/maps/m.pgm"), "{e}")
                }
                other => panic!("{bytes:?}: {:?}", other.err()),
            }
        }
    }

    #[test]
    fn pixels_of_every_format_follow_pixel_blocked() {
        // The same 2 x 2 picture as grey PGM, grey + alpha PNG and RGB PNG.
        let shades = [0u8, 254, 205, 254];
        let alpha = [255u8, 255, 255, 0];
        let png = |color: png::ColorType, data: &[u8]| {
            let mut out = Vec::new();
            let mut enc = png::Encoder::new(&mut out, 2, 2);
            enc.set_color(color);
            enc.set_depth(png::BitDepth::Eight);
            let mut w = enc.write_header().unwrap();
            w.write_image_data(data).unwrap();
            w.finish().unwrap();
            out
        };
        let mut pgm = b"P5\n2 2\n255\n".to_vec();
        pgm.extend_from_slice(&shades);
        let la: Vec<u8> = shades
            .iter()
            .zip(alpha)
            .flat_map(|(&s, a)| [s, a])
            .collect();
        let rgb: Vec<u8> = shades.iter().flat_map(|&s| [s, s, s]).collect();
        let m = meta(YAML).unwrap();
        for (bytes, transparent_last) in [
            (pgm, false),
            (png(png::ColorType::GrayscaleAlpha, &la), true),
            (png(png::ColorType::Rgb, &rgb), false),
        ] {
            let map = parse(YAML, Path::new("."), &bytes, LIMIT).unwrap();
            for (i, &s) in shades.iter().enumerate() {
                let a = if transparent_last && i == 3 { 0 } else { 255 };
                let (x, y) = ((i % 2) as isize, (i / 2) as isize);
                assert_eq!(
                    map.grid.view().is_blocked(x, y),
                    pixel_blocked(&m, s, a),
                    "{i}"
                );
            }
        }
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
