//! The convergence plot: relMSE against render time on log-log axes, one curve per algorithm
//! (the geometric mean over seeds with a min/max band when there are several), and guide
//! lines of slope -1 (the rate of an unbiased Monte Carlo estimator) and -2/3 (progressive
//! photon mapping's asymptotic rate with alpha = 2/3).

use crate::output::write_png_rgb8;
use anyhow::{anyhow, Result};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::Path;
use std::sync::OnceLock;

/// DejaVu Sans (see assets/DejaVuSans-LICENSE.txt): plotters' pure-Rust text rendering needs a
/// font in memory, and system fonts are not dependable.
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Plot size in pixels.
pub const PLOT_SIZE: (u32, u32) = (1024, 720);

/// The error curves of one algorithm: per seed, (seconds, relMSE) in increasing time.
pub struct Curve {
    pub label: String,
    pub runs: Vec<Vec<(f64, f64)>>,
}

/// Points where the band is evaluated.
const BAND_POINTS: usize = 64;

/// One point of a band: time, minimum, maximum and geometric mean of the seeds' errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandPoint {
    pub t: f64,
    pub min: f64,
    pub max: f64,
    pub mean: f64,
}

/// Keeps the points a log-log plot can show (both coordinates finite and > 0).
fn loggable(run: &[(f64, f64)]) -> Vec<(f64, f64)> {
    run.iter()
        .copied()
        .filter(|&(t, e)| t.is_finite() && e.is_finite() && t > 0.0 && e > 0.0)
        .collect()
}

/// log(error) at time `t`, interpolated linearly in log-log between the run's samples
/// (`None` outside the run's time span).
fn log_error_at(run: &[(f64, f64)], t: f64) -> Option<f64> {
    let i = run.partition_point(|&(ti, _)| ti < t);
    if i == run.len() {
        return None;
    }
    if run[i].0 == t || i == 0 {
        return (run[i].0 == t).then(|| run[i].1.ln());
    }
    let (t0, e0) = run[i - 1];
    let (t1, e1) = run[i];
    let s = (t.ln() - t0.ln()) / (t1.ln() - t0.ln());
    Some(e0.ln() + s * (e1.ln() - e0.ln()))
}

/// The min/max/geometric-mean band of several runs, at `points` log-spaced times over the span
/// all runs cover. Empty if they share no time span.
pub fn band(runs: &[Vec<(f64, f64)>], points: usize) -> Vec<BandPoint> {
    let runs: Vec<Vec<(f64, f64)>> = runs.iter().map(|r| loggable(r)).collect();
    if runs.iter().any(|r| r.is_empty()) || points < 2 {
        return Vec::new();
    }
    let lo = runs.iter().map(|r| r[0].0).fold(f64::MIN, f64::max);
    let hi = runs
        .iter()
        .map(|r| r[r.len() - 1].0)
        .fold(f64::MAX, f64::min);
    if lo >= hi {
        return Vec::new();
    }
    (0..points)
        .filter_map(|k| {
            // Exact end points, so rounding cannot push them outside a run's span.
            let t = match k {
                0 => lo,
                k if k == points - 1 => hi,
                _ => (lo.ln() + (hi.ln() - lo.ln()) * k as f64 / (points - 1) as f64).exp(),
            };
            let logs: Vec<f64> = runs
                .iter()
                .map(|r| log_error_at(r, t))
                .collect::<Option<_>>()?;
            let min = logs.iter().copied().fold(f64::MAX, f64::min).exp();
            let max = logs.iter().copied().fold(f64::MIN, f64::max).exp();
            let mean = (logs.iter().sum::<f64>() / logs.len() as f64).exp();
            Some(BandPoint { t, min, max, mean })
        })
        .collect()
}

fn register_font_once() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    ok.then_some(())
        .ok_or_else(|| anyhow!("the plot font could not be loaded"))
}

