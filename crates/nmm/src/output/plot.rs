//! Line plots of histories: panels stacked vertically over one shared x range, written as
//! PNG and SVG; and maps ([`plot_map`]): filled polygons and polylines in true proportions
//! (e.g. the blocks of a model as cut by its joints).
//!
//! Owns the figure layout only; the caller chooses what to plot (e.g. slip history above the
//! input acceleration, both over time).
//!
//! # Layout and ranges
//! * The figure (`width × height` pixels) is split into `panels.len()` rows of equal height.
//!   Every panel has a title, axis labels, a legend (when any series or line has a label) and
//!   horizontal reference lines (`hlines`, dashed grey, e.g. a friction limit).
//! * x range, shared by all panels: `[min x, max x]` over the finite points of every series,
//!   widened by 2 % of its span on each side. y range, per panel: `[min y, max y]` over the
//!   finite points and the `hlines`, widened by 6 % of its span. A degenerate range
//!   (constant data) becomes `v ± 0.1·|v|` (`[-1, 1]` around 0) and an empty one `[0, 1]`
//!   (see [`padded_range`]). Nothing here panics on empty, constant or non-finite data.
//! * Non-finite points (NaN, ±∞) are skipped; a line is broken where they occur.
//!
//! # Fonts
//! plotters is built without system font support; DejaVu Sans (`assets/DejaVuSans.ttf`,
//! licence in `assets/DejaVuSans-LICENSE.txt`) is embedded in the binary and registered as
//! plotters' `sans-serif` family on first use.

use plotters::chart::SeriesAnno;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Smallest and largest accepted figure sizes, pixels.
const MIN_SIZE: u32 = 100;
const MAX_SIZE: u32 = 16_384;

/// Tableau 10 palette, picked by [`LineStyle::colour`] modulo 10.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Errors of [`plot_panels`].
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("no panel to plot")]
    NoPanels,
    #[error("figure size {width}x{height} for {panels} panel(s) is out of range (each panel at least {MIN_SIZE}x{MIN_SIZE}, at most {MAX_SIZE} pixels a side)")]
    InvalidSize {
        width: u32,
        height: u32,
        panels: usize,
    },
    #[error("the embedded font could not be loaded")]
    Font,
    #[error("drawing {path}: {message}")]
    Draw { path: PathBuf, message: String },
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stroke {
    Solid,
    Dashed,
    /// Markers only, no line.
    Points,
}

/// Stroke and colour (an index into a 10-colour palette, taken modulo 10).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineStyle {
    pub stroke: Stroke,
    pub colour: usize,
}

impl LineStyle {
    pub fn solid(colour: usize) -> Self {
        Self {
            stroke: Stroke::Solid,
            colour,
        }
    }
    pub fn dashed(colour: usize) -> Self {
        Self {
            stroke: Stroke::Dashed,
            colour,
        }
    }
    pub fn points(colour: usize) -> Self {
        Self {
            stroke: Stroke::Points,
            colour,
        }
    }
}

/// One curve of a panel. An empty label keeps it out of the legend.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: LineStyle,
}

/// One plot of the figure.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Horizontal reference lines `(y, label)`, drawn dashed across the whole x range.
    pub hlines: Vec<(f64, String)>,
}

/// Draws `panels` stacked vertically, sharing one x range, into `<stem>.png` and
/// `<stem>.svg` (`width × height` pixels for the whole figure). Returns the two paths.
pub fn plot_panels(
    path_stem: &Path,
    panels: &[Panel],
    width: u32,
    height: u32,
) -> Result<Vec<PathBuf>, PlotError> {
    if panels.is_empty() {
        return Err(PlotError::NoPanels);
    }
    let n = panels.len();
    let fits = |v: u32, per: usize| v >= MIN_SIZE * per as u32 && v <= MAX_SIZE;
    if n > (MAX_SIZE / MIN_SIZE) as usize || !fits(width, 1) || !fits(height, n) {
        return Err(PlotError::InvalidSize {
            width,
            height,
            panels: n,
        });
    }
    ensure_font()?;

    let xs = panels
        .iter()
        .flat_map(|p| p.series.iter())
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .map(|p| p.0);
    let x_range = padded_range(xs, 0.02);

    let png = with_extension(path_stem, "png");
    let svg = with_extension(path_stem, "svg");
    {
        let root = BitMapBackend::new(&png, (width, height)).into_drawing_area();
        draw_figure(&root, panels, &x_range).map_err(|message| PlotError::Draw {
            path: png.clone(),
            message,
        })?;
    }
    {
        let root = SVGBackend::new(&svg, (width, height)).into_drawing_area();
        draw_figure(&root, panels, &x_range).map_err(|message| PlotError::Draw {
            path: svg.clone(),
            message,
        })?;
    }
    Ok(vec![png, svg])
}

