//! Charts as SVG or PNG, drawn with plotters: stacked panels of lines, points and error bars.
//! SVG text is text (the viewer's sans-serif); PNG text is drawn with DejaVu Sans, embedded in
//! the binary, so that no system fonts are needed; the PNG is compressed.

mod axis;
mod beside;
mod draw;
mod legend;

use image::ImageEncoder;
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::sync::Once;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    Line,
    Points,
    /// Vertical bars, one per pair of points `(x, low), (x, high)`: error bars.
    Bars,
    /// Bars as [`Style::Bars`], the spread of the series before it: in its colour, and
    /// without a legend entry of their own (the name goes unused).
    Spread,
}

#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

#[derive(Debug, Clone)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub log_x: bool,
    pub log_y: bool,
}

/// The size of one panel, in pixels; panels stack top to bottom.
pub const W: u32 = 760;
pub const H: u32 = 300;

/// DejaVu Sans (fonts/LICENSE-DejaVu.txt), for the text of PNG plots and the layout of both.
static DEJAVU_SANS: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU_SANS).is_err() {
            unreachable!("the embedded font is a valid TrueType font");
        }
    });
}

fn size(panels: &[Panel]) -> (u32, u32) {
    (W, H * panels.len().max(1) as u32)
}

fn draw_all<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, panels: &[Panel]) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let y_area = panels.iter().map(|p| draw::y_area(&root, p)).max().unwrap_or(0);
    if !panels.is_empty() {
        for (area, p) in root.split_evenly((panels.len(), 1)).iter().zip(panels) {
            draw::panel(area, p, y_area)?;
        }
    }
    root.present().map_err(|e| e.to_string())
}

/// Panels stacked top to bottom in one SVG document.
pub fn render_svg(panels: &[Panel]) -> String {
    register_font();
    let mut svg = String::new();
    let drawn = draw_all(
        SVGBackend::with_string(&mut svg, size(panels)).into_drawing_area(),
        panels,
    );
    debug_assert!(drawn.is_ok(), "{drawn:?}");
    svg
}

/// Panels stacked top to bottom as a PNG image.
pub fn render_png(panels: &[Panel]) -> Vec<u8> {
    register_font();
    let (w, h) = size(panels);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    let drawn = draw_all(BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area(), panels);
    debug_assert!(drawn.is_ok(), "{drawn:?}");
    let mut png = Vec::new();
    let enc = PngEncoder::new_with_quality(&mut png, CompressionType::Best, FilterType::Adaptive);
    let encoded = enc.write_image(&rgb, w, h, image::ColorType::Rgb8);
    debug_assert!(encoded.is_ok(), "{encoded:?}");
    png
}

/// Writes the panels to `path`: SVG or PNG by the file's ending.
pub fn write(path: &str, panels: &[Panel]) -> Result<(), String> {
    let lower = path.to_ascii_lowercase();
    let bytes = if lower.ends_with(".svg") {
        render_svg(panels).into_bytes()
    } else if lower.ends_with(".png") {
        render_png(panels)
    } else {
        return Err(format!("{path}: name the plot *.svg or *.png"));
    };
    std::fs::write(path, bytes).map_err(|e| format!("cannot write {path}: {e}"))
}

#[cfg(test)]
mod tests;
