//! Charts as SVG or PNG, with no fonts or system libraries: stacked panels of lines and
//! points, drawn through one [`Surface`] by an SVG writer or a small rasterizer.

mod raster;

use std::fmt::Write;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    Line,
    Points,
    /// Vertical bars, one per pair of points `(x, low), (x, high)`: error bars.
    Bars,
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

pub const W: f64 = 760.0;
pub const H: f64 = 300.0;
const M: (f64, f64, f64, f64) = (70.0, 20.0, 30.0, 45.0); // left, right, top, bottom

/// Colours as RGB.
pub type Rgb = [u8; 3];
const COLORS: [Rgb; 6] = [
    [31, 119, 180],
    [214, 39, 40],
    [44, 160, 44],
    [148, 103, 189],
    [255, 127, 14],
    [140, 86, 75],
];
const FRAME: Rgb = [68, 68, 68];
const GRID: Rgb = [221, 221, 221];
const INK: Rgb = [0, 0, 0];

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// What a chart is drawn with.
pub trait Surface {
    fn line(&mut self, a: (f64, f64), b: (f64, f64), c: Rgb);
    fn polyline(&mut self, pts: &[(f64, f64)], c: Rgb);
    fn dot(&mut self, p: (f64, f64), c: Rgb);
    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: Rgb, filled: bool);
    /// Text with its baseline at `y`; `vertical` reads bottom to top.
    fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, vertical: bool, s: &str);
}

/// Round tick positions covering `[lo, hi]`.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).abs().max(1e-12);
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while t <= hi + step * 1e-9 {
        out.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
        // Where the step is below the spacing of floats at `t` (values all equal, or a few
        // ulps apart, at a large magnitude), adding it leaves `t` where it is.
        let next = t + step;
        if next <= t {
            break;
        }
        t = next;
    }
    out
}

/// Ticks of a log axis whose range is `[lo, hi]` in decades: 1, 2 and 5 per decade when it
/// spans few decades, decades only otherwise.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mults: &[f64] = if hi - lo <= 2.5 { &[1.0, 2.0, 5.0] } else { &[1.0] };
    let mut out = Vec::new();
    for d in (lo.floor() as i32)..=(hi.ceil() as i32) {
        for m in mults {
            let t = m * 10f64.powi(d);
            if (lo - 1e-9..=hi + 1e-9).contains(&t.log10()) {
                out.push(t);
            }
        }
    }
    out
}