/// A filled polygon of a [`plot_map`], coloured from the palette (index modulo 10).
#[derive(Clone, Debug, PartialEq)]
pub struct MapPolygon {
    pub points: Vec<(f64, f64)>,
    pub colour: usize,
}

/// A polyline of a [`plot_map`]: palette colour (index modulo 10) and width in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct MapLine {
    pub points: Vec<(f64, f64)>,
    pub colour: usize,
    pub width: u32,
}

/// A map in true proportions (1 m in x = 1 m in y): filled polygons with black outlines,
/// then polylines over them, into `<stem>.png` and
/// `<stem>.svg`; the height follows from `width` and the data's aspect ratio (within
/// the size limits). Returns the two paths.
pub fn plot_map(
    path_stem: &Path,
    title: &str,
    polygons: &[MapPolygon],
    lines: &[MapLine],
    width: u32,
) -> Result<Vec<PathBuf>, PlotError> {
    let pts = || {
        polygons
            .iter()
            .flat_map(|p| p.points.iter())
            .chain(lines.iter().flat_map(|l| l.points.iter()))
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    let xr = padded_range(pts().map(|p| p.0), 0.03);
    let yr = padded_range(pts().map(|p| p.1), 0.03);
    let (label_x, label_y, top) = (40u32, 60u32, 40u32);
    if !(MIN_SIZE..=MAX_SIZE).contains(&width) {
        return Err(PlotError::InvalidSize {
            width,
            height: 0,
            panels: 1,
        });
    }
    let plot_w = (width - label_y - 20) as f64;
    let ratio = (yr.end - yr.start) / (xr.end - xr.start);
    let height = ((plot_w * ratio) as u32 + label_x + top).clamp(MIN_SIZE, MAX_SIZE);
    ensure_font()?;
    let png = with_extension(path_stem, "png");
    let svg = with_extension(path_stem, "svg");
    let draw = |root: &DrawingArea<_, Shift>| -> Result<(), String> {
        draw_map(root, title, polygons, lines, (&xr, &yr), (label_x, label_y))
            .map_err(|e| e.to_string())
    };
    {
        let root = BitMapBackend::new(&png, (width, height)).into_drawing_area();
        draw(&root).map_err(|message| PlotError::Draw {
            path: png.clone(),
            message,
        })?;
    }
    {
        let root = SVGBackend::new(&svg, (width, height)).into_drawing_area();
        draw_map(
            &root,
            title,
            polygons,
            lines,
            (&xr, &yr),
            (label_x, label_y),
        )
        .map_err(|e| PlotError::Draw {
            path: svg.clone(),
            message: e.to_string(),
        })?;
    }
    Ok(vec![png, svg])
}

/// A chart in metres on both axes.
type MapChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The axes of a map in metres (x and y on the same scale), its mesh drawn: shared by the
/// figures' maps and `nmm plot`'s scenes.
fn map_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    (title, size): (&str, u32),
    (xr, yr): (&Range<f64>, &Range<f64>),
    (label_x, label_y): (u32, u32),
) -> Result<MapChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (xs, ys) = (xr.end - xr.start, yr.end - yr.start);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", size))
        .margin(10)
        .x_label_area_size(label_x)
        .y_label_area_size(label_y)
        .build_cartesian_2d(xr.clone(), yr.clone())?;
    let x_fmt = |v: &f64| tick_label(*v, xs);
    let y_fmt = |v: &f64| tick_label(*v, ys);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .draw()?;
    Ok(chart)
}

