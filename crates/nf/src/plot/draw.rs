//! One panel drawn with plotters on any backend: the title fitted to the width (smaller, then
//! wrapped), axes from [`Axis`], the series, and a legend.

use super::axis::Axis;
use super::beside;
use super::legend::{self, LegendBox, Spot};
use super::{Panel, Series, Style};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

type Area<DB> = DrawingArea<DB, Shift>;
type Failed = String;

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];
const GRID: RGBColor = RGBColor(221, 221, 221);
const FRAME: RGBColor = RGBColor(68, 68, 68);
const FONT: &str = "sans-serif";
const TICK_SIZE: f64 = 14.0;

fn failed(e: impl std::fmt::Display) -> Failed {
    format!("cannot draw the plot: {e}")
}

/// Text as one line of printable characters: no control characters, nor the two that XML
/// refuses.
fn clean(s: &str) -> String {
    s.chars()
        .filter(|c| !c.is_control() && !matches!(c, '\u{fffe}' | '\u{ffff}'))
        .collect()
}

fn width<DB: DrawingBackend>(area: &Area<DB>, s: &str, size: f64) -> u32 {
    area.estimate_text_size(s, &(FONT, size).into_font().into())
        .map_or(0, |(w, _)| w)
}

/// The largest size from `max` down to `min` (in steps of 1) at which `s` is at most `room`
/// wide, or `min`.
fn fit_size(s: &str, room: u32, max: f64, min: f64, w: impl Fn(&str, f64) -> u32) -> f64 {
    let mut size = max;
    while size > min && w(s, size) > room {
        size -= 1.0;
    }
    size
}

/// `s` as lines at most `room` wide: words moved to the next line, a word too long for a line
/// broken between characters. At most `max_lines` lines, the last ending in "..." if cut.
pub(super) fn wrap(s: &str, room: u32, max_lines: usize, w: impl Fn(&str) -> u32) -> Vec<String> {
    let mut lines: Vec<String> = vec![String::new()];
    for word in s.split(' ').filter(|w| !w.is_empty()) {
        let last = lines.last_mut().expect("one line at least");
        let joined = if last.is_empty() {
            word.to_string()
        } else {
            format!("{last} {word}")
        };
        if w(&joined) <= room {
            *last = joined;
            continue;
        }
        if !last.is_empty() {
            lines.push(String::new());
        }
        for c in word.chars() {
            let last = lines.last_mut().expect("one line at least");
            last.push(c);
            if w(last) > room && last.chars().count() > 1 {
                last.pop();
                lines.push(c.to_string());
            }
        }
    }
    if lines.len() > max_lines {
        lines.truncate(max_lines);
        let last = lines.last_mut().expect("one line at least");
        while !last.is_empty() && w(&format!("{last}...")) > room {
            last.pop();
        }
        last.push_str("...");
    }
    lines
}

/// The title at the top of `area`, from 18 px down to 13 px, wrapped where even that is too
/// wide; returns the area below it.
fn title<DB: DrawingBackend>(area: &Area<DB>, text: &str) -> Result<Area<DB>, Failed> {
    let room = area.dim_in_pixel().0.saturating_sub(20);
    let size = fit_size(text, room, 18.0, 13.0, |s, z| width(area, s, z));
    let lines = wrap(text, room, 3, |s| width(area, s, size));
    let line_h = (size * 1.15).ceil() as i32;
    let style = TextStyle::from((FONT, size).into_font()).pos(Pos::new(HPos::Center, VPos::Top));
    let cx = area.dim_in_pixel().0 as i32 / 2;
    for (i, line) in lines.iter().enumerate() {
        area.draw_text(line, &style, (cx, 6 + i as i32 * line_h))
            .map_err(failed)?;
    }
    Ok(area.split_vertically(10 + lines.len() as i32 * line_h).1)
}

