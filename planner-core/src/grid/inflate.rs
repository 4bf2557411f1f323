//! Inflation by a robot radius as a dilation of the blocked set, a row of words at a time.
//!
//! The structuring element is every offset `(dx, dy)` whose unit squares come closer than
//! the radius: with `g(d) = max(|d| - 1, 0)`, the gap `g(dx)^2 + g(dy)^2 < r^2`. For each
//! `|dy| = k` that is a run `|dx| <= w_k`, so an output row is the OR over `dy` of the
//! source rows spread sideways by `w_|dy|` (shifts on whole words), with the outside of the
//! map blocked.

use super::{GridMut, GridRef, MAX_ROW_WORDS, word_at};
use crate::error::GridError;

pub(super) fn check_radius(radius: f32) -> Result<(), GridError> {
    if !radius.is_finite() || radius < 0.0 {
        return Err(GridError::InvalidRadius);
    }
    Ok(())
}

/// Writes `src` inflated by `radius` into `out`, an all-free grid of the same size.
pub(super) fn inflate(
    src: GridRef<'_>,
    radius: f32,
    out: &mut GridMut<'_>,
) -> Result<(), GridError> {
    check_radius(radius)?;
    if out.width != src.width() || out.height != src.height() {
        return Err(GridError::SizeMismatch);
    }
    let (w, h) = (src.width(), src.height());
    let row_words = w.div_ceil(32);
    // Offsets are capped at one past the longer side: a longer one lands outside the map,
    // and so does the capped offset, which is closer (a huge finite radius must not loop
    // for ever).
    let cap = w.max(h) + 1;
    let gap = |d: usize| d.saturating_sub(1) as f32;
    let reach = (libm::ceilf(radius) as usize).min(cap);
    // The sideways reach of rows `k` away; None when no cell of them is close (row 0 always
    // counts: a blocked cell stays blocked).
    let spread = |k: usize| -> Option<usize> {
        let gk = gap(k);
        if k > 0 && gk * gk >= radius * radius {
            return None;
        }
        let mut d = 0;
        while d < cap && {
            let g = gap(d + 1);
            g * g + gk * gk < radius * radius
        } {
            d += 1;
        }
        Some(d)
    };
    if row_words > MAX_ROW_WORDS {
        return Err(GridError::CapacityExceeded);
    }
    let mut acc = [0u32; MAX_ROW_WORDS];
    let mut row = [0u32; MAX_ROW_WORDS];
    let acc = &mut acc[..row_words];
    let row = &mut row[..row_words];
    let tail = if w % 32 == 0 {
        !0
    } else {
        (1u32 << (w % 32)) - 1
    };
    for y in 0..h {
        acc.fill(0);
        'rows: for k in 0..=reach {
            let Some(d) = spread(k) else { break };
            for dy in [-(k as isize), k as isize] {
                let sy = y as isize + dy;
                if sy < 0 || sy >= h as isize {
                    acc.fill(!0);
                    break 'rows;
                }
                let base = sy as usize * w;
                for (i, word) in row.iter_mut().enumerate() {
                    *word = word_at(src.bits, base + 32 * i);
                }
                if let Some(last) = row.last_mut() {
                    *last &= tail;
                }
                spread_row(row, d);
                // Cells within `d` of either side see the outside of the map.
                for x in (0..d.min(w)).chain(w.saturating_sub(d)..w) {
                    row[x / 32] |= 1 << (x % 32);
                }
                for (a, r) in acc.iter_mut().zip(row.iter()) {
                    *a |= *r;
                }
                if k == 0 {
                    break;
                }
            }
        }
        out.write_row(y, acc);
    }
    out.rebuild_columns();
    Ok(())
}

/// `row[x] |= row[x - j] | row[x + j]` for every `1 <= j <= d` (bits beyond the row stay
/// as they are; the caller masks the last word).
fn spread_row(row: &mut [u32], d: usize) {
    let mut covered = 0;
    while covered < d {
        let step = (covered + 1).min(d - covered);
        shift_or(row, step, true);
        shift_or(row, step, false);
        covered += step;
    }
}

/// `row[x] |= row[x - step]` (`up`) or `row[x] |= row[x + step]`, on the values before the
/// call: words are visited so that each reads only words not yet updated.
fn shift_or(row: &mut [u32], step: usize, up: bool) {
    let (q, r) = (step / 32, (step % 32) as u32);
    let n = row.len();
    let get = |row: &[u32], i: isize| -> u32 {
        if i < 0 || i as usize >= n {
            0
        } else {
            row[i as usize]
        }
    };
    if up {
        for i in (0..n).rev() {
            let i = i as isize;
            let lo = get(row, i - q as isize);
            let lower = get(row, i - q as isize - 1);
            let v = if r == 0 {
                lo
            } else {
                (lo << r) | (lower >> (32 - r))
            };
            row[i as usize] |= v;
        }
    } else {
        for i in 0..n {
            let i = i as isize;
            let hi = get(row, i + q as isize);
            let higher = get(row, i + q as isize + 1);
            let v = if r == 0 {
                hi
            } else {
                (hi >> r) | (higher << (32 - r))
            };
            row[i as usize] |= v;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::grid::{Grid, GridRef, words_for};

    type G = Grid<{ words_for(80, 70) }>;

    /// The definition, cell by cell: blocked when some blocked cell (or the outside) is
    /// closer than `radius`.
    fn brute(src: GridRef<'_>, radius: f32, x: isize, y: isize) -> bool {
        let cap = src.width().max(src.height()) as isize + 1;
        let reach = (libm::ceilf(radius) as isize).min(cap);
        if src.is_blocked(x, y) {
            return true;
        }
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let gx = (dx.unsigned_abs() as f32 - 1.0).max(0.0);
                let gy = (dy.unsigned_abs() as f32 - 1.0).max(0.0);
                if gx * gx + gy * gy < radius * radius && src.is_blocked(x + dx, y + dy) {
                    return true;
                }
            }
        }
        false
    }

    #[test]
    fn word_rows_agree_with_the_definition() {
        let mut state = 0x1234_5678_9abc_def0u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (w, h) in [(80, 70), (33, 5), (64, 64), (1, 9), (31, 2)] {
            let mut g = G::new(w, h).unwrap();
            for y in 0..h {
                for x in 0..w {
                    if next() % 23 == 0 {
                        g.set_blocked(x, y, true).unwrap();
                    }
                }
            }
            for radius in [0.0, 0.3, 0.5, 1.0, 1.2, 2.0, 2.5, 3.7, 6.0, 1e30] {
                let mut out = G::new(1, 1).unwrap();
                g.inflate_into(radius, &mut out).unwrap();
                for y in 0..h as isize {
                    for x in 0..w as isize {
                        let want = brute(g.view(), radius, x, y);
                        assert_eq!(
                            out.view().is_blocked(x, y),
                            want,
                            "{w}x{h} r {radius} at {x},{y}"
                        );
                        // The column layout was rebuilt from the rows.
                        assert_eq!(
                            out.view().column_run_blocked(x, y, y),
                            want,
                            "columns {w}x{h} r {radius} at {x},{y}"
                        );
                    }
                }
            }
        }
    }
}