fn draw_map<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    polygons: &[MapPolygon],
    lines: &[MapLine],
    (xr, yr): (&Range<f64>, &Range<f64>),
    (label_x, label_y): (u32, u32),
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let mut chart = map_chart(root, (title, 18), (xr, yr), (label_x, label_y))?;
    for p in polygons {
        let colour = PALETTE[p.colour % PALETTE.len()];
        chart.draw_series(std::iter::once(Polygon::new(
            p.points.clone(),
            colour.mix(0.35).filled(),
        )))?;
        let mut ring = p.points.clone();
        if let Some(&first) = ring.first() {
            ring.push(first);
        }
        chart.draw_series(std::iter::once(PathElement::new(
            ring,
            BLACK.stroke_width(1),
        )))?;
    }
    for l in lines {
        let colour = PALETTE[l.colour % PALETTE.len()];
        chart.draw_series(std::iter::once(PathElement::new(
            l.points.clone(),
            colour.stroke_width(l.width),
        )))?;
    }
    root.present()
}

/// `[min, max]` of the finite values, widened by `margin × span` on each side. Constant data
/// `v` (a span below `1e-12·|v|`) gives `v ± 0.1·|v|`, or `[-1, 1]` for `v = 0`; no finite
/// value gives `[0, 1]`.
pub fn padded_range(values: impl Iterator<Item = f64>, margin: f64) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let span = hi - lo;
    if !span.is_finite() {
        return lo..hi;
    }
    // A span that is 0, or lost in rounding next to the values, is treated as constant data.
    if span <= 1e-12 * lo.abs().max(hi.abs()) {
        let mid = 0.5 * lo + 0.5 * hi;
        let pad = if mid == 0.0 { 1.0 } else { 0.1 * mid.abs() };
        return (mid - pad)..(mid + pad);
    }
    let pad = margin * span;
    let (a, b) = (lo - pad, hi + pad);
    if a.is_finite() && b.is_finite() {
        a..b
    } else {
        lo..hi
    }
}

fn with_extension(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        register_font("sans-serif", FontStyle::Normal, FONT).is_ok()
            && register_font("sans-serif", FontStyle::Bold, FONT).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Font)
    }
}

