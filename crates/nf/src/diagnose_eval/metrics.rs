//! What the suite counts of each diagnosis, against the truth the twin was given.

use super::Outcome;
use crate::diagnose::Kind;
use nf_model::angle::wrap_180;
use std::collections::BTreeMap;

/// What one recording really has.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// The catalogue effects concealed in it; empty for a clean recording.
    pub effects: Vec<Kind>,
    /// The twin's azimuth psi, deg.
    pub psi_deg: f64,
}

/// Counts over the recordings of a row, or of a whole category.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tally {
    /// Recordings diagnosed.
    pub runs: u32,
    /// Recordings the diagnosis gave no outcome for (not in `runs`).
    pub refused: u32,
    /// Diagnosed recordings with a concealed effect.
    pub with_effect: u32,
    /// Of those, the ones whose first named effect is a concealed one.
    pub named_first: u32,
    /// Effects concealed, over all recordings (two per two-effect recording).
    pub concealed: u32,
    /// Of those, the ones named anywhere.
    pub recalled: u32,
    /// Diagnosed clean recordings.
    pub clean: u32,
    /// Of those, the ones with any effect named (noise terms are not false alarms).
    pub false_alarms: u32,
    /// Sums of the squared azimuth errors, arcsec^2, of the baseline and the final azimuth.
    pub sq_err_baseline: f64,
    pub sq_err_final: f64,
    /// Sum of the squared final errors over their reported sigmas.
    pub sq_z_final: f64,
    /// Final azimuths worse than the baseline's by more than 3 baseline sigma.
    pub worse_than_baseline: u32,
    /// Final azimuths off by more than 3 of their own reported sigma.
    pub beyond_3_sigma: u32,
    /// How often each noise term was named.
    pub noise_named: BTreeMap<Kind, u32>,
    /// How often each effect was named on a clean recording.
    pub false_named: BTreeMap<Kind, u32>,
}

/// What one diagnosis got wrong, as the suite counts it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Missed {
    /// An effect named on a clean recording.
    pub false_alarm: bool,
    /// The final azimuth worse than the baseline's by more than 3 baseline sigma.
    pub worse: bool,
    /// The final azimuth off by more than 3 of its own reported sigma.
    pub beyond: bool,
}

impl Missed {
    pub fn of(truth: &Truth, o: &Outcome) -> Missed {
        let before = error_arcsec(o.baseline_deg, truth.psi_deg);
        let after = error_arcsec(o.final_deg, truth.psi_deg);
        Missed {
            false_alarm: truth.effects.is_empty() && !o.effects.is_empty(),
            worse: after.abs() - before.abs() > 3.0 * o.baseline_sigma_arcsec,
            beyond: after.abs() > 3.0 * o.final_sigma_arcsec,
        }
    }

    pub fn any(&self) -> bool {
        self.false_alarm || self.worse || self.beyond
    }

    /// The misses in words, `, `-separated.
    pub fn describe(&self) -> String {
        [
            (self.false_alarm, "false alarm"),
            (self.worse, "worse than the baseline by 3 sigma"),
            (self.beyond, "beyond 3 reported sigma"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, text)| *text)
        .collect::<Vec<_>>()
        .join(", ")
    }
}

/// Azimuth error, arcsec, wrapped to +-180 deg.
pub fn error_arcsec(azimuth_deg: f64, psi_deg: f64) -> f64 {
    wrap_180(azimuth_deg - psi_deg) * 3600.0
}

