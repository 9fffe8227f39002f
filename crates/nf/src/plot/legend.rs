//! Where a panel's legend goes: the first corner of the plot that no point, bar or line
//! reaches; where every corner holds some, above the data in room made for it at the top
//! of the y axis; where that room would squeeze the data, beside the plot, which is made
//! narrower for it; and only where that would squeeze it too, over what it hides least.

use super::axis::Axis;
use super::{Panel, Style};
use plotters::coord::ranged1d::Ranged;
use plotters::prelude::SeriesLabelPosition;

/// The legend's box, pixels, as plotters draws it: 5 px in from its corner of the plot.
#[derive(Debug, Clone, Copy)]
pub(super) struct LegendBox {
    pub w: f64,
    pub h: f64,
}

/// A corner of the plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Corner {
    pub left: bool,
    pub top: bool,
}

impl Corner {
    pub fn position(self) -> SeriesLabelPosition {
        use SeriesLabelPosition::*;
        match (self.left, self.top) {
            (true, true) => UpperLeft,
            (false, true) => UpperRight,
            (true, false) => LowerLeft,
            (false, false) => LowerRight,
        }
    }
}

/// Where the legend goes: in a corner of the plot, or beside it on the right.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Spot {
    Corner(Corner),
    Beside,
}

/// Where the legend goes and the y axis that leaves it room.
#[derive(Debug, Clone)]
pub(super) struct Placement {
    pub spot: Spot,
    pub y: Axis,
}

/// The gap between the plot and a legend beside it, px.
pub(super) const BESIDE_GAP: f64 = 10.0;
/// The widest share of the plot a legend beside it may take from it.
const MOST_BESIDE: f64 = 0.4;

/// Plotters' gap between the box and the plot's edge, px.
const INSET: f64 = 5.0;
/// Clearance around the box: the largest dot's radius and a little, px.
const CLEAR: f64 = 6.0;
/// The y axis grows by at most this factor to leave a legend room above the data: more
/// would squeeze the data for a legend (an Allan plot's six entries over its term lines
/// made room of several decades).
const MOST_GROWTH: f64 = 1.4;
/// The share of the y axis a legend's room may take.
pub(super) const MOST_ROOM: f64 = 1.0 - 1.0 / MOST_GROWTH;

/// Corners in order of preference: top before bottom, left before right.
const CORNERS: [Corner; 4] = [
    Corner { left: true, top: true },
    Corner { left: false, top: true },
    Corner { left: true, top: false },
    Corner {
        left: false,
        top: false,
    },
];