/// The panel's axes: x over every point, y over those x can show.
fn axes(p: &Panel) -> (Axis, Axis) {
    let all = || p.series.iter().flat_map(|s| s.points.iter());
    // A little room either side: the first and last dots are not cut by the frame.
    let x = Axis::fit(all().map(|q| q.0), p.log_x, 0.02);
    let y_pts = all().filter(|q| x.shows(q.0)).map(|q| q.1);
    let y = Axis::fit(y_pts, p.log_y, 0.05);
    (x, y)
}

/// The width the panel's y tick labels and axis label take, pixels: with or without the
/// room a legend may need above the data.
pub(super) fn y_area<DB: DrawingBackend>(area: &Area<DB>, p: &Panel) -> u32 {
    let y = axes(p).1;
    let tick_w = [y.with_room_above(legend::MOST_ROOM), y]
        .iter()
        .flat_map(|y| y.ticks().into_iter().map(|t| width(area, &y.label(t), TICK_SIZE)))
        .max();
    tick_w.unwrap_or(0) + 36
}

/// One panel into `area`, its y labels in `y_area` pixels (the figure's widest, so that
/// stacked panels share their x positions).
pub(super) fn panel<DB: DrawingBackend>(area: &Area<DB>, p: &Panel, y_area: u32) -> Result<(), Failed> {
    let (x, y) = axes(p);
    let rest = title(area, &clean(&p.title))?;
    let (x_label, y_label) = (clean(&p.x_label), clean(&p.y_label));
    let (w, h) = rest.dim_in_pixel();
    let x_size = fit_size(&x_label, w.saturating_sub(y_area + 20), 15.0, 9.0, |s, z| {
        width(&rest, s, z)
    });
    let y_size = fit_size(&y_label, h.saturating_sub(50), 15.0, 9.0, |s, z| width(&rest, s, z));
    // The plot's size within the margins and label areas below (and a legend beside it).
    let (pw, ph) = (w.saturating_sub(26 + y_area), h.saturating_sub(54));
    let names: Vec<String> = p
        .series
        .iter()
        .map(|s| match s.style {
            Style::Spread => String::new(),
            _ => clean(&s.name),
        })
        .collect();
    let legend = legend_style(&rest, &names, pw);
    let (y, spot) = match legend {
        Some((_, b)) => {
            let at = legend::place(p, (&x, &y), (f64::from(pw), f64::from(ph)), b);
            (at.y, Some(at.spot))
        }
        None => (y, None),
    };
    let beside = match (legend, spot) {
        (Some((_, b)), Some(Spot::Beside)) => (b.w + legend::BESIDE_GAP).ceil() as u32,
        _ => 0,
    };
    let pw = pw.saturating_sub(beside);

    let mut chart = ChartBuilder::on(&rest)
        .margin_right(20 + beside)
        .margin_left(6)
        .margin_bottom(6)
        .margin_top(4)
        .x_label_area_size(44)
        .y_label_area_size(y_area)
        .build_cartesian_2d(x.clone(), y.clone())
        .map_err(failed)?;
    chart
        .configure_mesh()
        .bold_line_style(GRID)
        .axis_style(FRAME)
        .label_style((FONT, TICK_SIZE))
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT, x_size.min(y_size)))
        .draw()
        .map_err(failed)?;
    // The frame: plotters draws the left and bottom axes only.
    let plot = chart.plotting_area().strip_coord_spec();
    debug_assert_eq!(plot.dim_in_pixel(), (pw, ph), "the plot's size as laid out");
    let frame = Rectangle::new([(0, 0), (pw as i32 - 1, ph as i32 - 1)], FRAME);
    plot.draw(&frame).map_err(failed)?;

    // A spread takes the colour of the series before it. Dots and lines of a series drawn
    // before others of their kind are larger, one pixel for each drawn after (up to two):
    // where they coincide (residuals before and after a finding that changes few, a model
    // equal to another) each shows round the next.
    let mut colour = 0;
    let mut entries = Vec::new();
    for (k, (s, name)) in p.series.iter().zip(&names).enumerate() {
        colour += usize::from(s.style != Style::Spread);
        let c = COLORS[(colour + COLORS.len() - 1) % COLORS.len()];
        let later = p.series[k + 1..].iter().filter(|l| l.style == s.style).count();
        draw_series(&mut chart, s, name, (c, later.min(2) as u32), (&x, &y))?;
        if !name.is_empty() {
            entries.push(beside::Entry {
                name: name.clone(),
                style: s.style,
                colour: c,
            });
        }
    }
    match (legend, spot) {
        (Some((size, _)), Some(Spot::Corner(corner))) => chart
            .configure_series_labels()
            .position(corner.position())
            .background_style(WHITE.mix(0.85))
            .border_style(GRID)
            .label_font((FONT, size))
            .draw()
            .map_err(failed)?,
        // The plot's top right corner in `rest` is at (6 + y_area + pw, 4).
        (Some((size, b)), Some(Spot::Beside)) => beside::draw(
            &rest,
            &entries,
            (FONT, size),
            ((6 + y_area + pw) as i32 + legend::BESIDE_GAP as i32, 4),
            (b.w.round() as i32, b.h.round() as i32),
            GRID,
        )?,
        _ => {}
    }
    Ok(())
}