/// Tick label: plain decimals with as many digits as the tick spacing needs, exponent
/// notation for very large or very small magnitudes.
fn tick_label(v: f64, span: f64) -> String {
    // Ticks are generated in floating point: a tick meant to be 0 may come out as 1e-17.
    if v == 0.0 || v.abs() < 1e-9 * span {
        return "0".to_string();
    }
    let mag = v.abs();
    if !(1e-3..1e6).contains(&mag) {
        return format!("{v:.2e}");
    }
    let step = span / 8.0;
    // One digit more than the spacing needs, then trailing zeros trimmed.
    let decimals = if step > 0.0 {
        (1.0 - step.log10().floor()).clamp(0.0, 8.0) as usize
    } else {
        3
    };
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[Panel],
    x_range: &Range<f64>,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((panels.len(), 1));
    for (panel, area) in panels.iter().zip(&areas) {
        draw_panel(area, panel, x_range).map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_panel<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    panel: &Panel,
    x_range: &Range<f64>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let ys = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .map(|p| p.1)
        .chain(panel.hlines.iter().map(|h| h.0));
    let y_range = padded_range(ys, 0.06);
    let x_span = x_range.end - x_range.start;
    let y_span = y_range.end - y_range.start;

    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(75)
        .build_cartesian_2d(x_range.clone(), y_range.clone())?;
    let x_fmt = |v: &f64| tick_label(*v, x_span);
    let y_fmt = |v: &f64| tick_label(*v, y_span);
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;

    let mut has_legend = false;
    for s in &panel.series {
        let colour = PALETTE[s.style.colour % PALETTE.len()];
        let runs = finite_runs(&s.points);
        let mut first = true;
        // An all-non-finite (or empty) series still gets its legend entry.
        let empty: Vec<(f64, f64)> = Vec::new();
        let runs: Vec<&[(f64, f64)]> = if runs.is_empty() {
            vec![&empty[..]]
        } else {
            runs
        };
        for run in runs {
            let line = ShapeStyle::from(&colour).stroke_width(2);
            let anno = match s.style.stroke {
                Stroke::Solid => chart.draw_series(LineSeries::new(run.iter().copied(), line))?,
                Stroke::Dashed => {
                    chart.draw_series(DashedLineSeries::new(run.iter().copied(), 8, 5, line))?
                }
                Stroke::Points => chart.draw_series(
                    run.iter()
                        .map(|&p| Circle::new(p, 3, ShapeStyle::from(&colour).filled())),
                )?,
            };
            if first && !s.label.is_empty() {
                has_legend = true;
                set_legend(anno.label(s.label.as_str()), s.style.stroke, colour);
            }
            first = false;
        }
    }
    let grey = RGBColor(90, 90, 90);
    for (y, label) in &panel.hlines {
        if !y.is_finite() {
            continue;
        }
        let style = ShapeStyle::from(&grey).stroke_width(1);
        let anno = chart.draw_series(DashedLineSeries::new(
            [(x_range.start, *y), (x_range.end, *y)],
            6,
            4,
            style,
        ))?;
        if !label.is_empty() {
            has_legend = true;
            set_legend(anno.label(label.as_str()), Stroke::Dashed, grey);
        }
    }
    if has_legend {
        chart
            .configure_series_labels()
            .position(legend_corner(panel, x_range, &y_range))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 13))
            .draw()?;
    }
    Ok(())
}

/// The corner of the plot holding the fewest data points (first of upper right, upper left,
/// lower right, lower left on ties): each corner is 45 % of the width by 40 % of the height.
fn legend_corner(panel: &Panel, x: &Range<f64>, y: &Range<f64>) -> SeriesLabelPosition {
    let (w, h) = (x.end - x.start, y.end - y.start);
    let mut count = [0usize; 4];
    for &(px, py) in panel.series.iter().flat_map(|s| s.points.iter()) {
        let (fx, fy) = ((px - x.start) / w, (py - y.start) / h);
        if !(fx.is_finite() && fy.is_finite()) {
            continue;
        }
        let right = fx >= 0.55;
        let left = fx <= 0.45;
        let top = fy >= 0.6;
        let bottom = fy <= 0.4;
        count[0] += (top && right) as usize;
        count[1] += (top && left) as usize;
        count[2] += (bottom && right) as usize;
        count[3] += (bottom && left) as usize;
    }
    let best = (0..4).min_by_key(|&k| count[k]).unwrap_or(0);
    [
        SeriesLabelPosition::UpperRight,
        SeriesLabelPosition::UpperLeft,
        SeriesLabelPosition::LowerRight,
        SeriesLabelPosition::LowerLeft,
    ][best]
        .clone()
}

/// Sets the legend mark of a series: a short line, a dashed line or a dot.
fn set_legend<'a, DB: DrawingBackend + 'a>(
    anno: &mut SeriesAnno<'a, DB>,
    stroke: Stroke,
    colour: RGBColor,
) {
    let line = ShapeStyle::from(&colour).stroke_width(2);
    match stroke {
        Stroke::Solid => {
            anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], line));
        }
        Stroke::Dashed => {
            anno.legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (7, 0)], line)
                    + PathElement::new(vec![(12, 0), (20, 0)], line)
            });
        }
        Stroke::Points => {
            let dot = ShapeStyle::from(&colour).filled();
            anno.legend(move |(x, y)| Circle::new((x + 10, y), 3, dot));
        }
    }
}

