//! Moving AI `.map` text: the header, the terrain rows, and writing a grid back as text.
//! Shared by every grid storage through [`GridMut`].

use super::{GridMut, GridRef};
use crate::error::MapError;

/// Reads the header (`type octile`, `height H`, `width W`, `map`, in any order before
/// `map`): the declared size and the lines after it.
pub(super) fn header(text: &[u8]) -> Result<(usize, usize, Lines<'_>), MapError> {
    let mut lines = Lines::new(text);
    let mut width = None;
    let mut height = None;
    let mut saw_type = false;
    loop {
        let (no, line) = lines.next().ok_or(MapError::MalformedHeader {
            line: lines.line_no + 1,
        })?;
        let mut words = line
            .split(|b| *b == b' ' || *b == b'\t')
            .filter(|w| !w.is_empty());
        let key = words.next();
        let value = words.next();
        if words.next().is_some() {
            return Err(MapError::MalformedHeader { line: no });
        }
        match (key, value) {
            (Some(b"type"), Some(kind)) if !saw_type => {
                if kind != b"octile" {
                    return Err(MapError::UnsupportedType);
                }
                saw_type = true;
            }
            (Some(b"height"), Some(v)) if height.is_none() => {
                height = Some(parse_dimension(v).ok_or(MapError::MalformedHeader { line: no })?);
            }
            (Some(b"width"), Some(v)) if width.is_none() => {
                width = Some(parse_dimension(v).ok_or(MapError::MalformedHeader { line: no })?);
            }
            (Some(b"map"), None) => break,
            _ => return Err(MapError::MalformedHeader { line: no }),
        }
    }
    match (width, height, saw_type) {
        (Some(width), Some(height), true) => Ok((width, height, lines)),
        _ => Err(MapError::MalformedHeader {
            line: lines.line_no,
        }),
    }
}

/// The error for a declared size that a storage refused.
pub(super) fn size_error(width: usize, height: usize) -> MapError {
    if width == 0 || height == 0 {
        MapError::EmptyMap
    } else {
        MapError::CapacityExceeded { width, height }
    }
}

/// Fills `grid` from the rows after the header; text after the last row must be blank.
pub(super) fn fill(grid: &mut GridMut<'_>, body: &mut Lines<'_>) -> Result<(), MapError> {
    let height = grid.height;
    for row in 0..height {
        let (_, line) = body.next().ok_or(MapError::MissingRows {
            expected: height,
            found: row,
        })?;
        fill_row(grid, row, line)?;
    }
    for (no, line) in body {
        if !line.iter().all(|b| b.is_ascii_whitespace()) {
            return Err(MapError::TrailingData { line: no });
        }
    }
    Ok(())
}

/// Width and height of bare rows (empty lines skipped; the width is the first row's).
pub(super) fn rows_size(text: &[u8]) -> (usize, usize) {
    let mut rows = Lines::new(text).filter(|(_, l)| !l.is_empty());
    let width = rows.next().map_or(0, |(_, l)| l.len());
    let height = if width == 0 { 0 } else { 1 + rows.count() };
    (width, height)
}

/// Fills `grid` from bare rows (see [`rows_size`]).
pub(super) fn fill_rows(grid: &mut GridMut<'_>, text: &[u8]) -> Result<(), MapError> {
    for (row, (_, line)) in Lines::new(text).filter(|(_, l)| !l.is_empty()).enumerate() {
        fill_row(grid, row, line)?;
    }
    Ok(())
}

fn fill_row(grid: &mut GridMut<'_>, row: usize, line: &[u8]) -> Result<(), MapError> {
    if line.len() != grid.width {
        return Err(MapError::WrongRowLength {
            row: row + 1,
            expected: grid.width,
            found: line.len(),
        });
    }
    for (x, &byte) in line.iter().enumerate() {
        let blocked = match byte {
            b'.' | b'G' => false,
            b'@' | b'O' | b'T' | b'S' | b'W' => true,
            _ => {
                return Err(MapError::UnknownCharacter {
                    row: row + 1,
                    column: x + 1,
                    byte,
                });
            }
        };
        // Cannot fail: row < height and x < width were checked above.
        let _ = grid.set_blocked(x, row, blocked);
    }
    Ok(())
}

/// Writes `grid` as Moving AI `.map` text (`.` free, `@` blocked).
pub(super) fn write(grid: GridRef<'_>, out: &mut impl core::fmt::Write) -> core::fmt::Result {
    write!(
        out,
        "type octile\nheight {}\nwidth {}\nmap\n",
        grid.height(),
        grid.width()
    )?;
    for y in 0..grid.height() as isize {
        for x in 0..grid.width() as isize {
            out.write_char(if grid.is_blocked(x, y) { '@' } else { '.' })?;
        }
        out.write_char('\n')?;
    }
    Ok(())
}

/// Parses a decimal side length; `None` for anything but 1-6 ASCII digits.
fn parse_dimension(text: &[u8]) -> Option<usize> {
    if text.is_empty() || text.len() > 6 {
        return None;
    }
    text.iter().try_fold(0usize, |acc, &b| {
        b.is_ascii_digit().then(|| acc * 10 + (b - b'0') as usize)
    })
}

/// Lines of a byte slice with 1-based numbers, without the `\n` or `\r\n`.
pub(super) struct Lines<'t> {
    rest: &'t [u8],
    line_no: usize,
}

impl<'t> Lines<'t> {
    fn new(text: &'t [u8]) -> Self {
        Lines {
            rest: text,
            line_no: 0,
        }
    }
}

impl<'t> Iterator for Lines<'t> {
    type Item = (usize, &'t [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(n) => (&self.rest[..n], &self.rest[n + 1..]),
            None => (self.rest, &[][..]),
        };
        self.rest = rest;
        self.line_no += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((self.line_no, line))
    }
}
