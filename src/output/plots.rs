//! Plots written on every run, PNG and SVG (plotters, with a bundled DejaVu font so that no system
//! font library is needed): the pull-out curve of each prescribed target, and T(x), u(x), τ(x) and
//! σn(x) along each reinforcement at chosen steps (the paper's Figs. 5, 6, 8, 9 and 10).

use super::owned_folder::OwnedFolder;
use crate::error::Error;
use image::ImageEncoder;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// One curve: a label and its points.
pub type Series = (String, Vec<(f64, f64)>);

/// One panel: title, axis labels (with units) and curves.
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Labels of series drawn as markers only (measured points), the others as lines.
    pub markers_only: Vec<String>,
}

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        // The bundled font is valid TrueType; failing to register it only costs the labels.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
    });
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
];

fn bounds(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    let pts = series.iter().flat_map(|(_, p)| p.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    if x0 > x1 {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    // a span within round-off of its values (a force that is zero to 1e-14 throughout) is drawn
    // flat, not stretched over the whole axis as if it varied
    let pad = |a: f64, b: f64| {
        let flat = (b - a).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0);
        let d = if flat { 0.5 * a.abs().max(b.abs()).max(1.0) } else { 0.05 * (b - a) };
        (a - d, b + d)
    };
    (pad(x0, x1), pad(y0.min(0.0), y1.max(0.0)))
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> Result<(), String> {
    let ((x0, x1), (y0, mut y1)) = bounds(&panel.series);
    let legend = panel.series.len() > 1 || panel.series.iter().any(|(l, _)| !l.is_empty());
    if legend {
        // headroom above the data, so that the legend in the upper right never covers it
        y1 += 0.12 * (1 + panel.series.len()) as f64 * (y1 - y0);
    }
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    // a curve drawn right after a series of measured points takes their colour (the points and
    // the curve fitted or computed for them)
    let mut k = 0;
    let mut after_markers = false;
    for (i, (label, points)) in panel.series.iter().enumerate() {
        let markers = panel.markers_only.contains(label);
        if i > 0 && !(after_markers && !markers) {
            k += 1;
        }
        after_markers = markers;
        let colour = COLOURS[k % COLOURS.len()];
        if markers {
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                .map_err(|e| e.to_string())?
                .label(label.as_str())
                .legend(move |(x, y)| Circle::new((x + 9, y), 5, colour.filled()));
            continue;
        }
        chart
            .draw_series(LineSeries::new(points.iter().copied(), colour.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 2, colour.filled()))).map_err(|e| e.to_string())?;
    }
    if legend {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn draw_all<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, panels: &[Panel], columns: usize) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let rows = panels.len().div_ceil(columns).max(1);
    let areas = root.split_evenly((rows, columns));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, panel)?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Write `stem.png` and `stem.svg` in `folder` (`stem` may name a folder inside it too) with the
/// panels on a grid of `columns`.
///
/// # Errors
/// [`Error::Write`] naming the file.
pub fn write_figure(folder: &OwnedFolder, stem: &str, panels: &[Panel], columns: usize) -> Result<(), Error> {
    register_font();
    let columns = columns.max(1);
    let rows = panels.len().div_ceil(columns).max(1);
    let size = (640 * columns as u32, 440 * rows as u32);
    let fail = |name: &str, message: String| Error::Write {
        path: folder.path().join(name),
        source: std::io::Error::other(message),
    };
    // SVG: drawn to a string
    let svg_name = format!("{stem}.svg");
    let mut svg = String::new();
    draw_all(SVGBackend::with_string(&mut svg, size).into_drawing_area(), panels, columns)
        .map_err(|m| fail(&svg_name, m))?;
    folder.write(&svg_name, svg.as_bytes())?;
    // PNG: drawn to an RGB buffer, encoded in memory
    let png_name = format!("{stem}.png");
    let mut rgb = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    draw_all(BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area(), panels, columns)
        .map_err(|m| fail(&png_name, m))?;
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&rgb, size.0, size.1, image::ColorType::Rgb8)
        .map_err(|e| fail(&png_name, e.to_string()))?;
    folder.write(&png_name, &png)
}

#[cfg(test)]
mod tests {
    //! The axes' ranges: a curve that is zero to round-off is drawn flat at zero; a real one fills
    //! its axis with a 5 % margin.
    use super::*;

    #[test]
    fn a_curve_zero_to_round_off_is_drawn_flat() {
        let noise: Series = ("force".into(), vec![(0.0, 0.0), (0.002, 0.0), (0.004, 3.5e-14), (0.008, 0.0)]);
        let (_, (y0, y1)) = bounds(&[noise]);
        assert!(y0 <= -0.5 && y1 >= 0.5, "({y0}, {y1})");
        let curve: Series = ("force".into(), vec![(0.0, 0.0), (0.01, 12.0)]);
        let (_, (y0, y1)) = bounds(&[curve]);
        assert!((y0 + 0.6).abs() < 1e-12 && (y1 - 12.6).abs() < 1e-12, "({y0}, {y1})");
    }
}
