//! The ROS map_server loader from memory (`planner_mapfile::ros::parse`, reached through
//! `host_sim::mapfile`): arbitrary YAML text and image bytes (PGM or PNG, often with a valid
//! magic so the decoders are reached).
//! No panic and no huge allocation (a header announcing a big image is refused before
//! decoding); every failure is a `RosMapError`; an accepted map has the image's size
//! (rows of 1..=MAX_ROW_PIXELS, at most LIMIT cells), valid thresholds, a positive
//! resolution and a finite origin, and its cells follow `pixel_blocked`.
#![no_main]

use arbitrary::{Arbitrary, Unstructured};
use host_sim::mapfile::ros::{self, MAX_ROW_PIXELS, RosMapError};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

/// The size limit the loader is given (the CLI's `--max-cells`).
const LIMIT: usize = 1024 * 1024;

/// How the image bytes start: mostly a real header so that the decoders' bodies run.
#[derive(Arbitrary, Debug)]
enum ImageInput {
    Raw(Vec<u8>),
    /// Binary PGM: `P5 w h maxval` then the pixels.
    Pgm {
        w: u16,
        h: u16,
        maxval: u16,
        pixels: Vec<u8>,
    },
    /// ASCII PGM header text then arbitrary body.
    PgmText(String, Vec<u8>),
    /// PNG signature then arbitrary chunks.
    Png(Vec<u8>),
}

impl ImageInput {
    fn bytes(&self) -> Vec<u8> {
        match self {
            ImageInput::Raw(b) => b.clone(),
            ImageInput::Pgm {
                w,
                h,
                maxval,
                pixels,
            } => {
                let mut b = format!("P5\n{} {}\n{}\n", w % 40, h % 40, maxval).into_bytes();
                b.extend_from_slice(pixels);
                b
            }
            ImageInput::PgmText(head, body) => {
                let mut b = format!("P2\n{head}").into_bytes();
                b.extend_from_slice(body);
                b
            }
            ImageInput::Png(rest) => {
                let mut b = b"\x89PNG\r\n\x1a\n".to_vec();
                b.extend_from_slice(rest);
                b
            }
        }
    }
}

/// The YAML: either free text or the usual keys with arbitrary values.
#[derive(Arbitrary, Debug)]
enum YamlInput {
    Text(String),
    Fields {
        resolution: String,
        origin: String,
        negate: Option<String>,
        occupied: Option<String>,
        free: Option<String>,
        mode: Option<String>,
        extra: String,
    },
}

impl YamlInput {
    fn text(&self) -> String {
        match self {
            YamlInput::Text(t) => t.clone(),
            YamlInput::Fields {
                resolution,
                origin,
                negate,
                occupied,
                free,
                mode,
                extra,
            } => {
                let mut t = format!("image: map.pgm\nresolution: {resolution}\norigin: {origin}\n");
                for (k, v) in [
                    ("negate", negate),
                    ("occupied_thresh", occupied),
                    ("free_thresh", free),
                    ("mode", mode),
                ] {
                    if let Some(v) = v {
                        t.push_str(&format!("{k}: {v}\n"));
                    }
                }
                t.push_str(extra);
                t
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let (Ok(yaml), Ok(image)) = (YamlInput::arbitrary(&mut u), ImageInput::arbitrary(&mut u))
    else {
        return;
    };
    let text = yaml.text();
    let bytes = image.bytes();
    let meta = ros::parse_yaml(&text, Path::new("/maps"));
    match ros::parse(&text, Path::new("/maps"), &bytes, LIMIT) {
        Ok(map) => {
            let meta = meta.expect("parse accepted YAML that parse_yaml refuses");
            let m = &map.meta;
            assert_eq!(
                (m.resolution, m.origin, m.negate, m.mode),
                (meta.resolution, meta.origin, meta.negate, meta.mode)
            );
            assert!(m.resolution.is_finite() && m.resolution > 0.0);
            assert!(m.origin.iter().all(|v| v.is_finite()));
            assert!(
                0.0 <= m.free_thresh
                    && m.free_thresh < m.occupied_thresh
                    && m.occupied_thresh <= 1.0
            );
            let (w, h) = (map.grid.width(), map.grid.height());
            assert!((1..=MAX_ROW_PIXELS).contains(&w) && h >= 1 && w * h <= LIMIT);
            assert_eq!(m.height, h);
            // The corner cells map back to themselves through the world frame.
            for (x, y) in [(0, 0), (w - 1, h - 1)] {
                let (wx, wy) = m.cell_to_world(x, y);
                if m.origin.iter().all(|v| v.abs() < 1e6)
                    && m.resolution > 1e-6
                    && m.resolution < 1e6
                {
                    assert_eq!(m.world_to_cell(wx, wy), Some((x, y)), "{m:?}");
                }
            }
        }
        Err(e) => {
            // A YAML error comes first; otherwise the error is about the image.
            match &meta {
                Err(_) => assert!(
                    !matches!(
                        e,
                        RosMapError::Image { .. }
                            | RosMapError::BadSize(..)
                            | RosMapError::TooLarge { .. }
                            | RosMapError::Io(..)
                    ),
                    "{e:?}"
                ),
                Ok(_) => assert!(
                    matches!(
                        e,
                        RosMapError::Image { .. }
                            | RosMapError::BadSize(..)
                            | RosMapError::TooLarge { .. }
                    ),
                    "{e:?}"
                ),
            }
            let _ = e.to_string();
        }
    }
});
