//! A legend drawn beside the plot, on its right, where inside it would hide data
//! ([`super::legend::Spot::Beside`]): the box, marker and text as plotters draws its own
//! legend inside the plot.

use super::Style;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One entry: the series' name, how it is drawn and its colour.
pub(super) struct Entry {
    pub name: String,
    pub style: Style,
    pub colour: RGBColor,
}

/// The entries in a box of `w` by `h` pixels with its top left at `(x, y)` of `area`, the
/// text `size` px in `font`: a 30 px marker column and 10 px margins, a row per entry 1.25 of
/// the text's height (what `legend_style` reckons).
pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    (font, size): (&str, f64),
    (x, y): (i32, i32),
    (w, h): (i32, i32),
    border: RGBColor,
) -> Result<(), String> {
    let failed = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("cannot draw the plot: {e}");
    area.draw(&Rectangle::new([(x, y), (x + w, y + h)], WHITE.filled()))
        .map_err(failed)?;
    area.draw(&Rectangle::new([(x, y), (x + w, y + h)], border))
        .map_err(failed)?;
    let text = TextStyle::from((font, size).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    let row = size * 1.25;
    for (i, e) in entries.iter().enumerate() {
        let cy = y + 10 + (row * (i as f64 + 0.5)).round() as i32;
        match e.style {
            Style::Points => area.draw(&Circle::new((x + 18, cy), 3, e.colour.filled())),
            _ => area.draw(&PathElement::new(
                [(x + 10, cy), (x + 26, cy)],
                e.colour.stroke_width(2),
            )),
        }
        .map_err(failed)?;
        area.draw_text(&e.name, &text, (x + 40, cy)).map_err(failed)?;
    }
    Ok(())
}