impl Tally {
    /// Counts one recording; `None` is a recording the diagnosis refused.
    pub fn add(&mut self, truth: &Truth, outcome: Option<&Outcome>) {
        let Some(o) = outcome else {
            self.refused += 1;
            return;
        };
        self.runs += 1;
        let missed = Missed::of(truth, o);
        if truth.effects.is_empty() {
            self.clean += 1;
            self.false_alarms += u32::from(missed.false_alarm);
            count(&mut self.false_named, &o.effects);
        } else {
            self.with_effect += 1;
            self.named_first += u32::from(o.effects.first().is_some_and(|e| truth.effects.contains(e)));
            self.concealed += truth.effects.len() as u32;
            self.recalled += truth.effects.iter().filter(|e| o.effects.contains(e)).count() as u32;
        }
        let before = error_arcsec(o.baseline_deg, truth.psi_deg);
        let after = error_arcsec(o.final_deg, truth.psi_deg);
        self.sq_err_baseline += before * before;
        self.sq_err_final += after * after;
        self.sq_z_final += (after / o.final_sigma_arcsec).powi(2);
        self.worse_than_baseline += u32::from(missed.worse);
        self.beyond_3_sigma += u32::from(missed.beyond);
        count(&mut self.noise_named, &o.noise_terms);
    }

    /// Adds another tally's counts (a category's total from its rows).
    pub fn merge(&mut self, other: &Tally) {
        self.runs += other.runs;
        self.refused += other.refused;
        self.with_effect += other.with_effect;
        self.named_first += other.named_first;
        self.concealed += other.concealed;
        self.recalled += other.recalled;
        self.clean += other.clean;
        self.false_alarms += other.false_alarms;
        self.sq_err_baseline += other.sq_err_baseline;
        self.sq_err_final += other.sq_err_final;
        self.sq_z_final += other.sq_z_final;
        self.worse_than_baseline += other.worse_than_baseline;
        self.beyond_3_sigma += other.beyond_3_sigma;
        for (mine, theirs) in [
            (&mut self.noise_named, &other.noise_named),
            (&mut self.false_named, &other.false_named),
        ] {
            for (name, k) in theirs {
                *mine.entry(*name).or_default() += k;
            }
        }
    }

    /// Share of the recordings with an effect whose first named effect is concealed in them.
    pub fn named_first_rate(&self) -> Option<f64> {
        ratio(self.named_first, self.with_effect)
    }

    /// Share of the concealed effects that were named.
    pub fn recall(&self) -> Option<f64> {
        ratio(self.recalled, self.concealed)
    }

    /// Share of the clean recordings with an effect named.
    pub fn false_alarm_rate(&self) -> Option<f64> {
        ratio(self.false_alarms, self.clean)
    }

    /// RMS azimuth error of the baseline, arcsec.
    pub fn rms_baseline(&self) -> Option<f64> {
        (self.runs > 0).then(|| (self.sq_err_baseline / self.runs as f64).sqrt())
    }

    pub fn rms_final(&self) -> Option<f64> {
        (self.runs > 0).then(|| (self.sq_err_final / self.runs as f64).sqrt())
    }

    /// RMS of the final errors over their reported sigmas: 1 where the sigmas hold.
    pub fn rms_z_final(&self) -> Option<f64> {
        (self.runs > 0).then(|| (self.sq_z_final / self.runs as f64).sqrt())
    }
}

fn count(counts: &mut BTreeMap<Kind, u32>, names: &[Kind]) {
    for name in names {
        *counts.entry(*name).or_default() += 1;
    }
}