/// Maximal runs of consecutive finite points.
fn finite_runs(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    points
        .split(|p| !(p.0.is_finite() && p.1.is_finite()))
        .filter(|r| !r.is_empty())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_handle_empty_constant_and_non_finite() {
        assert_eq!(padded_range(std::iter::empty(), 0.05), 0.0..1.0);
        assert_eq!(
            padded_range([f64::NAN, f64::INFINITY].into_iter(), 0.05),
            0.0..1.0
        );
        assert_eq!(padded_range([0.0, 0.0].into_iter(), 0.05), -1.0..1.0);
        let r = padded_range([2.0, 2.0].into_iter(), 0.05);
        assert!((r.start - 1.8).abs() < 1e-12 && (r.end - 2.2).abs() < 1e-12);
        let r = padded_range([0.0, f64::NAN, 10.0].into_iter(), 0.05);
        assert!((r.start + 0.5).abs() < 1e-12 && (r.end - 10.5).abs() < 1e-12);
        let r = padded_range([f64::MAX, -f64::MAX].into_iter(), 0.05);
        assert!(r.start.is_finite() && r.end.is_finite() && r.start < r.end);
    }

    #[test]
    fn runs_break_at_non_finite_points() {
        let p = [(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (3.0, 4.0)];
        let runs = finite_runs(&p);
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[1], &p[2..]);
    }

    #[test]
    fn tick_labels_follow_spacing() {
        assert_eq!(tick_label(0.25, 1.0), "0.25");
        assert_eq!(tick_label(3.0, 100.0), "3");
        assert_eq!(tick_label(1.5e-6, 1e-5), "1.50e-6");
        assert_eq!(tick_label(-2.2e-16, 2.0), "0");
    }
}

/// An RGB colour of a [`Scene`].
pub type Rgb = (u8, u8, u8);
/// A point of a [`Scene`] (data coordinates).
pub type Pt = (f64, f64);
/// A polyline of a [`Scene`]: points, colour, width in pixels.
pub type SceneLine = (Vec<Pt>, Rgb, u32);
/// An arrow of a [`Scene`]: from, to (the head), colour.
pub type Arrow = (Pt, Pt, Rgb);

/// A polygon of a [`Scene`]: filled (colour, opacity in [0, 1]) and/or outlined (colour,
/// width in pixels).
#[derive(Clone, Debug, PartialEq)]
pub struct ScenePolygon {
    pub points: Vec<(f64, f64)>,
    pub fill: Option<(Rgb, f64)>,
    pub outline: Option<(Rgb, u32)>,
}

/// The shape of a [`SceneMarker`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerShape {
    Circle,
    Square,
    Triangle,
}

/// A marker at a point of a [`Scene`]: shape, colour, size in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneMarker {
    pub at: (f64, f64),
    pub shape: MarkerShape,
    pub colour: Rgb,
    pub size: u32,
}

/// A map in true proportions with everything a picture of blocks needs: polygons, polylines,
/// markers, arrows, text labels, a legend and, optionally, a colour bar. Drawn by
/// [`plot_scene`]. Generic: the caller decides what each element stands for.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    pub title: String,
    pub polygons: Vec<ScenePolygon>,
    /// Polylines: points, colour, width in pixels.
    pub lines: Vec<SceneLine>,
    pub markers: Vec<SceneMarker>,
    /// Arrows from → to (data coordinates), colour.
    pub arrows: Vec<Arrow>,
    /// Text at a point (data coordinates), size in pixels.
    pub labels: Vec<((f64, f64), String, u32)>,
    /// Legend entries: text and colour, in order.
    pub legend: Vec<(String, Rgb)>,
    /// Colour bar: the range of values mapped by [`colour_map`] and its label (with unit).
    pub colour_bar: Option<(f64, f64, String)>,
}

