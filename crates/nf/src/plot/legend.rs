//! Where a panel's legend goes: the first corner of the plot that no point, bar or line
//! reaches, or, where every corner holds some, above the data in room made for it at the
//! top of the y axis. A legend never hides what is drawn.

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

/// Where the legend goes and the y axis that leaves it room.
#[derive(Debug, Clone)]
pub(super) struct Placement {
    pub corner: Corner,
    pub y: Axis,
}

/// Plotters' gap between the box and the plot's edge, px.
const INSET: f64 = 5.0;
/// Clearance around the box: a dot's radius and a little, px.
const CLEAR: f64 = 4.0;
/// The y axis gives a legend at most this share of its height.
pub(super) const MOST_ROOM: f64 = 0.6;

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

/// Where the legend `b` goes in a plot of `pw` by `ph` pixels over the axes `x` and `y`.
pub(super) fn place(p: &Panel, (x, y): (&Axis, &Axis), (pw, ph): (f64, f64), b: LegendBox) -> Placement {
    match CORNERS.into_iter().find(|&c| !reaches(p, (x, y), (pw, ph), b, c)) {
        Some(corner) => Placement { corner, y: y.clone() },
        None => Placement {
            corner: CORNERS[0],
            y: y.with_room_above(((INSET + b.h + CLEAR) / ph.max(1.0)).min(MOST_ROOM)),
        },
    }
}

/// Whether anything drawn of `p` comes within the box at `corner`.
fn reaches(p: &Panel, (x, y): (&Axis, &Axis), (pw, ph): (f64, f64), b: LegendBox, c: Corner) -> bool {
    let (w, h) = (INSET + b.w + CLEAR, INSET + b.h + CLEAR);
    let (x0, x1) = if c.left { (0.0, w) } else { (pw - w, pw) };
    let (y0, y1) = if c.top { (0.0, h) } else { (ph - h, ph) };
    let inside = |(a, c): (f64, f64)| (x0..=x1).contains(&a) && (y0..=y1).contains(&c);
    // Pixels, y down, as plotters maps them.
    let px = |(a, c): &(f64, f64)| (f64::from(x.map(a, (0, pw as i32))), f64::from(y.map(c, (ph as i32, 0))));
    let good = |&(a, c): &(f64, f64)| x.shows(a) && y.shows(c);
    p.series.iter().any(|s| match s.style {
        Style::Points => s.points.iter().filter(|q| good(q)).map(px).any(inside),
        Style::Line => s.points.split(|q| !good(q)).any(|run| {
            run.windows(2).any(|seg| segment(px(&seg[0]), px(&seg[1])).any(inside)) || run.iter().map(px).any(inside)
        }),
        Style::Bars | Style::Spread => s
            .points
            .chunks_exact(2)
            .filter(|bar| good(&bar[0]) && good(&bar[1]))
            .any(|bar| segment(px(&bar[0]), px(&bar[1])).any(inside)),
    })
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
        assert!(!reaches(p, (&x, &at.y), PLOT, BOX, at.corner), "{:?}", at.corner);
        at
    }

    #[test]
    fn the_legend_takes_the_first_free_corner() {
        // A falling line leaves the upper right and lower left free.
        let falling = panel(vec![series(vec![(0.0, 10.0), (10.0, 0.0)], Style::Line)]);
        assert_eq!(placed(&falling).corner, CORNERS[1]);
        // A rising one the upper left.
        let rising = panel(vec![series(vec![(0.0, 0.0), (10.0, 10.0)], Style::Line)]);
        assert_eq!(placed(&rising).corner, CORNERS[0]);
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
        assert_eq!(at.corner, CORNERS[0]);
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
}
