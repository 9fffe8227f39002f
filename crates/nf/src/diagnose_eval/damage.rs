//! Inclinometer data lost on the way to the host. The twin always writes both tilt columns,
//! so the loss is made in the recording's text, before it is read as any file would be.

use nf_twin::Rng;

/// What a row's loss of data looks like.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loss {
    Nothing,
    /// The `tilt_y_deg` column is not in the file at all.
    TiltYColumn,
    /// One to three rows have empty tilt fields (X and Y: the reading was lost).
    TiltReadings,
}

/// The edit made to one recording's text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Damage {
    Intact,
    DropColumn(&'static str),
    /// Empties the tilt fields of these rows (visit numbers).
    BlankTilts(Vec<usize>),
}

impl Loss {
    /// The edit for a run of `visits` rows.
    pub fn draw(self, rng: &mut Rng, visits: usize) -> Damage {
        match self {
            Loss::Nothing => Damage::Intact,
            Loss::TiltYColumn => Damage::DropColumn("tilt_y_deg"),
            Loss::TiltReadings => {
                let k = 1 + (rng.next_u64() % 3) as usize;
                let mut rows: Vec<usize> = Vec::new();
                while rows.len() < k.min(visits) {
                    let r = (rng.next_u64() % visits as u64) as usize;
                    if !rows.contains(&r) {
                        rows.push(r);
                    }
                }
                Damage::BlankTilts(rows)
            }
        }
    }
}

impl Damage {
    /// The text with the edit made: metadata lines stay, the header and rows lose cells.
    pub fn apply(&self, text: &str) -> String {
        if *self == Damage::Intact {
            return text.to_string();
        }
        let mut out = String::with_capacity(text.len());
        let mut header: Vec<&str> = Vec::new();
        let mut row = 0;
        for line in text.lines() {
            let edited = if line.starts_with('#') {
                line.to_string()
            } else if header.is_empty() {
                header = line.split(',').collect();
                self.edit(&header, line.split(',').collect(), None)
            } else {
                row += 1;
                self.edit(&header, line.split(',').collect(), Some(row - 1))
            };
            out.push_str(&edited);
            out.push('\n');
        }
        out
    }

    /// One line's cells after the edit; `row` is `None` for the header.
    fn edit(&self, header: &[&str], mut cells: Vec<&str>, row: Option<usize>) -> String {
        let at = |name: &str| header.iter().position(|h| *h == name);
        match self {
            Damage::Intact => {}
            Damage::DropColumn(name) => {
                if let Some(i) = at(name).filter(|&i| i < cells.len()) {
                    cells.remove(i);
                }
            }
            Damage::BlankTilts(rows) => {
                if row.is_some_and(|r| rows.contains(&r)) {
                    for i in ["tilt_x_deg", "tilt_y_deg"].iter().filter_map(|n| at(n)) {
                        if let Some(c) = cells.get_mut(i) {
                            *c = "";
                        }
                    }
                }
            }
        }
        cells.join(",")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose_eval::cases::{Site, random_case};
    use crate::recording::Recording;
    use nf_model::order::Order;

    /// A short twin recording's text (both tilt columns present).
    fn text() -> String {
        let mut rng = Rng::new(5);
        let mut case = random_case(&mut rng, &Site::ORDINARY, Order::Sequential);
        case.twin.instrument.tilt_deg = 0.3;
        (case.twin.sample_rate_hz, case.run.sample_rate_hz) = (100, 100);
        let mut rec = nf_twin::Recorder::default();
        nf_twin::simulate(&case.twin, &case.run, &mut rec);
        rec.text()
    }

    #[test]
    fn a_dropped_tilt_y_column_is_absent_and_x_stays() {
        let t = text();
        assert!(Recording::parse(&t).unwrap().has_tilt_xy());
        let rec = Recording::parse(&Loss::TiltYColumn.draw(&mut Rng::new(1), 10).apply(&t)).unwrap();
        assert!(rec.has_tilt_x());
        assert!(rec.rows.iter().all(|r| r.tilt_y_deg.is_none()));
        let header = t.lines().find(|l| !l.starts_with('#')).unwrap();
        assert!(header.contains("tilt_y_deg"));
    }

    #[test]
    fn blanked_tilt_readings_are_missing_in_exactly_those_rows() {
        let t = text();
        let mut rng = Rng::new(2);
        let mut counts = Vec::new();
        for _ in 0..12 {
            let damage = Loss::TiltReadings.draw(&mut rng, 36);
            let Damage::BlankTilts(rows) = &damage else {
                panic!("{damage:?}")
            };
            let rec = Recording::parse(&damage.apply(&t)).unwrap();
            let missing: Vec<usize> = (0..rec.rows.len())
                .filter(|&i| rec.rows[i].tilt_x_deg.is_none())
                .collect();
            let mut want = rows.clone();
            want.sort();
            assert_eq!(missing, want);
            assert!(
                rec.rows
                    .iter()
                    .all(|r| r.tilt_x_deg.is_none() == r.tilt_y_deg.is_none())
            );
            // The gyro columns are untouched.
            assert_eq!(rec.rows.len(), Recording::parse(&t).unwrap().rows.len());
            counts.push(rows.len());
        }
        assert!(counts.iter().all(|k| (1..=3).contains(k)));
        assert!((1..=3).all(|k| counts.contains(&k)), "{counts:?}");
    }
}