fn fmt_tick(t: f64) -> String {
    if t != 0.0 && (t.abs() < 1e-3 || t.abs() >= 1e6) {
        return format!("{t:.0e}");
    }
    let s = format!("{t:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn draw_panel(s: &mut impl Surface, p: &Panel, y0: f64) {
    let tx = |x: f64| if p.log_x { x.log10() } else { x };
    let ty = |y: f64| if p.log_y { y.log10() } else { y };
    let good = |&(x, y): &(f64, f64)| tx(x).is_finite() && ty(y).is_finite();
    let (mut xl, mut xh, mut yl, mut yh) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in p.series.iter().flat_map(|s| s.points.iter()).filter(|p| good(p)) {
        xl = xl.min(tx(x));
        xh = xh.max(tx(x));
        yl = yl.min(ty(y));
        yh = yh.max(ty(y));
    }
    if xl > xh {
        (xl, xh, yl, yh) = (0.0, 1.0, 0.0, 1.0);
    }
    if yh - yl < 1e-12 {
        yl -= 1.0;
        yh += 1.0;
    }
    let pad = (yh - yl) * 0.05;
    let (yl, yh) = (yl - pad, yh + pad);
    let (pw, ph) = (W - M.0 - M.1, H - M.2 - M.3);
    let top = y0 + M.2;
    let sx = |x: f64| M.0 + (tx(x) - xl) / (xh - xl).max(1e-12) * pw;
    let sy = |y: f64| top + (1.0 - (ty(y) - yl) / (yh - yl)) * ph;
    let axis = |log: bool, lo: f64, hi: f64| if log { log_ticks(lo, hi) } else { ticks(lo, hi) };
    for t in axis(p.log_x, xl, xh) {
        let x = sx(t);
        s.line((x, top), (x, top + ph), GRID);
        s.text(x, top + ph + 15.0, 11.0, Anchor::Middle, false, &fmt_tick(t));
    }
    for t in axis(p.log_y, yl, yh) {
        let y = sy(t);
        s.line((M.0, y), (M.0 + pw, y), GRID);
        s.text(M.0 - 5.0, y + 4.0, 11.0, Anchor::End, false, &fmt_tick(t));
    }
    s.rect(M.0, top, pw, ph, FRAME, false);
    s.text(W / 2.0, y0 + 18.0, 14.0, Anchor::Middle, false, &p.title);
    s.text(M.0 + pw / 2.0, y0 + H - 8.0, 12.0, Anchor::Middle, false, &p.x_label);
    s.text(16.0, top + ph / 2.0, 12.0, Anchor::Middle, true, &p.y_label);
    for (k, series) in p.series.iter().enumerate() {
        let c = COLORS[k % COLORS.len()];
        let at = |&(x, y): &(f64, f64)| (sx(x), sy(y));
        let pts: Vec<(f64, f64)> = series.points.iter().filter(|p| good(p)).map(at).collect();
        match series.style {
            Style::Line => s.polyline(&pts, c),
            Style::Points => pts.iter().for_each(|&q| s.dot(q, c)),
            Style::Bars => series
                .points
                .chunks_exact(2)
                .filter(|b| good(&b[0]) && good(&b[1]))
                .for_each(|b| s.line(at(&b[0]), at(&b[1]), c)),
        }
        let ly = top + 14.0 + 14.0 * k as f64;
        s.rect(M.0 + 10.0, ly - 4.0, 10.0, 3.0, c, true);
        s.text(M.0 + 25.0, ly, 11.0, Anchor::Start, false, &series.name);
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

struct Svg(String);

impl Surface for Svg {
    fn line(&mut self, a: (f64, f64), b: (f64, f64), c: Rgb) {
        let _ = writeln!(
            self.0,
            r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}"/>"#,
            a.0,
            a.1,
            b.0,
            b.1,
            hex(c)
        );
    }

    fn polyline(&mut self, pts: &[(f64, f64)], c: Rgb) {
        let d: Vec<String> = pts.iter().map(|p| format!("{:.1},{:.1}", p.0, p.1)).collect();
        let _ = writeln!(
            self.0,
            r#"<polyline fill="none" stroke="{}" stroke-width="1.5" points="{}"/>"#,
            hex(c),
            d.join(" ")
        );
    }

    fn dot(&mut self, p: (f64, f64), c: Rgb) {
        let _ = writeln!(
            self.0,
            r#"<circle cx="{:.1}" cy="{:.1}" r="2.2" fill="{}"/>"#,
            p.0,
            p.1,
            hex(c)
        );
    }

    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: Rgb, filled: bool) {
        let paint = if filled {
            format!(r#"fill="{}""#, hex(c))
        } else {
            format!(r#"fill="none" stroke="{}""#, hex(c))
        };
        let _ = writeln!(
            self.0,
            r#"<rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" {paint}/>"#
        );
    }

    fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, vertical: bool, s: &str) {
        let a = match anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let rot = if vertical {
            format!(r#" transform="rotate(-90 {x:.1} {y:.1})""#)
        } else {
            String::new()
        };
        let _ = writeln!(
            self.0,
            r#"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="{a}"{rot}>{}</text>"#,
            esc(s)
        );
    }
}

/// Panels stacked top to bottom in one SVG document.
pub fn render_svg(panels: &[Panel]) -> String {
    let total = H * panels.len() as f64;
    let mut s = Svg(format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{total}\" viewBox=\"0 0 {W} {total}\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    ));
    for (i, p) in panels.iter().enumerate() {
        draw_panel(&mut s, p, i as f64 * H);
    }
    s.0.push_str("</svg>\n");
    s.0
}

/// Panels stacked top to bottom as a PNG image.
pub fn render_png(panels: &[Panel]) -> Vec<u8> {
    let mut r = raster::Raster::new(W as usize, (H as usize) * panels.len().max(1));
    for (i, p) in panels.iter().enumerate() {
        draw_panel(&mut r, p, i as f64 * H);
    }
    r.png()
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
mod tests {
    use super::*;

    fn panel() -> Panel {
        Panel {
            title: "a < b".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![
                Series {
                    name: "line".into(),
                    points: vec![(0.0, 1.0), (1.0, 2.0)],
                    style: Style::Line,
                },
                Series {
                    name: "pts".into(),
                    points: vec![(0.5, 1.5), (f64::NAN, 0.0)],
                    style: Style::Points,
                },
            ],
            log_x: false,
            log_y: false,
        }
    }

    #[test]
    fn log_axes_tick_at_decades_and_skip_what_they_cannot_show() {
        assert_eq!(log_ticks(-0.2, 1.1), vec![1.0, 2.0, 5.0, 10.0]);
        assert_eq!(log_ticks(-3.0, 2.0), vec![1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0]);
        assert_eq!(fmt_tick(1e-4), "1e-4");
        let mut p = panel();
        (p.log_x, p.log_y) = (true, true);
        p.series.push(Series {
            name: "ci".into(),
            points: vec![(1.0, 1.0), (1.0, 2.0), (0.5, -1.0), (0.5, 3.0)],
            style: Style::Bars,
        });
        // y = -1 cannot be drawn on a log axis: one bar of the two.
        let svg = render_svg(&[p]);
        assert_eq!(svg.matches(r##"stroke="#2ca02c"/>"##).count(), 1, "{svg}");
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = ticks(-0.013, 0.021);
        assert!(t.first().unwrap() >= &-0.013 && t.last().unwrap() <= &0.021 && t.len() >= 3);
    }

    #[test]
    fn equal_values_at_any_magnitude_draw_in_finite_time() {
        // All x equal at about 2000 or more (or a few ulps apart): the tick step fell below the
        // spacing of floats there, `t += step` stood still and the tick list grew until the
        // memory ran out. Found by the `plot` fuzz target.
        for v in [2000.0f64, 2048.0, -52077.00000000004, 1e6, 1e20, -1e300] {
            for w in [v, f64::from_bits(v.to_bits() + 1), f64::from_bits(v.to_bits() + 3)] {
                assert!(ticks(v.min(w), v.max(w)).len() <= 12, "{v} {w}");
                let mut p = panel();
                p.series[0].points = vec![(v, 1.0), (w, 2.0)];
                p.series[1].points = vec![(v, 0.5), (w, 1.5)];
                let mut q = panel();
                q.series[0].points = vec![(0.0, v), (1.0, w)];
                q.series[1].points = vec![(0.5, v)];
                assert!(render_svg(&[p.clone(), q.clone()]).ends_with("</svg>\n"));
                assert_eq!(render_png(&[p, q])[..4], *b"\x89PNG");
            }
        }
    }

    #[test]
    fn svg_has_every_series() {
        let s = render_svg(&[panel(), panel()]);
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
        assert_eq!(s.matches("<polyline").count(), 2);
        assert_eq!(s.matches("<circle").count(), 2);
        assert!(s.contains("a &lt; b"));
        assert!(write("/tmp/x.gif", &[]).is_err());
    }

    #[test]
    fn png_is_a_valid_image_of_the_right_size() {
        let png = render_png(&[panel(), panel()]);
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(&png[12..16], b"IHDR");
        assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), W as u32);
        assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 2 * H as u32);
        assert_eq!(&png[png.len() - 8..png.len() - 4], b"IEND");
    }
}