/// A perceptually ordered colour map (viridis, by 9 stops, linear in between) of `t` in
/// [0, 1] (clamped; NaN is grey).
pub fn colour_map(t: f64) -> Rgb {
    const STOPS: [Rgb; 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    if t.is_nan() {
        return (160, 160, 160);
    }
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// The view of a scene: its x and y ranges in data coordinates (the extent of its
/// polygons, lines, markers and arrows, widened by 4 % on each side), as [`plot_scene`]
/// draws it. The union of several scenes' views (see [`union_view`]) keeps a sequence of
/// pictures in one frame of reference.
pub fn scene_view(scene: &Scene) -> (Range<f64>, Range<f64>) {
    let pts = || {
        scene
            .polygons
            .iter()
            .flat_map(|p| p.points.iter().copied())
            .chain(scene.lines.iter().flat_map(|l| l.0.iter().copied()))
            .chain(scene.markers.iter().map(|m| m.at))
            .chain(scene.arrows.iter().flat_map(|a| [a.0, a.1]))
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    (
        padded_range(pts().map(|p| p.0), 0.04),
        padded_range(pts().map(|p| p.1), 0.04),
    )
}

/// The smallest view holding both `a` and `b`.
pub fn union_view(
    a: &(Range<f64>, Range<f64>),
    b: &(Range<f64>, Range<f64>),
) -> (Range<f64>, Range<f64>) {
    (
        a.0.start.min(b.0.start)..a.0.end.max(b.0.end),
        a.1.start.min(b.1.start)..a.1.end.max(b.1.end),
    )
}

/// The layout of a scene drawn `width` pixels wide in `view`: the height in pixels and the
/// width of the right-hand column (legend and colour bar).
fn scene_layout(scene: &Scene, width: u32, view: &(Range<f64>, Range<f64>)) -> (u32, u32) {
    let (xr, yr) = view;
    let side = if scene.colour_bar.is_some() || !scene.legend.is_empty() {
        190u32
    } else {
        0
    };
    let (label_x, label_y, top) = (SCENE_LABELS.0, SCENE_LABELS.1, 45u32);
    let plot_w = width.saturating_sub(label_y + 20 + side).max(50) as f64;
    let ratio = (yr.end - yr.start) / (xr.end - xr.start);
    let height = ((plot_w * ratio) as u32 + label_x + top).clamp(MIN_SIZE.max(360), MAX_SIZE);
    (height, side)
}

/// Pixels of the x and y axes' labels of a scene.
const SCENE_LABELS: (u32, u32) = (40, 70);

fn check_width(width: u32) -> Result<(), PlotError> {
    if (MIN_SIZE..=MAX_SIZE).contains(&width) {
        Ok(())
    } else {
        Err(PlotError::InvalidSize {
            width,
            height: 0,
            panels: 1,
        })
    }
}

/// Draws `scene` into `path`, PNG or SVG by its extension (`.png`, `.svg`, any case),
/// `width` pixels wide, the height from the data's aspect ratio (within the size limits).
/// The legend and the colour bar take a column on the right.
pub fn plot_scene(path: &Path, scene: &Scene, width: u32) -> Result<(), PlotError> {
    check_width(width)?;
    let (xr, yr) = scene_view(scene);
    let (height, side) = scene_layout(scene, width, &(xr.clone(), yr.clone()));
    let (label_x, label_y) = SCENE_LABELS;
    ensure_font()?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let fail = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    match ext.as_deref() {
        Some("png") => {
            let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
            draw_scene(&root, scene, (&xr, &yr), (label_x, label_y), side)
                .map_err(|e| fail(e.to_string()))
        }
        Some("svg") => {
            let root = SVGBackend::new(path, (width, height)).into_drawing_area();
            draw_scene(&root, scene, (&xr, &yr), (label_x, label_y), side)
                .map_err(|e| fail(e.to_string()))
        }
        _ => Err(fail("the file name must end in .png or .svg".into())),
    }
}

/// An animated GIF of scenes drawn one after the other in one view and at one size
/// (`nmm plot RUN_DIR --every K` writes one): each frame is drawn as [`plot_scene`] draws
/// a PNG, into memory, reduced to its own 256-colour palette (NeuQuant, `gif`'s
/// `from_rgb_speed`) and written at once, so only one picture is held at a time. It plays
/// in a loop, `delay` hundredths of a second per frame.
pub struct GifAnimation {
    path: PathBuf,
    encoder: gif::Encoder<std::io::BufWriter<std::fs::File>>,
    view: (Range<f64>, Range<f64>),
    size: (u32, u32),
    delay: u16,
    frames: usize,
}

impl GifAnimation {
    /// Starts the animation in `path`: frames `width` pixels wide showing `view` (e.g. the
    /// [`union_view`] of every frame's [`scene_view`]); the height is that of the first
    /// scene drawn in this view, `first` (not drawn here: give it to [`Self::add`]).
    pub fn create(
        path: &Path,
        first: &Scene,
        width: u32,
        view: (Range<f64>, Range<f64>),
        delay: u16,
    ) -> Result<GifAnimation, PlotError> {
        check_width(width)?;
        let (height, _) = scene_layout(first, width, &view);
        let fail = |message: String| PlotError::Draw {
            path: path.to_path_buf(),
            message,
        };
        let file = std::fs::File::create(path).map_err(|e| fail(e.to_string()))?;
        let mut encoder = gif::Encoder::new(
            std::io::BufWriter::new(file),
            width as u16,
            height as u16,
            &[],
        )
        .map_err(|e| fail(e.to_string()))?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| fail(e.to_string()))?;
        Ok(GifAnimation {
            path: path.to_path_buf(),
            encoder,
            view,
            size: (width, height),
            delay,
            frames: 0,
        })
    }

    /// Draws `scene` as the next frame.
    pub fn add(&mut self, scene: &Scene) -> Result<(), PlotError> {
        ensure_font()?;
        let (w, h) = self.size;
        let fail = |message: String| PlotError::Draw {
            path: self.path.clone(),
            message,
        };
        let side = if scene.colour_bar.is_some() || !scene.legend.is_empty() {
            190u32
        } else {
            0
        };
        let mut pixels = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut pixels, (w, h)).into_drawing_area();
            draw_scene(
                &root,
                scene,
                (&self.view.0, &self.view.1),
                SCENE_LABELS,
                side,
            )
            .map_err(|e| fail(e.to_string()))?;
        }
        let mut frame = gif::Frame::from_rgb_speed(w as u16, h as u16, &pixels, 10);
        frame.delay = self.delay;
        self.encoder
            .write_frame(&frame)
            .map_err(|e| fail(e.to_string()))?;
        self.frames += 1;
        Ok(())
    }

    /// Writes the end of the file; returns the number of frames.
    pub fn finish(self) -> Result<usize, PlotError> {
        let path = self.path;
        let mut out = self.encoder.into_inner().map_err(|e| PlotError::Draw {
            path: path.clone(),
            message: e.to_string(),
        })?;
        std::io::Write::flush(&mut out).map_err(|e| PlotError::Draw {
            path,
            message: e.to_string(),
        })?;
        Ok(self.frames)
    }
}

fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

fn draw_scene<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    scene: &Scene,
    (xr, yr): (&Range<f64>, &Range<f64>),
    (label_x, label_y): (u32, u32),
    side: u32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (w, h) = root.dim_in_pixel();
    let (main, right) = root.split_horizontally(w - side);
    let mut chart = map_chart(&main, (&scene.title, 17), (xr, yr), (label_x, label_y))?;
    let xs = xr.end - xr.start;
    for p in &scene.polygons {
        if let Some((c, alpha)) = p.fill {
            chart.draw_series(std::iter::once(Polygon::new(
                p.points.clone(),
                rgb(c).mix(alpha).filled(),
            )))?;
        }
    }
    for p in &scene.polygons {
        if let Some((c, width)) = p.outline {
            let mut ring = p.points.clone();
            if let Some(&first) = ring.first() {
                ring.push(first);
            }
            chart.draw_series(std::iter::once(PathElement::new(
                ring,
                rgb(c).stroke_width(width),
            )))?;
        }
    }
    for (points, c, width) in &scene.lines {
        chart.draw_series(std::iter::once(PathElement::new(
            points.clone(),
            rgb(*c).stroke_width(*width),
        )))?;
    }
    // arrow heads 12 px long, in data units of the x axis (true proportions)
    let px = chart.plotting_area().dim_in_pixel().0.max(1) as f64;
    let head = 12.0 * xs / px;
    for &(a, b, c) in &scene.arrows {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let l = (dx * dx + dy * dy).sqrt();
        if l.is_nan() || l <= 0.0 {
            continue;
        }
        let (ux, uy) = (dx / l, dy / l);
        let hl = head.min(0.5 * l);
        let p1 = (b.0 - hl * ux + 0.4 * hl * uy, b.1 - hl * uy - 0.4 * hl * ux);
        let p2 = (b.0 - hl * ux - 0.4 * hl * uy, b.1 - hl * uy + 0.4 * hl * ux);
        chart.draw_series(std::iter::once(PathElement::new(
            vec![a, b],
            rgb(c).stroke_width(2),
        )))?;
        chart.draw_series(std::iter::once(Polygon::new(
            vec![b, p1, p2],
            rgb(c).filled(),
        )))?;
    }
    for m in &scene.markers {
        let c = rgb(m.colour);
        let s = m.size as i32;
        match m.shape {
            MarkerShape::Circle => {
                chart.draw_series(std::iter::once(Circle::new(m.at, s, c.filled())))?;
                chart.draw_series(std::iter::once(Circle::new(m.at, s, BLACK.stroke_width(1))))?;
            }
            MarkerShape::Square => {
                chart.draw_series(std::iter::once(
                    EmptyElement::at(m.at) + Rectangle::new([(-s, -s), (s, s)], c.filled()),
                ))?;
            }
            MarkerShape::Triangle => {
                chart.draw_series(std::iter::once(TriangleMarker::new(m.at, s, c.filled())))?;
            }
        }
    }
    for (at, text, size) in &scene.labels {
        let style = TextStyle::from(("sans-serif", *size as i32).into_font()).pos(
            plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ),
        );
        chart.draw_series(std::iter::once(Text::new(text.clone(), *at, style)))?;
    }
    // the right-hand column: colour bar, then legend
    let mut y0 = 50i32;
    if let Some((lo, hi, label)) = &scene.colour_bar {
        right.draw(&Text::new(
            label.clone(),
            (10, y0 - 20),
            ("sans-serif", 14).into_font(),
        ))?;
        let bar_h = (h as i32 / 2).clamp(120, 420);
        let n = 64;
        for k in 0..n {
            let t = 1.0 - (k as f64 + 0.5) / n as f64;
            let ya = y0 + bar_h * k / n;
            let yb = y0 + bar_h * (k + 1) / n;
            right.draw(&Rectangle::new(
                [(10, ya), (34, yb)],
                rgb(colour_map(t)).filled(),
            ))?;
        }
        right.draw(&Rectangle::new(
            [(10, y0), (34, y0 + bar_h)],
            BLACK.stroke_width(1),
        ))?;
        let span = hi - lo;
        for k in 0..=4 {
            let v = hi - span * k as f64 / 4.0;
            let y = y0 + bar_h * k / 4;
            right.draw(&PathElement::new(
                vec![(34, y), (40, y)],
                BLACK.stroke_width(1),
            ))?;
            right.draw(&Text::new(
                bar_label(v, span.abs().max(hi.abs()).max(lo.abs())),
                (44, y - 7),
                ("sans-serif", 13).into_font(),
            ))?;
        }
        y0 += bar_h + 30;
    }
    for (text, c) in &scene.legend {
        right.draw(&Rectangle::new([(10, y0), (30, y0 + 12)], rgb(*c).filled()))?;
        right.draw(&Text::new(
            text.clone(),
            (36, y0 - 1),
            ("sans-serif", 13).into_font(),
        ))?;
        y0 += 20;
    }
    root.present()
}

/// A colour-bar tick label: 4 significant digits, exponent form for very large or small
/// magnitudes (`scale`: the bar's largest magnitude).
fn bar_label(v: f64, scale: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !(1e-2..1e5).contains(&scale) {
        format!("{v:.3e}")
    } else {
        // 4 significant digits of the bar's largest magnitude
        let decimals = (3 - scale.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    }
}
