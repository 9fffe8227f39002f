//! Small SVG charts (no fonts, no system libraries): stacked panels of lines and points.

use std::fmt::Write;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    Line,
    Points,
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
}

const W: f64 = 760.0;
const H: f64 = 300.0;
const M: (f64, f64, f64, f64) = (70.0, 20.0, 30.0, 45.0); // left, right, top, bottom
const COLORS: [&str; 6] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

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
        t += step;
    }
    out
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

fn panel(out: &mut String, p: &Panel, y0: f64) {
    let tx = |x: f64| if p.log_x { x.log10() } else { x };
    let pts = p
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut xl, mut xh, mut yl, mut yh) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        xl = xl.min(tx(x));
        xh = xh.max(tx(x));
        yl = yl.min(y);
        yh = yh.max(y);
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
    let sx = |x: f64| M.0 + (tx(x) - xl) / (xh - xl).max(1e-12) * pw;
    let sy = |y: f64| y0 + M.2 + (1.0 - (y - yl) / (yh - yl)) * ph;
    let _ = writeln!(
        out,
        r##"<rect x="{}" y="{}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>"##,
        M.0,
        y0 + M.2
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="14" text-anchor="middle">{}</text>"#,
        W / 2.0,
        y0 + 18.0,
        esc(&p.title)
    );
    let xt = if p.log_x {
        ticks(xl, xh).into_iter().map(|t| 10f64.powf(t)).collect()
    } else {
        ticks(xl, xh)
    };
    for t in xt {
        let x = sx(t);
        let _ = writeln!(
            out,
            r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/>"##,
            y0 + M.2,
            y0 + M.2 + ph
        );
        let _ = writeln!(
            out,
            r#"<text x="{x:.1}" y="{:.1}" font-size="11" text-anchor="middle">{t}</text>"#,
            y0 + M.2 + ph + 15.0
        );
    }
    for t in ticks(yl, yh) {
        let y = sy(t);
        let _ = writeln!(
            out,
            r##"<line x1="{}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/>"##,
            M.0,
            M.0 + pw
        );
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{:.1}" font-size="11" text-anchor="end">{}</text>"#,
            M.0 - 5.0,
            y + 4.0,
            fmt_tick(t)
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{:.1}" font-size="12" text-anchor="middle">{}</text>"#,
        M.0 + pw / 2.0,
        y0 + H - 8.0,
        esc(&p.x_label)
    );
    let _ = writeln!(
        out,
        r#"<text x="14" y="{:.1}" font-size="12" text-anchor="middle" transform="rotate(-90 14 {:.1})">{}</text>"#,
        y0 + M.2 + ph / 2.0,
        y0 + M.2 + ph / 2.0,
        esc(&p.y_label)
    );
    for (k, s) in p.series.iter().enumerate() {
        let c = COLORS[k % COLORS.len()];
        let good = s.points.iter().filter(|(x, y)| x.is_finite() && y.is_finite());
        match s.style {
            Style::Line => {
                let d: Vec<String> = good.map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y))).collect();
                let _ = writeln!(
                    out,
                    r#"<polyline fill="none" stroke="{c}" stroke-width="1.5" points="{}"/>"#,
                    d.join(" ")
                );
            }
            Style::Points => {
                for &(x, y) in good {
                    let _ = writeln!(
                        out,
                        r#"<circle cx="{:.1}" cy="{:.1}" r="2.2" fill="{c}"/>"#,
                        sx(x),
                        sy(y)
                    );
                }
            }
        }
        let ly = y0 + M.2 + 14.0 + 14.0 * k as f64;
        let _ = writeln!(
            out,
            r#"<rect x="{}" y="{:.1}" width="10" height="3" fill="{c}"/>"#,
            M.0 + 10.0,
            ly - 4.0
        );
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{ly:.1}" font-size="11">{}</text>"#,
            M.0 + 25.0,
            esc(&s.name)
        );
    }
}

fn fmt_tick(t: f64) -> String {
    let s = format!("{t:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// Panels stacked top to bottom in one SVG document.
pub fn render(panels: &[Panel]) -> String {
    let mut out = String::new();
    let total = H * panels.len() as f64;
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{total}" viewBox="0 0 {W} {total}" font-family="sans-serif">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (i, p) in panels.iter().enumerate() {
        panel(&mut out, p, i as f64 * H);
    }
    out.push_str("</svg>\n");
    out
}

/// Writes the panels to `path` (SVG).
pub fn write(path: &str, panels: &[Panel]) -> Result<(), String> {
    if !path.to_ascii_lowercase().ends_with(".svg") {
        return Err(format!("{path}: plots are written as SVG; name the file *.svg"));
    }
    std::fs::write(path, render(panels)).map_err(|e| format!("cannot write {path}: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = ticks(-0.013, 0.021);
        assert!(t.first().unwrap() >= &-0.013 && t.last().unwrap() <= &0.021 && t.len() >= 3);
    }

    #[test]
    fn renders_every_series() {
        let p = Panel {
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
        };
        let s = render(&[p.clone(), p]);
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
        assert_eq!(s.matches("<polyline").count(), 2);
        assert_eq!(s.matches("<circle").count(), 2);
        assert!(s.contains("a &lt; b"));
        assert!(write("/tmp/x.png", &[]).is_err());
    }
}