/// The legend's text size and box for `names` in a plot `pw` wide: smaller where a name is
/// too long for it; `None` when no series is named.
fn legend_style<DB: DrawingBackend>(area: &Area<DB>, names: &[String], pw: u32) -> Option<(f64, LegendBox)> {
    let named: Vec<&String> = names.iter().filter(|n| !n.is_empty()).collect();
    let widest = named.iter().max_by_key(|n| width(area, n, TICK_SIZE))?;
    let size = fit_size(widest, pw.saturating_sub(60), TICK_SIZE, 9.0, |s, z| width(area, s, z));
    // plotters' legend: a 30 px marker area and 10 px margins around the names, a row per
    // name 1.25 of the text's height.
    let b = LegendBox {
        w: f64::from(width(area, widest, size)) + 50.0,
        h: named.len() as f64 * size * 1.25 + 20.0,
    };
    Some((size, b))
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

fn draw_series<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    s: &Series,
    name: &str,
    (c, larger): (RGBColor, u32),
    (x, y): (&Axis, &Axis),
) -> Result<(), Failed> {
    let good = |&(a, b): &(f64, f64)| x.shows(a) && y.shows(b);
    let (radius, line) = (3 + larger, c.stroke_width(2 + larger));
    let legend_line = c.stroke_width(2);
    let drawn = match s.style {
        Style::Points => {
            let dots = s.points.iter().filter(|q| good(q));
            let dots = dots.map(|&q| Circle::new(q, radius, c.filled()));
            let drawn = chart.draw_series(dots).map_err(failed)?;
            if !name.is_empty() {
                drawn
                    .label(name)
                    .legend(move |(a, b)| Circle::new((a + 8, b), 3, c.filled()));
            }
            return Ok(());
        }
        // A point that cannot be shown breaks the line; a point alone between two breaks is
        // a small dot.
        Style::Line => {
            let lone = s.points.split(|q| !good(q)).filter(|run| run.len() == 1);
            chart
                .draw_series(lone.map(|run| Circle::new(run[0], 2, c.filled())))
                .map_err(failed)?;
            s.points
                .split(|q| !good(q))
                .filter(|run| run.len() > 1)
                .map(|run| PathElement::new(run.to_vec(), line))
                .collect::<Vec<_>>()
        }
        Style::Bars | Style::Spread => s
            .points
            .chunks_exact(2)
            .filter(|b| good(&b[0]) && good(&b[1]))
            .map(|b| PathElement::new(b.to_vec(), c.stroke_width(1)))
            .collect(),
    };
    let drawn = chart.draw_series(drawn).map_err(failed)?;
    if !name.is_empty() {
        drawn
            .label(name)
            .legend(move |(a, b)| PathElement::new([(a, b), (a + 16, b)], legend_line));
    }
    Ok(())
}