/// `k / n`, or `None` when there is nothing to count (a rate that does not apply).
fn ratio(k: u32, n: u32) -> Option<f64> {
    (n > 0).then(|| k as f64 / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(effects: &[Kind], baseline: (f64, f64), last: (f64, f64)) -> Outcome {
        // Errors in arcsec against psi = 10 deg, with their sigmas.
        Outcome {
            effects: effects.to_vec(),
            noise_terms: vec![Kind::BiasInstability],
            baseline_deg: 10.0 + baseline.0 / 3600.0,
            baseline_sigma_arcsec: baseline.1,
            final_deg: 10.0 + last.0 / 3600.0,
            final_sigma_arcsec: last.1,
        }
    }

    fn truth(effects: &[Kind]) -> Truth {
        Truth {
            effects: effects.to_vec(),
            psi_deg: 10.0,
        }
    }

    #[test]
    fn worse_than_baseline_and_beyond_3_sigma_count_by_their_definitions() {
        let mut t = Tally::default();
        // 50 - 30 = 20 > 3 * 5: worse; 50 > 3 * 5: beyond.
        t.add(&truth(&[]), Some(&outcome(&[], (30.0, 5.0), (50.0, 5.0))));
        // 40 - 30 = 10 < 15: not worse; 40 < 3 * 20: not beyond.
        t.add(&truth(&[]), Some(&outcome(&[], (30.0, 5.0), (-40.0, 20.0))));
        // The sign does not matter: |-30| - |10| = 20 > 3 * 6; 30 < 3 * 11 is within.
        t.add(&truth(&[]), Some(&outcome(&[], (10.0, 6.0), (-30.0, 11.0))));
        assert_eq!(t.worse_than_baseline, 2);
        assert_eq!(t.beyond_3_sigma, 1);
        assert_eq!(t.runs, 3);
        let rms_base = ((900.0 + 900.0 + 100.0) / 3.0f64).sqrt();
        assert!((t.rms_baseline().unwrap() - rms_base).abs() < 1e-6);
        let rms_final = ((2500.0 + 1600.0 + 900.0) / 3.0f64).sqrt();
        assert!((t.rms_final().unwrap() - rms_final).abs() < 1e-6);
        // z = 10, -2 and -30 / 11.
        let rms_z = ((100.0 + 4.0 + (30.0f64 / 11.0).powi(2)) / 3.0).sqrt();
        assert!((t.rms_z_final().unwrap() - rms_z).abs() < 1e-9);
        let mut twice = Tally::default();
        twice.merge(&t);
        twice.merge(&t);
        assert!((twice.rms_z_final().unwrap() - rms_z).abs() < 1e-9);
    }

    #[test]
    fn errors_wrap_across_north() {
        assert!((error_arcsec(0.01, 359.99) - 72.0).abs() < 1e-6);
        let mut t = Tally::default();
        let truth = Truth {
            effects: Vec::new(),
            psi_deg: 359.99,
        };
        let mut o = outcome(&[], (0.0, 1.0), (0.0, 1.0));
        (o.baseline_deg, o.final_deg) = (359.99, 0.01);
        t.add(&truth, Some(&o));
        // 72" against a 1" baseline sigma: worse and beyond.
        assert_eq!((t.worse_than_baseline, t.beyond_3_sigma), (1, 1));
    }

    #[test]
    fn named_first_recall_and_false_alarms() {
        let mut t = Tally::default();
        let pair = truth(&[Kind::BiasDrift, Kind::Outliers]);
        // Both named, the second concealed one first.
        t.add(
            &pair,
            Some(&outcome(&[Kind::Outliers, Kind::BiasDrift], (0.0, 1.0), (0.0, 1.0))),
        );
        // One of two named, after a wrong one.
        t.add(
            &pair,
            Some(&outcome(&[Kind::ScaleFactor, Kind::BiasDrift], (0.0, 1.0), (0.0, 1.0))),
        );
        // Clean: a noise term alone is no false alarm, an effect is.
        t.add(&truth(&[]), Some(&outcome(&[], (0.0, 1.0), (0.0, 1.0))));
        t.add(&truth(&[]), Some(&outcome(&[Kind::BiasJump], (0.0, 1.0), (0.0, 1.0))));
        t.add(&truth(&[]), None);
        assert_eq!((t.with_effect, t.named_first), (2, 1));
        assert_eq!((t.concealed, t.recalled), (4, 3));
        assert_eq!((t.clean, t.false_alarms, t.refused, t.runs), (2, 1, 1, 4));
        assert_eq!(t.recall(), Some(0.75));
        assert_eq!(t.false_alarm_rate(), Some(0.5));
        assert_eq!(t.noise_named[&Kind::BiasInstability], 4);
        assert_eq!(t.false_named.iter().collect::<Vec<_>>(), [(&Kind::BiasJump, &1)]);
        let mut total = Tally::default();
        total.merge(&t);
        total.merge(&t);
        assert_eq!(
            (total.runs, total.recalled, total.noise_named[&Kind::BiasInstability]),
            (8, 6, 8)
        );
        assert_eq!(Tally::default().named_first_rate(), None);
    }
}