/// A tick label on a log axis with at most 3 significant digits: 0.02, 0.3, 1, 40, 1e-5.
fn tick_label(v: f64) -> String {
    if !(1e-3..1e5).contains(&v) {
        return format!("{v:.0e}");
    }
    let decimals = (2 - v.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Curve colors, by curve index.
const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// The plot's margin on every side, in pixels.
const MARGIN: u32 = 16;

/// The title's font size: 26 px, or the largest smaller size at which it fits `width` (a long
/// scene or reference name would otherwise run off both sides of the centred caption).
fn caption_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    width: u32,
) -> u32 {
    const SIZES: [u32; 8] = [26, 24, 22, 20, 18, 16, 14, 12];
    SIZES
        .into_iter()
        .find(|&size| {
            area.estimate_text_size(title, &TextStyle::from((FAMILY, size).into_font()))
                .is_ok_and(|(text_width, _)| text_width <= width)
        })
        .unwrap_or(SIZES[SIZES.len() - 1])
}

/// Draws the plot into an RGB8 buffer of [`PLOT_SIZE`].
pub fn draw_plot(title: &str, curves: &[Curve]) -> Result<Vec<u8>> {
    register_font_once()?;
    let (w, h) = PLOT_SIZE;
    let mut buffer = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let points: Vec<(f64, f64)> = curves
            .iter()
            .flat_map(|c| c.runs.iter().flat_map(|r| loggable(r)))
            .collect();
        let (x_lo, x_hi, y_lo, y_hi) = if points.is_empty() {
            (0.1, 10.0, 1e-3, 1.0)
        } else {
            let fold = |f: fn(&(f64, f64)) -> f64, min: bool| {
                points.iter().map(f).fold(
                    if min { f64::MAX } else { f64::MIN },
                    if min { f64::min } else { f64::max },
                )
            };
            // Margins: a factor 1.3 in time and 2 in error on each side.
            (
                fold(|p| p.0, true) / 1.3,
                fold(|p| p.0, false) * 1.3,
                fold(|p| p.1, true) / 2.0,
                fold(|p| p.1, false) * 2.0,
            )
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FAMILY, caption_size(&root, title, w - 2 * MARGIN)))
            .margin(MARGIN)
            .x_label_area_size(56)
            .y_label_area_size(86)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (y_lo..y_hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("render time [s]")
            .y_desc("relMSE")
            .axis_desc_style((FAMILY, 20))
            .label_style((FAMILY, 16))
            .x_labels(12)
            .y_labels(12)
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.12))
            .draw()?;

        // Guides through the first curve's start (or the plot's upper left), clipped to the plot.
        let anchor = curves
            .first()
            .and_then(|c| c.runs.first())
            .map(|r| loggable(r))
            .and_then(|r| r.first().copied());
        let (t0, e0) = anchor.unwrap_or((x_lo, y_hi / 2.0));
        // (slope, label, dash length and gap in pixels, the legend's three dashes)
        let guides = [
            (-1.0, "slope -1", (10, 6), [(0, 9), (13, 22), (22, 22)]),
            (
                -2.0 / 3.0,
                "slope -2/3",
                (3, 5),
                [(0, 3), (8, 11), (16, 19)],
            ),
        ];
        for (slope, label, (on, off), sample) in guides {
            let line: Vec<(f64, f64)> = (0..=64)
                .map(|k| (x_lo.ln() + (x_hi.ln() - x_lo.ln()) * k as f64 / 64.0).exp())
                .map(|t| (t, e0 * (t / t0).powf(slope)))
                .filter(|&(_, e)| e >= y_lo && e <= y_hi)
                .collect();
            let style = BLACK.mix(0.6).stroke_width(1);
            chart
                .draw_series(DashedLineSeries::new(line, on, off, style))?
                .label(label)
                .legend(move |(x, y)| {
                    let dash = |(a, b): (i32, i32)| PathElement::new(vec![(a, 0), (b, 0)], style);
                    EmptyElement::at((x, y)) + dash(sample[0]) + dash(sample[1]) + dash(sample[2])
                });
        }

        for (i, curve) in curves.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let center: Vec<(f64, f64)> = if curve.runs.len() > 1 {
                let band = band(&curve.runs, BAND_POINTS);
                let mut outline: Vec<(f64, f64)> = band.iter().map(|b| (b.t, b.min)).collect();
                outline.extend(band.iter().rev().map(|b| (b.t, b.max)));
                if !outline.is_empty() {
                    chart.draw_series(std::iter::once(Polygon::new(
                        outline,
                        color.mix(0.22).filled(),
                    )))?;
                }
                band.iter().map(|b| (b.t, b.mean)).collect()
            } else {
                curve.runs.first().map(|r| loggable(r)).unwrap_or_default()
            };
            let label = if curve.runs.len() > 1 {
                format!(
                    "{} (geometric mean, min/max of {} seeds)",
                    curve.label,
                    curve.runs.len()
                )
            } else {
                curve.label.clone()
            };
            chart
                .draw_series(LineSeries::new(center, color.stroke_width(2)))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 22, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .label_font((FAMILY, 16))
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()?;
        root.present()?;
    }
    Ok(buffer)
}

