//! Occupancy backgrounds as pixels, for maps drawn at one pixel a cell or less: one pixel
//! per `block x block` cells, its shade the share of blocked cells under it, from white (no
//! cell blocked: free floor for sure) to the blocked colour (every cell blocked). "Dark when
//! any cell is blocked" would turn a shelf lattice finer than the block into one black
//! square; the shades keep aisles and cross-aisles visible. PNG pictures get the pixels
//! painted straight into their buffer, SVG pictures an embedded PNG image: millions of
//! one-pixel rectangles would make both slow and an SVG of hundreds of megabytes.

use super::Rgb;
use anyhow::Context;
use planner_core::grid::GridRef;

/// An RGB image placed on the canvas at `(x, y)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Raster {
    /// Left edge on the canvas (pixels).
    pub x: i32,
    /// Top edge on the canvas (pixels).
    pub y: i32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` RGB triples, row by row.
    pub rgb: Vec<u8>,
}

impl Raster {
    /// `grid` at one pixel per `block x block` cells (the last row and column of blocks may
    /// hold fewer cells): white mixed with `blocked` by the share of blocked cells in the
    /// block, so white only where all are free and `blocked` only where all are blocked.
    /// With `unknown` (cells of unknown space, `unknown_rgb`), a block with occupied cells
    /// (blocked, not unknown) is shaded by their share in `blocked`, one with only unknown and
    /// free cells by the unknown share in `unknown_rgb`.
    pub fn occupancy(
        grid: GridRef<'_>,
        unknown: Option<(GridRef<'_>, Rgb)>,
        block: usize,
        at: (i32, i32),
        blocked: Rgb,
    ) -> Raster {
        let block = block.max(1);
        let (w, h) = (grid.width(), grid.height());
        let (bw, bh) = (w.div_ceil(block), h.div_ceil(block));
        let mut rgb = vec![255u8; bw * bh * 3];
        for by in 0..bh {
            let (y0, y1) = (by * block, ((by + 1) * block).min(h) - 1);
            for bx in 0..bw {
                let (x0, x1) = (bx * block, ((bx + 1) * block).min(w) - 1);
                let cells = ((y1 - y0 + 1) * (x1 - x0 + 1)) as u32;
                let rows = y0 as isize..=y1 as isize;
                let (x0, x1) = (x0 as isize, x1 as isize);
                // (colour, count) of the block's shade, if any.
                let shade_of = match unknown {
                    None => {
                        let count = rows.map(|y| grid.row_run_count(y, x0, x1)).sum();
                        (blocked, count)
                    }
                    Some((unknown, unknown_rgb)) => {
                        let (mut occupied, mut unknowns) = (0u32, 0u32);
                        for y in rows {
                            for x in x0..=x1 {
                                if unknown.is_blocked(x, y) {
                                    unknowns += 1;
                                } else if grid.is_blocked(x, y) {
                                    occupied += 1;
                                }
                            }
                        }
                        if occupied > 0 {
                            (blocked, occupied)
                        } else {
                            (unknown_rgb, unknowns)
                        }
                    }
                };
                if shade_of.1 > 0 {
                    let i = (by * bw + bx) * 3;
                    rgb[i..i + 3].copy_from_slice(&shade(shade_of.0, shade_of.1, cells));
                }
            }
        }
        Raster {
            x: at.0,
            y: at.1,
            width: bw as u32,
            height: bh as u32,
            rgb,
        }
    }

    /// Copies the pixels into an RGB canvas buffer of `canvas` (width, height), clipped.
    pub fn paint(&self, buf: &mut [u8], canvas: (u32, u32)) {
        let (cw, ch) = (canvas.0 as i64, canvas.1 as i64);
        let (x0, x1) = (
            (self.x as i64).max(0),
            (self.x as i64 + self.width as i64).min(cw),
        );
        if x0 >= x1 {
            return;
        }
        for row in 0..self.height as i64 {
            let y = self.y as i64 + row;
            if !(0..ch).contains(&y) {
                continue;
            }
            let src = (row * self.width as i64 + (x0 - self.x as i64)) as usize * 3;
            let dst = (y * cw + x0) as usize * 3;
            let n = (x1 - x0) as usize * 3;
            if let (Some(d), Some(s)) = (buf.get_mut(dst..dst + n), self.rgb.get(src..src + n)) {
                d.copy_from_slice(s);
            }
        }
    }

    /// The pixels as an SVG `<image>` element holding a PNG (crisp when scaled).
    pub fn svg_image(&self) -> anyhow::Result<String> {
        let mut png_bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut png_bytes, self.width, self.height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder.write_header().context("encoding the map image")?;
            writer
                .write_image_data(&self.rgb)
                .context("encoding the map image")?;
            writer.finish().context("encoding the map image")?;
        }
        Ok(format!(
            "<image x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" preserveAspectRatio=\"none\" \
             style=\"image-rendering:pixelated\" href=\"data:image/png;base64,{}\"/>",
            self.x,
            self.y,
            self.width,
            self.height,
            base64(&png_bytes)
        ))
    }
}

/// White mixed with `blocked` by `count / cells` (exactly `blocked` when they are equal, never
/// white when `count > 0`).
fn shade(blocked: Rgb, count: u32, cells: u32) -> Rgb {
    if count >= cells {
        return blocked;
    }
    let mix = |c: u8| {
        let toward = (255 - c as u32) * count / cells;
        (255 - toward.max(1)) as u8
    };
    [mix(blocked[0]), mix(blocked[1]), mix(blocked[2])]
}

/// Standard base64 with padding (RFC 4648).
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_core::grid::GridBuf;

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn unknown_space_has_its_own_shade_unless_occupied_cells_share_the_pixel() {
        // 6 x 3 cells in blocks of 3: two pixels. Left: 2 unknown (blocked too) and 1
        // occupied cell; right: 3 unknown cells only.
        let (mut g, mut u) = (GridBuf::new(6, 3).unwrap(), GridBuf::new(6, 3).unwrap());
        for (x, y) in [(0, 0), (1, 0), (3, 0), (4, 1), (5, 2)] {
            g.set_blocked(x, y, true).unwrap();
            u.set_blocked(x, y, true).unwrap();
        }
        g.set_blocked(2, 2, true).unwrap();
        let (dark, grey) = ([0, 0, 0], [100, 100, 100]);
        let r = Raster::occupancy(g.view(), Some((u.view(), grey)), 3, (0, 0), dark);
        assert_eq!(&r.rgb[..3], &shade(dark, 1, 9));
        assert_eq!(&r.rgb[3..], &shade(grey, 3, 9));
        // Without the unknown layer both count as blocked.
        let r = Raster::occupancy(g.view(), None, 3, (0, 0), dark);
        assert_eq!(&r.rgb[..3], &shade(dark, 3, 9));
    }

    #[test]
    fn a_pixel_is_shaded_by_the_share_of_blocked_cells_under_it() {
        // 7 x 5 cells in blocks of 3: 3 x 2 pixels, the last column and row partial.
        let mut g = GridBuf::new(7, 5).unwrap();
        g.set_blocked(4, 1, true).unwrap(); // pixel (1, 0): 1 of 9
        for (x, y) in [(0, 3), (1, 3), (2, 3), (0, 4), (1, 4), (2, 4)] {
            g.set_blocked(x, y, true).unwrap(); // pixel (0, 1): 6 of 6 (a partial block)
        }
        g.set_blocked(6, 4, true).unwrap(); // pixel (2, 1): 1 of 2 (a partial block)
        let r = Raster::occupancy(g.view(), None, 3, (10, 20), [45, 45, 50]);
        assert_eq!((r.width, r.height), (3, 2));
        let px: Vec<&[u8]> = r.rgb.chunks(3).collect();
        assert_eq!(px[0], [255, 255, 255]);
        assert_eq!(px[1], [232, 232, 233]); // 255 - 210 / 9, 255 - 205 / 9
        assert_eq!(px[2], [255, 255, 255]);
        assert_eq!(px[3], [45, 45, 50]);
        assert_eq!(px[4], [255, 255, 255]);
        assert_eq!(px[5], [150, 150, 153]); // 255 - 210 / 2, 255 - 205 / 2
        // Cells outside the map (past the partial blocks) do not count as blocked.
        let free = Raster::occupancy(GridBuf::new(7, 5).unwrap().view(), None, 3, (0, 0), [0; 3]);
        assert!(free.rgb.iter().all(|&v| v == 255));
        // A single blocked cell among many still leaves a mark.
        assert_ne!(shade([254, 254, 254], 1, 10_000), [255, 255, 255]);
        assert_eq!(shade([0, 0, 0], 3, 3), [0, 0, 0]);
    }

    #[test]
    fn paints_clipped_and_encodes_for_svg() {
        let r = Raster {
            x: -1,
            y: 1,
            width: 2,
            height: 2,
            rgb: vec![1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4],
        };
        let mut buf = vec![0u8; 2 * 2 * 3];
        r.paint(&mut buf, (2, 2));
        assert_eq!(buf, [0, 0, 0, 0, 0, 0, 2, 2, 2, 0, 0, 0]);
        let svg = r.svg_image().unwrap();
        assert!(
            svg.starts_with("<image x=\"-1\" y=\"1\" width=\"2\" height=\"2\""),
            "{svg}"
        );
        assert!(
            svg.contains("href=\"data:image/png;base64,iVBORw0KGgo"),
            "{svg}"
        );
    }
}
