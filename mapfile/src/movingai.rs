//! Moving AI `.map` files into a [`GridBuf`] sized at run time.

use crate::error::MapLoadError;
use crate::options::MapOptions;
use planner_core::error::MapError;
use planner_core::grid::GridBuf;
use std::path::Path;

/// Reads and parses a Moving AI `.map` file; a declared size over `options.max_cells` is
/// [`MapLoadError::TooLarge`] before the grid is allocated.
pub fn load(path: &Path, options: &MapOptions) -> Result<GridBuf, MapLoadError> {
    let bytes = std::fs::read(path).map_err(|error| MapLoadError::Read {
        path: path.into(),
        error,
    })?;
    parse(&bytes, path, options)
}

/// Parses `.map` text read from `path` (named in errors).
pub fn parse(bytes: &[u8], path: &Path, options: &MapOptions) -> Result<GridBuf, MapLoadError> {
    GridBuf::parse_movingai(bytes, options.max_cells).map_err(|error| match error {
        // The parser refuses a size over the limit and sides over u16::MAX alike: only the
        // first is ours to name.
        MapError::CapacityExceeded { width, height } => options
            .check(&path.display().to_string(), width, height)
            .err()
            .unwrap_or(MapLoadError::MovingAi {
                path: path.into(),
                error,
            }),
        error => MapLoadError::MovingAi {
            path: path.into(),
            error,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn over_the_limit_is_too_large_and_other_errors_name_the_file() {
        let text = b"type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n";
        let p = Path::new("dir/w.map");
        let g = parse(text, p, &MapOptions::default()).unwrap();
        assert!(g.view().is_blocked(1, 1) && (g.width(), g.height()) == (4, 3));
        let e = parse(
            text,
            p,
            &MapOptions {
                max_cells: 11,
                ..MapOptions::default()
            },
        )
        .unwrap_err();
        assert!(
            matches!(&e, MapLoadError::TooLarge { width: 4, height: 3, max_cells: 11, source } if source == "dir/w.map"),
            "{e:?}"
        );
        // A side the grid cannot address is the parser's error, not the limit's.
        let wide = b"type octile\nheight 1\nwidth 70000\nmap\n";
        let e = parse(
            wide,
            p,
            &MapOptions {
                max_cells: 1000,
                ..MapOptions::default()
            },
        )
        .unwrap_err();
        assert!(matches!(e, MapLoadError::TooLarge { .. }), "{e:?}");
        let e = parse(wide, p, &MapOptions::default()).unwrap_err();
        assert!(matches!(e, MapLoadError::MovingAi { .. }), "{e:?}");
        assert!(e.to_string().contains("dir/w.map"), "{e}");
        let e = load(Path::new("/nonexistent/x.map"), &MapOptions::default()).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/x.map"), "{e}");
    }
}
