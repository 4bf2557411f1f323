//! Line plots of per-iteration values: convergence curves like the papers' figures.

use super::{Figure, Style, drawing_error, font, rgb, write_files};
use plotters::coord::Shift;
use plotters::element::{DashedPathElement, DynElement};
use plotters::prelude::*;
use std::ops::Range;
use std::path::Path;

/// One curve: `values[i]` is the value after iteration `i + 1`.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// Legend text.
    pub label: &'a str,
    /// One value per iteration; non-finite values leave a gap.
    pub values: &'a [f32],
    /// Stroke; `None` takes the palette colour of the series' index, 2 px, solid (so the same
    /// algorithm gets the same colour as its layer when both use `Style::palette(i)`'s colour).
    pub style: Option<Style>,
}

impl<'a> Series<'a> {
    /// A series in the default style.
    pub const fn new(label: &'a str, values: &'a [f32]) -> Self {
        Series {
            label,
            values,
            style: None,
        }
    }

    /// The same series with the given stroke.
    pub const fn with_style(self, style: Style) -> Self {
        Series {
            style: Some(style),
            ..self
        }
    }
}

/// Draws `series` against the iteration number (1, 2, ...) with a legend, and writes a PNG
/// and/or an SVG. Empty or all-non-finite input gives empty axes, not an error.
pub fn convergence_plot(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series<'_>],
    png: Option<&Path>,
    svg: Option<&Path>,
) -> anyhow::Result<()> {
    let plot = Plot {
        title,
        x_label,
        y_label,
        series,
    };
    write_files(&plot, png, svg)
}

struct Plot<'s> {
    title: &'s str,
    x_label: &'s str,
    y_label: &'s str,
    series: &'s [Series<'s>],
}

impl Plot<'_> {
    fn style(&self, i: usize) -> Style {
        self.series[i].style.unwrap_or_else(|| Style {
            width: 2.0,
            ..Style::palette(i)
        })
    }

    /// Iterations shown: 1 to the longest series' length (at least 1 to 2).
    fn x_range(&self) -> Range<f64> {
        let n = self
            .series
            .iter()
            .map(|s| s.values.len())
            .max()
            .unwrap_or(0);
        1.0..(n.max(2) as f64)
    }

    /// Finite values' range with 5 % headroom; a flat or empty range is widened.
    fn y_range(&self) -> Range<f64> {
        let finite = self
            .series
            .iter()
            .flat_map(|s| s.values.iter())
            .filter(|v| v.is_finite())
            .map(|&v| v as f64);
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if lo > hi {
            return 0.0..1.0;
        }
        if hi - lo <= f64::EPSILON * hi.abs().max(1.0) {
            let pad = (hi.abs() * 0.1).max(1.0);
            return (lo - pad)..(hi + pad);
        }
        let pad = (hi - lo) * 0.05;
        (lo - pad)..(hi + pad)
    }
}

impl Figure for Plot<'_> {
    fn size(&self) -> (u32, u32) {
        (1000, 620)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()> {
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, font(24.0))
            .margin(18)
            .x_label_area_size(56)
            .y_label_area_size(86)
            .build_cartesian_2d(self.x_range(), self.y_range())
            .map_err(drawing_error)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .label_style(font(15.0))
            .axis_desc_style(font(17.0))
            .x_label_formatter(&fmt_tick)
            .y_label_formatter(&fmt_tick)
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()
            .map_err(drawing_error)?;
        for (i, s) in self.series.iter().enumerate() {
            let style = self.style(i);
            let width = style.width.round().max(1.0) as u32;
            let shape = rgb(style.color).stroke_width(width);
            // Runs of finite values; gaps where values are not finite.
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for (k, &v) in s.values.iter().enumerate() {
                if v.is_finite() {
                    if let Some(run) = runs.last_mut() {
                        run.push(((k + 1) as f64, v as f64));
                    }
                } else if runs.last().is_some_and(|r| !r.is_empty()) {
                    runs.push(Vec::new());
                }
            }
            let dash = 4 * width as i32 + 4;
            for (r, run) in runs.into_iter().enumerate() {
                let annotation = if style.dashed {
                    chart.draw_series(DashedLineSeries::new(run, dash, dash * 2 / 3, shape))
                } else {
                    chart.draw_series(LineSeries::new(run, shape))
                }
                .map_err(drawing_error)?;
                if r == 0 {
                    annotation.label(s.label).legend(
                        move |(x, y)| -> DynElement<'static, DB, (i32, i32)> {
                            if style.dashed {
                                DashedPathElement::new(vec![(x, y), (x + 24, y)], 6, 4, shape)
                                    .into_dyn()
                            } else {
                                PathElement::new(vec![(x, y), (x + 24, y)], shape).into_dyn()
                            }
                        },
                    );
                }
            }
        }
        if !self.series.is_empty() {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
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

/// A tick label: integers without decimals, others with trailing zeros trimmed.
fn fmt_tick(v: &f64) -> String {
    let v = *v;
    if !v.is_finite() {
        return v.to_string();
    }
    if v.abs() >= 1e6 || (v != 0.0 && v.abs() < 1e-3) {
        return format!("{v:.2e}");
    }
    if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) {
        return format!("{}", v.round() as i64);
    }
    let s = format!("{v:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::super::testutil::{png_size, temp_dir};
    use super::*;

    #[test]
    fn convergence_plot_writes_png_and_svg_with_labels() {
        let a: Vec<f32> = (0..100).map(|i| 100.0 / (1.0 + i as f32)).collect();
        let mut b: Vec<f32> = (0..80).map(|i| 90.0 - i as f32 * 0.5).collect();
        b[10] = f32::NAN;
        let series = [
            Series::new("PSO", &a),
            Series::new("GA & friends", &b).with_style(Style::dashed([0, 0, 0], 2.0)),
        ];
        let dir = temp_dir("plot");
        let (png, svg) = (dir.join("c.png"), dir.join("c.svg"));
        convergence_plot(
            "Convergence",
            "iteration",
            "best cost",
            &series,
            Some(&png),
            Some(&svg),
        )
        .unwrap();
        assert_eq!(png_size(&png), (1000, 620));
        let text = std::fs::read_to_string(&svg).unwrap();
        for label in [
            "PSO",
            "GA &amp; friends",
            "Convergence",
            "iteration",
            "best cost",
        ] {
            assert!(text.contains(label), "SVG lacks {label:?}");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(fmt_tick(&20.0), "20");
        assert_eq!(fmt_tick(&-3.0), "-3");
        assert_eq!(fmt_tick(&0.25), "0.25");
        assert_eq!(fmt_tick(&162.5), "162.5");
        assert_eq!(fmt_tick(&(0.1 + 0.2)), "0.3");
        assert_eq!(fmt_tick(&2.5e7), "2.50e7");
    }

    #[test]
    fn degenerate_series_draw_empty_axes() {
        let dir = temp_dir("plot-empty");
        let flat = [3.0f32; 4];
        let nan = [f32::NAN; 3];
        for (name, series) in [
            ("none", vec![]),
            ("flat", vec![Series::new("flat", &flat)]),
            ("nan", vec![Series::new("nan", &nan)]),
            ("empty", vec![Series::new("empty", &[])]),
        ] {
            let png = dir.join(format!("{name}.png"));
            convergence_plot(name, "it", "v", &series, Some(&png), None).unwrap();
            assert_eq!(png_size(&png), (1000, 620));
        }
        std::fs::remove_dir_all(dir).unwrap();
    }
}
