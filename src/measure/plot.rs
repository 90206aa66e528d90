//! PNG plots for `results/`: speedup curves, the scaling model's efficiency curves,
//! per-thread timelines (Gantt charts) and log–log error curves.
//!
//! Drawn with plotters into an in-memory RGB buffer and encoded with the `image` crate, with
//! a font compiled into the binary (Ubuntu Light, from `epaint_default_fonts`), so plots need
//! no system font library on a fresh machine.
//!
//! Every plot is made of the same pieces: `draw` (the white canvas, the footer, the PNG),
//! `chart` and `mesh` (the title, margins and axes), `line` (a series and its legend entry),
//! `colour` (the series' palette) and `legend` (the framed box).

use std::path::Path;
use std::sync::Once;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::error::Error;
use crate::files::output::PendingOutput;

const SIZE: (u32, u32) = (960, 600);

/// One line of a speedup plot: a label and `(threads, speedup)` points.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points, in increasing thread count.
    pub points: Vec<(usize, f64)>,
}

/// Speedup against threads, one line per series, with the ideal `speedup = threads` line.
/// `footer` (the command and machine) is printed under the chart.
pub fn speedup_plot(path: &Path, title: &str, footer: &str, series: &[Series]) -> Result<(), Error> {
    let max_threads = series.iter().flat_map(|s| s.points.iter().map(|p| p.0)).max().unwrap_or(1).max(2);
    let max_speedup =
        series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).fold(max_threads as f64, f64::max);
    draw(path, footer, |root| {
        let x = 0.5f64..max_threads as f64 + 0.5;
        let mut chart = chart(root, (title, 24), 56, x, 0f64..max_speedup * 1.05)?;
        mesh(&mut chart, "threads", "speedup over serial").draw()?;
        let ideal = [(1.0, 1.0), (max_threads as f64, max_threads as f64)];
        line(&mut chart, ideal, BLACK.stroke_width(1), "ideal")?;
        for (k, s) in series.iter().enumerate() {
            let colour = colour(k);
            let points: Vec<(f64, f64)> = s.points.iter().map(|&(t, v)| (t as f64, v)).collect();
            line(&mut chart, points.clone(), colour.stroke_width(2), &s.label)?;
            chart.draw_series(points.into_iter().map(|p| Circle::new(p, 4, colour.filled())))?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft, 16)
    })
}

/// One scheduler in an efficiency plot: predicted and measured `(threads, speedup)` points.
pub struct ModelLine {
    /// Legend text.
    pub label: String,
    /// The model's points, drawn as a line.
    pub predicted: Vec<(usize, f64)>,
    /// Measured points, drawn as triangles in the line's colour.
    pub measured: Vec<(usize, f64)>,
}

/// Parallel efficiency (speedup ÷ threads) against threads on a log axis: a line per
/// scheduler's prediction, its measured points as triangles of the same colour.
pub fn efficiency_plot(path: &Path, title: &str, footer: &str, lines: &[ModelLine]) -> Result<(), Error> {
    let points = |p: &[(usize, f64)]| -> Vec<(f64, f64)> {
        p.iter().map(|&(t, s)| (t as f64, s / t as f64)).collect()
    };
    let all: Vec<(f64, f64)> =
        lines.iter().flat_map(|l| points(&l.predicted).into_iter().chain(points(&l.measured))).collect();
    let max_threads = all.iter().map(|p| p.0).fold(2.0, f64::max);
    let top = all.iter().map(|p| p.1).fold(1.0, f64::max) * 1.1;
    draw(path, footer, |root| {
        let mut chart = chart(root, (title, 22), 60, (0.9f64..max_threads * 1.1).log_scale(), 0f64..top)?;
        mesh(&mut chart, "threads", "efficiency = speedup ÷ threads").draw()?;
        for (k, model) in lines.iter().enumerate() {
            let colour = colour(k);
            line(&mut chart, points(&model.predicted), colour.stroke_width(2), &model.label)?;
            chart.draw_series(
                points(&model.predicted).into_iter().map(|p| Circle::new(p, 3, colour.filled())),
            )?;
            chart.draw_series(
                points(&model.measured).into_iter().map(|p| TriangleMarker::new(p, 7, colour.filled())),
            )?;
        }
        legend(&mut chart, SeriesLabelPosition::LowerLeft, 16)
    })
}

/// A Gantt chart: lane `k` holds thread `k`'s tile jobs as `(start, end)` seconds.
pub fn timeline_plot(path: &Path, title: &str, footer: &str, lanes: &[Vec<(f64, f64)>]) -> Result<(), Error> {
    let end = lanes.iter().flatten().map(|s| s.1).fold(0.0, f64::max).max(1e-6);
    draw(path, footer, |root| {
        let mut chart = chart(root, (title, 22), 70, 0f64..end * 1.02, -0.5f64..lanes.len() as f64 - 0.5)?;
        mesh(&mut chart, "seconds since the render started", "thread")
            .y_labels(lanes.len().min(32))
            .y_label_formatter(&|y| format!("{}", y.round() as i64))
            .disable_y_mesh()
            .draw()?;
        for (lane, spans) in lanes.iter().enumerate() {
            let colour = colour(lane);
            let y = lane as f64;
            chart.draw_series(spans.iter().enumerate().map(|(k, &(s, e))| {
                // Alternate shades so neighbouring tiles stay distinguishable.
                let fill = if k % 2 == 0 { colour.filled() } else { colour.mix(0.6).filled() };
                Rectangle::new([(s, y - 0.4), (e, y + 0.4)], fill)
            }))?;
        }
        Ok(())
    })
}

