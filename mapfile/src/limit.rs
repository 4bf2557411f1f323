//! The one size limit of every command that loads or generates a map: `--max-cells`
//! (default 4096 x 4096 cells). Checked on the declared size, before anything is allocated.

/// Default limit: 4096 x 4096 cells (a 4096 x 4096 map is 4 MiB of grid bits, and the
/// planners' per-cell scratch is what really bounds it).
pub const DEFAULT_MAX_CELLS: usize = 4096 * 4096;

/// `--max-cells` values: `N` or `WxH` (also `W*H`), at least 1 cell.
pub fn parse_max_cells(text: &str) -> Result<usize, String> {
    let num = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|e| format!("{s:?}: {e} (expected a cell count N or WxH)"))
    };
    let cells = match text.split_once(['x', 'X', '*']) {
        Some((w, h)) => num(w)?
            .checked_mul(num(h)?)
            .ok_or_else(|| format!("{text}: too many cells"))?,
        None => num(text)?,
    };
    if cells == 0 {
        return Err("the limit must be at least 1 cell".into());
    }
    Ok(cells)
}

/// The limit as people read it: `16777216 cells (4096 x 4096)` when it is a square.
pub fn describe_cells(cells: usize) -> String {
    let side = cells.isqrt();
    if side * side == cells {
        format!("{cells} cells ({side} x {side})")
    } else {
        format!("{cells} cells")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_counts_and_sides() {
        assert_eq!(parse_max_cells("4096x4096"), Ok(DEFAULT_MAX_CELLS));
        assert_eq!(parse_max_cells("16777216"), Ok(DEFAULT_MAX_CELLS));
        assert_eq!(parse_max_cells("8192 X 100"), Ok(819_200));
        assert_eq!(parse_max_cells("3*5"), Ok(15));
        assert!(parse_max_cells("0").is_err());
        assert!(parse_max_cells("0x9").is_err());
        assert!(parse_max_cells("big").is_err());
        assert!(parse_max_cells("99999999999x99999999999").is_err());
        assert_eq!(
            describe_cells(DEFAULT_MAX_CELLS),
            "16777216 cells (4096 x 4096)"
        );
        assert_eq!(describe_cells(1000), "1000 cells");
    }

    #[test]
    fn check_names_source_size_limit_and_flag() {
        let o = crate::MapOptions {
            max_cells: 100,
            ..Default::default()
        };
        assert!(o.check("a.map", 10, 10).is_ok());
        let e = o.check("a.map", 11, 10).unwrap_err();
        let text = e.to_string();
        for part in ["a.map", "11 x 10", "110 cells", "100 cells", "--max-cells"] {
            assert!(text.contains(part), "{text:?} lacks {part:?}");
        }
        assert!(o.check("huge", usize::MAX, 2).is_err());
    }
}