/// Where the legend `b` goes in a plot of `pw` by `ph` pixels over the axes `x` and `y`: the
/// first corner nothing drawn reaches; else the top corner that needs the least room made
/// above the data within its width, where that is at most [`MOST_GROWTH`]; else beside the
/// plot, where it takes at most [`MOST_BESIDE`] of its width; else the corner that covers
/// least (a dot or a bar counting as much as a whole line: covering data hides more than
/// covering a model).
pub(super) fn place(p: &Panel, (x, y): (&Axis, &Axis), (pw, ph): (f64, f64), b: LegendBox) -> Placement {
    let drawn = drawn(p, (x, y), (pw, ph));
    let boxed = |c: Corner| boxed(c, b, (pw, ph));
    let inside = |c: Corner, q: &Mark| q.inside(boxed(c));
    if let Some(corner) = CORNERS.into_iter().find(|&c| !drawn.iter().any(|q| inside(c, q))) {
        return Placement {
            spot: Spot::Corner(corner),
            y: y.clone(),
        };
    }
    // The growth of the axis that brings everything under the box below its bottom edge.
    let growth = |c: Corner| {
        let (x0, x1, _, y1) = boxed(c);
        let highest = drawn
            .iter()
            .filter(|q| (x0..=x1).contains(&q.x))
            .map(|q| ph - q.y)
            .fold(0.0, f64::max);
        // Two pixels more: the box's edge is inside it, and positions are rounded.
        (highest + 2.0) / (ph - y1).max(1.0)
    };
    let top = CORNERS[..2]
        .iter()
        .map(|&c| (c, growth(c)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((corner, g)) = top.filter(|(_, g)| *g <= MOST_GROWTH) {
        return Placement {
            spot: Spot::Corner(corner),
            y: y.with_room_above(1.0 - 1.0 / g.max(1.0)),
        };
    }
    if b.w + BESIDE_GAP <= MOST_BESIDE * pw {
        return Placement {
            spot: Spot::Beside,
            y: y.clone(),
        };
    }
    let cover = |c: Corner| drawn.iter().filter(|q| inside(c, q)).map(|q| q.weight).sum::<f64>();
    let corner = CORNERS
        .into_iter()
        .min_by(|&a, &b| cover(a).total_cmp(&cover(b)))
        .unwrap_or(CORNERS[0]);
    Placement {
        spot: Spot::Corner(corner),
        y: y.clone(),
    }
}

/// The box at corner `c`, with plotters' inset and a clearance: `x0, x1, y0, y1`, pixels, y
/// down.
fn boxed(c: Corner, b: LegendBox, (pw, ph): (f64, f64)) -> (f64, f64, f64, f64) {
    let (w, h) = (INSET + b.w + CLEAR, INSET + b.h + CLEAR);
    let (x0, x1) = if c.left { (0.0, w) } else { (pw - w, pw) };
    let (y0, y1) = if c.top { (0.0, h) } else { (ph - h, ph) };
    (x0, x1, y0, y1)
}

/// A place where something is drawn, pixels (y down), and how much covering it hides.
struct Mark {
    x: f64,
    y: f64,
    weight: f64,
}

impl Mark {
    /// Whether it lies within `x0, x1, y0, y1` ([`boxed`]).
    fn inside(&self, (x0, x1, y0, y1): (f64, f64, f64, f64)) -> bool {
        (x0..=x1).contains(&self.x) && (y0..=y1).contains(&self.y)
    }
}

/// Every place something of `p` is drawn: its dots, and points along its lines and bars no
/// more than 2 px apart; each dot, each bar and each whole line weighs 1.
fn drawn(p: &Panel, (x, y): (&Axis, &Axis), (pw, ph): (f64, f64)) -> Vec<Mark> {
    let px = |(a, c): &(f64, f64)| (f64::from(x.map(a, (0, pw as i32))), f64::from(y.map(c, (ph as i32, 0))));
    let good = |&(a, c): &(f64, f64)| x.shows(a) && y.shows(c);
    let weighed = |places: Vec<(f64, f64)>| {
        let weight = 1.0 / places.len().max(1) as f64;
        places.into_iter().map(move |(x, y)| Mark { x, y, weight })
    };
    let mut out = Vec::new();
    for s in &p.series {
        match s.style {
            Style::Points => out.extend(s.points.iter().filter(|q| good(q)).flat_map(|q| weighed(vec![px(q)]))),
            Style::Line => {
                let mut places = Vec::new();
                for run in s.points.split(|q| !good(q)) {
                    places.extend(run.iter().map(px));
                    for seg in run.windows(2) {
                        places.extend(segment(px(&seg[0]), px(&seg[1])));
                    }
                }
                out.extend(weighed(places));
            }
            Style::Bars | Style::Spread => {
                for bar in s.points.chunks_exact(2).filter(|bar| good(&bar[0]) && good(&bar[1])) {
                    out.extend(weighed(segment(px(&bar[0]), px(&bar[1])).collect()));
                }
            }
        }
    }
    out
}

/// Points along a segment no more than 2 px apart, both ends included.
fn segment(a: (f64, f64), b: (f64, f64)) -> impl Iterator<Item = (f64, f64)> {
    let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 2.0)
        .ceil()
        .clamp(1.0, 4096.0) as usize;
    (0..=steps).map(move |i| {
        let t = i as f64 / steps as f64;
        (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
    })
}

/// Whether anything drawn of `p` comes within the box at `corner`.
#[cfg(test)]
fn reaches(p: &Panel, (x, y): (&Axis, &Axis), (pw, ph): (f64, f64), b: LegendBox, c: Corner) -> bool {
    drawn(p, (x, y), (pw, ph))
        .iter()
        .any(|q| q.inside(boxed(c, b, (pw, ph))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::Series;

    fn panel(series: Vec<Series>) -> Panel {
        Panel {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            series,
            log_x: false,
            log_y: false,
        }
    }

    fn series(points: Vec<(f64, f64)>, style: Style) -> Series {
        Series {
            name: "s".into(),
            points,
            style,
        }
    }

    const PLOT: (f64, f64) = (600.0, 200.0);
    const BOX: LegendBox = LegendBox { w: 120.0, h: 40.0 };

    fn placed(p: &Panel) -> Placement {
        let x = Axis::fit(p.series.iter().flat_map(|s| s.points.iter().map(|q| q.0)), p.log_x, 0.0);
        let y = Axis::fit(
            p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1)),
            p.log_y,
            0.05,
        );
        let at = place(p, (&x, &y), PLOT, BOX);
        // Wherever it went, nothing drawn is under it.
        if let Spot::Corner(c) = at.spot {
            assert!(!reaches(p, (&x, &at.y), PLOT, BOX, c), "{c:?}");
        }
        at
    }

    #[test]
    fn the_legend_takes_the_first_free_corner() {
        // A falling line leaves the upper right and lower left free.
        let falling = panel(vec![series(vec![(0.0, 10.0), (10.0, 0.0)], Style::Line)]);
        assert_eq!(placed(&falling).spot, Spot::Corner(CORNERS[1]));
        // A rising one the upper left.
        let rising = panel(vec![series(vec![(0.0, 0.0), (10.0, 10.0)], Style::Line)]);
        assert_eq!(placed(&rising).spot, Spot::Corner(CORNERS[0]));
        assert_eq!(placed(&rising).y.range(), placed(&falling).y.range(), "no room made");
    }

    #[test]
    fn a_line_crossing_a_corner_between_its_points_reaches_it() {
        // Points outside the upper left corner whose segment cuts it.
        let p = panel(vec![
            series(vec![(-1.0, 18.0), (10.0, 25.0), (40.0, 25.0)], Style::Line),
            series(vec![(0.0, 0.0), (40.0, 0.0), (40.0, 10.0)], Style::Points),
        ]);
        let x = Axis::fit([-1.0, 40.0], false, 0.0);
        let y = Axis::fit([0.0, 25.0], false, 0.05);
        assert!(reaches(&p, (&x, &y), PLOT, BOX, CORNERS[0]));
        // The same points as dots leave it free.
        let mut dots = p.clone();
        dots.series[0].style = Style::Points;
        assert!(!reaches(&dots, (&x, &y), PLOT, BOX, CORNERS[0]));
    }

    #[test]
    fn data_in_every_corner_make_room_above_them() {
        // Dots in all four corners and a bar in the middle.
        let corners = vec![(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)];
        let p = panel(vec![
            series(corners, Style::Points),
            series(vec![(0.5, 0.2), (0.5, 0.8)], Style::Bars),
        ]);
        let at = placed(&p);
        assert_eq!(at.spot, Spot::Corner(CORNERS[0]));
        let y = Axis::fit([0.0, 1.0], false, 0.05);
        assert!(at.y.range().end > y.range().end, "{:?} {:?}", at.y, y);
        assert_eq!(at.y.range().start, y.range().start);
        // On a log axis too: decades above.
        let mut log = p.clone();
        log.series[0].points = vec![(0.0, 1.0), (0.0, 100.0), (1.0, 1.0), (1.0, 100.0)];
        log.series[1].points.clear();
        log.log_y = true;
        let at = placed(&log);
        assert!(at.y.range().end > 100.0 * 1.2, "{:?}", at.y);
    }

    #[test]
    fn the_room_made_is_what_the_data_under_the_box_need() {
        // The left side reaches 0.8 and the right 1.0: room for the 0.8 under the left box.
        let p = panel(vec![series(
            vec![(0.0, 0.0), (0.0, 0.8), (1.0, 0.0), (1.0, 1.0)],
            Style::Points,
        )]);
        let at = placed(&p);
        assert_eq!(at.spot, Spot::Corner(CORNERS[0]));
        let right = {
            let mut q = p.clone();
            q.series[0].points = vec![(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)];
            placed(&q).y.range().end
        };
        assert!(at.y.range().end < right, "{:?} against {right}", at.y);
    }

    #[test]
    fn a_legend_too_tall_for_its_room_goes_beside_the_plot_or_where_it_covers_least() {
        // A box of two thirds of the plot: making room would squeeze the data to a third.
        // The dots sit in the upper corners and the lower left; a line's end alone in the
        // lower right.
        let p = panel(vec![
            series(vec![(0.0, 0.0), (0.0, 1.0), (1.0, 1.0)], Style::Points),
            series(vec![(0.5, 0.5), (1.0, 0.0)], Style::Line),
        ]);
        let x = Axis::fit([0.0, 1.0], false, 0.0);
        let y = Axis::fit([0.0, 1.0], false, 0.05);
        let tall = LegendBox { w: 120.0, h: 130.0 };
        let at = place(&p, (&x, &y), PLOT, tall);
        assert_eq!(at.spot, Spot::Beside);
        assert_eq!(at.y.range(), y.range(), "no room made");
        // Too wide to go beside (it would take more than 0.4 of the plot's width).
        let wide = LegendBox { w: 240.0, h: 130.0 };
        let at = place(&p, (&x, &y), PLOT, wide);
        assert_eq!(at.spot, Spot::Corner(CORNERS[3]));
        assert_eq!(at.y.range(), y.range(), "no room made");
    }
}
