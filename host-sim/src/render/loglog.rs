//! Log-log plots of measured points: time against map size, one line per planner.

use super::{Figure, Style, drawing_error, font, rgb, write_files};
use plotters::coord::Shift;
use plotters::element::{DashedPathElement, DynElement};
use plotters::prelude::*;
use std::ops::Range;
use std::path::Path;

/// One line of points `(x, y)`, both positive (others are left out).
#[derive(Clone, Copy, Debug)]
pub struct Points<'a> {
    /// Legend text.
    pub label: &'a str,
    /// The points, in order of `x`.
    pub points: &'a [(f64, f64)],
    /// Stroke (the palette colour of the line's index when `None`).
    pub style: Option<Style>,
}

/// Draws `lines` on logarithmic axes with markers and a legend, and writes a PNG and/or an
/// SVG. No positive point gives empty axes, not an error.
pub fn loglog_plot(
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Points<'_>],
    png: Option<&Path>,
    svg: Option<&Path>,
) -> anyhow::Result<()> {
    let plot = LogLog {
        title,
        x_label,
        y_label,
        lines,
    };
    write_files(&plot, png, svg)
}

struct LogLog<'s> {
    title: &'s str,
    x_label: &'s str,
    y_label: &'s str,
    lines: &'s [Points<'s>],
}

impl LogLog<'_> {
    fn points(&self, i: usize) -> Vec<(f64, f64)> {
        self.lines[i]
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
            .collect()
    }

    /// The range of one coordinate over every line, widened by a fifth of a decade.
    fn range(&self, pick: impl Fn((f64, f64)) -> f64) -> Range<f64> {
        let (lo, hi) = (0..self.lines.len())
            .flat_map(|i| self.points(i))
            .map(&pick)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        if lo > hi {
            return 1.0..10.0;
        }
        let pad = 10f64.powf(0.2);
        (lo / pad)..(hi * pad)
    }
}

impl Figure for LogLog<'_> {
    fn size(&self) -> (u32, u32) {
        (1000, 680)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()> {
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, font(24.0))
            .margin(18)
            .x_label_area_size(56)
            .y_label_area_size(86)
            .build_cartesian_2d(
                self.range(|p| p.0).log_scale(),
                self.range(|p| p.1).log_scale(),
            )
            .map_err(drawing_error)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .label_style(font(15.0))
            .axis_desc_style(font(17.0))
            .x_label_formatter(&fmt_log)
            .y_label_formatter(&fmt_log)
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()
            .map_err(drawing_error)?;
        for (i, line) in self.lines.iter().enumerate() {
            let style = line.style.unwrap_or(Style {
                width: 2.0,
                ..Style::palette(i)
            });
            let width = style.width.round().max(1.0) as u32;
            let shape = rgb(style.color).stroke_width(width);
            let points = self.points(i);
            let annotation = if style.dashed {
                chart.draw_series(DashedLineSeries::new(points.clone(), 10, 6, shape))
            } else {
                chart.draw_series(LineSeries::new(points.clone(), shape))
            }
            .map_err(drawing_error)?;
            annotation.label(line.label).legend(
                move |(x, y)| -> DynElement<'static, DB, (i32, i32)> {
                    if style.dashed {
                        DashedPathElement::new(vec![(x, y), (x + 24, y)], 6, 4, shape).into_dyn()
                    } else {
                        PathElement::new(vec![(x, y), (x + 24, y)], shape).into_dyn()
                    }
                },
            );
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&p| Circle::new(p, 4, rgb(style.color).filled())),
                )
                .map_err(drawing_error)?;
        }
        if !self.lines.is_empty() {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .margin(12)
                .legend_area_size(30)
                .label_font(font(15.0))
                .background_style(WHITE.mix(0.9))
                .border_style(RGBColor(120, 120, 120))
                .draw()
                .map_err(drawing_error)?;
        }
        Ok(())
    }
}

/// A tick label on a log axis: plain numbers from 0.01 to 10^6, else scientific.
fn fmt_log(v: &f64) -> String {
    let v = *v;
    if !(1e-2..1e6).contains(&v.abs()) {
        return format!("{v:.0e}");
    }
    if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) {
        return format!("{}", v.round() as i64);
    }
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::super::testutil::{png_size, temp_dir};
    use super::*;

    #[test]
    fn loglog_plot_writes_png_and_svg_with_labels() {
        let a = [(256.0, 0.1), (1024.0, 1.6), (4096.0, 25.0)];
        let b = [(256.0, 0.05), (1024.0, 0.0), (4096.0, 0.2)];
        let lines = [
            Points {
                label: "A*",
                points: &a,
                style: None,
            },
            Points {
                label: "anyangle",
                points: &b,
                style: Some(Style::dashed([0, 0, 0], 2.0)),
            },
        ];
        let dir = temp_dir("loglog");
        let (png, svg) = (dir.join("t.png"), dir.join("t.svg"));
        loglog_plot("Time", "side", "ms", &lines, Some(&png), Some(&svg)).unwrap();
        assert_eq!(png_size(&png), (1000, 680));
        let text = std::fs::read_to_string(&svg).unwrap();
        for label in ["A*", "anyangle", "Time", "side", "ms"] {
            assert!(text.contains(label), "SVG lacks {label:?}");
        }
        // No positive point: empty axes.
        loglog_plot("none", "x", "y", &[], Some(&png), None).unwrap();
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn log_ticks_are_short() {
        assert_eq!(fmt_log(&1000.0), "1000");
        assert_eq!(fmt_log(&0.25), "0.25");
        assert_eq!(fmt_log(&1e7), "1e7");
    }
}