/// Draws the plot and writes it as a PNG, atomically.
pub fn write_plot(path: &Path, title: &str, curves: &[Curve]) -> Result<()> {
    let buffer = draw_plot(title, curves)?;
    write_png_rgb8(path, PLOT_SIZE.0, PLOT_SIZE.1, &buffer)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_interpolates_in_log_log() {
        // Two runs on exact power laws e = c t^-1 with c = 1 and c = 4: in log-log the
        // interpolation is exact, min/max are the two laws, the mean is 2 t^-1.
        let run = |c: f64, ts: &[f64]| ts.iter().map(|&t| (t, c / t)).collect::<Vec<_>>();
        let runs = vec![
            run(1.0, &[0.5, 1.0, 2.0, 4.0, 8.0]),
            run(4.0, &[1.0, 3.0, 9.0]),
        ];
        let band = band(&runs, 5);
        assert_eq!(band.len(), 5);
        assert_eq!(
            (band[0].t, band[4].t),
            (1.0, 8.0),
            "the span both runs cover"
        );
        for b in &band {
            assert!((b.min - 1.0 / b.t).abs() < 1e-12 * b.min.max(1.0), "{b:?}");
            assert!((b.max - 4.0 / b.t).abs() < 1e-12 * b.max.max(1.0), "{b:?}");
            assert!(
                (b.mean - 2.0 / b.t).abs() < 1e-12 * b.mean.max(1.0),
                "{b:?}"
            );
        }
        assert!(super::band(&[run(1.0, &[1.0, 2.0]), run(1.0, &[3.0, 4.0])], 5).is_empty());
        assert!(
            super::band(&[vec![(0.0, 1.0)], vec![(1.0, -1.0)]], 5).is_empty(),
            "nothing loggable"
        );
    }

    #[test]
    fn tick_labels_are_short() {
        let labels: Vec<String> = [0.1 + 0.2, 0.02, 7.0, 40.0, 1.5, 1e-5, 2e6, 0.001]
            .map(tick_label)
            .to_vec();
        assert_eq!(
            labels,
            ["0.3", "0.02", "7", "40", "1.5", "1e-5", "2e6", "0.001"]
        );
    }

    #[test]
    fn plot_is_drawn_with_text() {
        let curve = |label: &str, c: f64| Curve {
            label: label.into(),
            runs: (0..3)
                .map(|s| {
                    (1..40)
                        .map(|i| (i as f64 * 0.1, c * (1.0 + 0.1 * s as f64) / i as f64))
                        .collect()
                })
                .collect(),
        };
        let buffer = draw_plot("test scene", &[curve("pt", 1.0), curve("ppm", 0.3)]).unwrap();
        assert_eq!(buffer.len(), (PLOT_SIZE.0 * PLOT_SIZE.1 * 3) as usize);
        // The title is drawn: the caption strip (top 40 rows) has dark pixels.
        let row = (PLOT_SIZE.0 * 3) as usize;
        let dark_in_title = buffer[..40 * row]
            .chunks(3)
            .filter(|p| p.iter().all(|&c| c < 100))
            .count();
        assert!(
            dark_in_title > 50,
            "{dark_in_title} dark pixels in the title strip"
        );
        // A long title is scaled to fit: no dark pixel in the caption strip's outer columns.
        let title = "cornell_box_water: relMSE against render time (256x206, 2 threads, \
                     reference cornell_box_water_reference.exr)";
        let long = draw_plot(title, &[curve("pt", 1.0)]).unwrap();
        let edge = (0..40usize)
            .flat_map(|y| {
                (0..8usize)
                    .chain(PLOT_SIZE.0 as usize - 8..PLOT_SIZE.0 as usize)
                    .map(move |x| (x, y))
            })
            .filter(|&(x, y)| long[y * row + 3 * x..][..3].iter().all(|&c| c < 100))
            .count();
        assert_eq!(edge, 0, "the title runs into the image's edge");
        // Both curve colors appear.
        for color in [COLORS[0], COLORS[1]] {
            let n = buffer
                .chunks(3)
                .filter(|p| p == &[color.0, color.1, color.2])
                .count();
            assert!(n > 100, "{color:?}: {n} pixels");
        }
    }

    #[test]
    fn plot_survives_empty_and_degenerate_curves() {
        let curves = [
            Curve {
                label: "empty".into(),
                runs: vec![],
            },
            Curve {
                label: "zero".into(),
                runs: vec![vec![(0.0, 0.0)], vec![(1.0, 0.0)]],
            },
        ];
        draw_plot("nothing", &curves).unwrap();
    }
}