/// One line of a log–log plot.
pub struct LogSeries {
    /// Legend text.
    pub label: String,
    /// Points `(x, y)`, both positive.
    pub points: Vec<(f64, f64)>,
    /// Drawn with triangles instead of circles (e.g. adaptive sampling against uniform).
    pub triangles: bool,
}

/// Log–log lines, e.g. error against run time, with a dotted reference line of slope
/// `reference_slope` through the first point of the first series.
pub fn log_log_plot(
    path: &Path,
    title: &str,
    (x_desc, y_desc): (&str, &str),
    footer: &str,
    series: &[LogSeries],
    reference_slope: f64,
) -> Result<(), Error> {
    let all = || series.iter().flat_map(|s| s.points.iter().copied()).filter(|p| p.0 > 0.0 && p.1 > 0.0);
    let (x_lo, x_hi) = all().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| (lo.min(p.0), hi.max(p.0)));
    let (y_lo, y_hi) = all().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
    if !(x_lo < x_hi && y_lo < y_hi) {
        return Err(Error::new(format!("plot {}: nothing to draw", path.display())));
    }
    draw(path, footer, |root| {
        let (x, y) = ((x_lo / 1.2..x_hi * 1.2).log_scale(), (y_lo / 1.2..y_hi * 1.2).log_scale());
        let mut chart = chart(root, (title, 22), 70, x, y)?;
        mesh(&mut chart, x_desc, y_desc).draw()?;
        if let Some(&(x0, y0)) = series.first().and_then(|s| s.points.first()) {
            let reference = [(x0, y0), (x_hi, y0 * (x_hi / x0).powf(reference_slope))];
            line(&mut chart, reference, BLACK.stroke_width(1), &format!("slope {reference_slope}"))?;
        }
        for (k, s) in series.iter().enumerate() {
            let colour = colour(k);
            line(&mut chart, s.points.clone(), colour.stroke_width(2), &s.label)?;
            if s.triangles {
                chart.draw_series(s.points.iter().map(|&p| TriangleMarker::new(p, 5, colour.filled())))?;
            } else {
                chart.draw_series(s.points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
            }
        }
        legend(&mut chart, SeriesLabelPosition::LowerLeft, 13)
    })
}

type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// The area a plot draws its chart on (all but the footer).
type Area<'b> = DrawingArea<BitMapBackend<'b>, Shift>;

/// A chart on an [`Area`] with axes of coordinates `X` and `Y`.
type Chart<'a, 'b, X, Y> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>;

/// An axis of numbers, linear or logarithmic, that plotters can number.
trait Axis: Ranged<ValueType = f64> + ValueFormatter<f64> {}
impl<A: Ranged<ValueType = f64> + ValueFormatter<f64>> Axis for A {}

/// Every plot's chart: `title` above (in a font of the given size), a margin, room for the
/// numbers of the horizontal axis and `y_label_width` pixels for those of the vertical one,
/// over the ranges `x` and `y`.
fn chart<'a, 'b, X: AsRangedCoord, Y: AsRangedCoord>(
    area: &'a Area<'b>,
    (title, title_size): (&str, u32),
    y_label_width: u32,
    x: X,
    y: Y,
) -> Result<Chart<'a, 'b, X::CoordDescType, Y::CoordDescType>, Box<dyn std::error::Error>> {
    let chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", title_size))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(y_label_width)
        .build_cartesian_2d(x, y)?;
    Ok(chart)
}

/// `chart`'s grid and axes, described by `x_desc` and `y_desc`, numbered in every plot's
/// font; more settings may follow before it is drawn.
fn mesh<'a, 'b, 'c, X: Axis, Y: Axis>(
    chart: &'c mut Chart<'a, 'b, X, Y>,
    x_desc: &str,
    y_desc: &str,
) -> MeshStyle<'a, 'c, X, Y, BitMapBackend<'b>> {
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc).y_desc(y_desc).label_style(("sans-serif", 16));
    mesh
}

/// Draws `points` as a line in `style`, named `label` in the legend by a short stroke of it.
fn line<X: Axis, Y: Axis>(
    chart: &mut Chart<'_, '_, X, Y>,
    points: impl IntoIterator<Item = (f64, f64)>,
    style: ShapeStyle,
    label: &str,
) -> DrawResult {
    chart
        .draw_series(LineSeries::new(points, style))?
        .label(label)
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style));
    Ok(())
}

/// The colour of the `k`-th series of a plot.
fn colour(k: usize) -> RGBAColor {
    Palette99::pick(k).to_rgba()
}

/// The series' legend in a framed, nearly opaque box.
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(position)
        .label_font(("sans-serif", font_size))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// Draws on a white canvas, with `footer` in small print at the bottom, and writes it as a
/// PNG (atomically).
fn draw(path: &Path, footer: &str, paint: impl FnOnce(&Area) -> DrawResult) -> Result<(), Error> {
    static FONT: Once = Once::new();
    FONT.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
            .unwrap_or_else(|_| panic!("the bundled font parses"))
    });
    let mut rgb = vec![255u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        let fail = |e: String| Error::new(format!("plot {}: {e}", path.display()));
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        let (chart, bottom) = root.split_vertically(SIZE.1 - 24);
        paint(&chart).map_err(|e| fail(e.to_string()))?;
        bottom
            .draw_text(footer, &("sans-serif", 14).into_text_style(&bottom), (16, 4))
            .map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    let output = PendingOutput::create(path)?;
    output.write_rgb8(SIZE.0, SIZE.1, &rgb)
}
