//! An independent path validator for benchmarks: `f64` separating-axis tests of each segment
//! against each nearby blocked square, written without planner-core's geometry, so a bug in
//! the shared collision rule cannot hide itself.

use planner_core::grid::GridRef;

/// Why a path failed.
#[derive(Debug, Clone, PartialEq)]
pub enum Invalid {
    /// No waypoint.
    Empty,
    /// First or last waypoint is not the requested cell centre.
    Endpoints,
    /// Segment `index` touches a blocked cell or leaves the map.
    Collision {
        /// Index of the segment's first waypoint.
        index: usize,
    },
}

/// Checks that `path` runs from `start` to `goal` (cell centres) and that no segment touches
/// a blocked cell, even at a corner, or leaves the map.
pub fn check(
    grid: GridRef<'_>,
    path: &[[f32; 2]],
    start: (u16, u16),
    goal: (u16, u16),
) -> Result<(), Invalid> {
    let wide: Vec<[f64; 2]> = path.iter().map(|p| [p[0] as f64, p[1] as f64]).collect();
    check_f64(grid, &wide, start, goal)
}

/// [`check`] of waypoints as read back from text (`f64`): what a consumer of printed paths
/// computes with.
pub fn check_f64(
    grid: GridRef<'_>,
    path: &[[f64; 2]],
    start: (u16, u16),
    goal: (u16, u16),
) -> Result<(), Invalid> {
    let (Some(first), Some(last)) = (path.first(), path.last()) else {
        return Err(Invalid::Empty);
    };
    let centre = |c: (u16, u16)| [c.0 as f64, c.1 as f64];
    if *first != centre(start) || *last != centre(goal) {
        return Err(Invalid::Endpoints);
    }
    check_segments(grid, path)
}

/// Whether no segment of `path` touches a blocked cell or leaves the map (a single waypoint
/// is checked as a point), whatever its ends.
pub fn check_segments(grid: GridRef<'_>, path: &[[f64; 2]]) -> Result<(), Invalid> {
    let Some(first) = path.first() else {
        return Err(Invalid::Empty);
    };
    let single = [*first, *first];
    let segments: Vec<&[[f64; 2]]> = if path.len() == 1 {
        vec![&single[..]]
    } else {
        path.windows(2).collect()
    };
    for (index, w) in segments.into_iter().enumerate() {
        let (a, b) = (w[0], w[1]);
        if !(a.iter().chain(&b).all(|v| v.is_finite())) {
            return Err(Invalid::Collision { index });
        }
        let (x0, x1) = (
            a[0].min(b[0]).floor() as i64 - 1,
            a[0].max(b[0]).ceil() as i64 + 1,
        );
        let (y0, y1) = (
            a[1].min(b[1]).floor() as i64 - 1,
            a[1].max(b[1]).ceil() as i64 + 1,
        );
        for y in y0..=y1 {
            for x in x0..=x1 {
                if grid.is_blocked(x as isize, y as isize) && touches(a, b, x as f64, y as f64) {
                    return Err(Invalid::Collision { index });
                }
            }
        }
    }
    Ok(())
}

/// Whether segment `ab` meets the closed unit square centred on `(cx, cy)`: no separating
/// axis among the square's two axes and the segment's normal.
fn touches(a: [f64; 2], b: [f64; 2], cx: f64, cy: f64) -> bool {
    let overlap = |lo1: f64, hi1: f64, lo2: f64, hi2: f64| lo1 <= hi2 && lo2 <= hi1;
    if !overlap(a[0].min(b[0]), a[0].max(b[0]), cx - 0.5, cx + 0.5)
        || !overlap(a[1].min(b[1]), a[1].max(b[1]), cy - 0.5, cy + 0.5)
    {
        return false;
    }
    let n = [b[1] - a[1], a[0] - b[0]];
    let seg = n[0] * a[0] + n[1] * a[1];
    let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
        .map(|(dx, dy)| n[0] * (cx + dx) + n[1] * (cy + dy));
    let (lo, hi) = corners
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    lo <= seg && seg <= hi
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_core::grid::GridBuf;

    #[test]
    fn corners_count_and_clear_paths_pass() {
        let g = GridBuf::parse_rows(b"...\n.@.\n...\n").unwrap();
        assert!(
            check(
                g.view(),
                &[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]],
                (0, 0),
                (2, 2)
            )
            .is_ok()
        );
        assert_eq!(
            check(g.view(), &[[0.0, 0.0], [2.0, 2.0]], (0, 0), (2, 2)),
            Err(Invalid::Collision { index: 0 })
        );
        // Touching only the corner (1.5, 0.5) of the blocked cell.
        assert_eq!(
            check(g.view(), &[[1.0, 0.0], [2.0, 1.0]], (1, 0), (2, 1)),
            Err(Invalid::Collision { index: 0 })
        );
        assert!(check(g.view(), &[[0.0, 0.0], [2.0, 0.4]], (0, 0), (2, 0)).is_err());
        assert_eq!(
            check(g.view(), &[[0.0, 0.0], [-0.6, 0.0]], (0, 0), (0, 0)),
            Err(Invalid::Endpoints)
        );
        assert_eq!(
            check(
                g.view(),
                &[[0.0, 0.0], [0.0, -0.6], [0.0, 0.0]],
                (0, 0),
                (0, 0)
            ),
            Err(Invalid::Collision { index: 0 })
        );
        assert_eq!(check(g.view(), &[], (0, 0), (0, 0)), Err(Invalid::Empty));
    }

    /// The margin a printed waypoint may lose matters: a segment that clears a corner by
    /// 1e-6 cell is valid, the same segment with its end moved by the 7.6e-6 cell an f32's
    /// shortest decimal may be off near 200 cells is not.
    #[test]
    fn read_back_values_decide() {
        let g = GridBuf::parse_rows(b"...\n.@.\n...\n").unwrap();
        // Cell (1, 1) has its top-right corner at (1.5, 0.5).
        let clear = [[0.0, 0.499996], [2.0, 0.5]];
        assert!(check_segments(g.view(), &clear).is_ok());
        let moved = [[0.0, 0.499996], [2.0, 0.5000076]];
        assert_eq!(
            check_segments(g.view(), &moved),
            Err(Invalid::Collision { index: 0 })
        );
        assert!(check_segments(g.view(), &[[0.0, f64::NAN], [1.0, 0.0]]).is_err());
        assert_eq!(
            check_f64(g.view(), &[[0.0, 0.0], [2.0, 0.0]], (0, 0), (2, 0)),
            Ok(())
        );
    }
}
