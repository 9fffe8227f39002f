//! Each dwell's length. A writer gives one for the run (`dwell_s`) or none; where every row
//! has `samples` and they differ, the rows' dwells differ with them: a dwell of sixteen times
//! the samples has a sixteenth of the white variance, and a fit that weighed it as the others
//! lost half its precision on a run of alternating short and long dwells (an outside audit).

use crate::recording::Recording;

/// Where [`of`] found the nominal dwell when the metadata gave it.
pub const FROM_METADATA: &str = "metadata dwell_s";

/// Sample counts within this share of the typical one are taken as the typical dwell: a few
/// dropped samples change a dwell mean's variance by less than any fit can tell.
const SAME_WITHIN: f64 = 0.01;

#[derive(Debug, Clone, PartialEq)]
pub struct Dwells {
    /// Each row's dwell, s, in the recording's order.
    pub each_s: Vec<f64>,
    /// The typical dwell (the median row's), s: the units of the noise search and the text.
    pub nominal_s: f64,
    /// Where the nominal dwell came from.
    pub from: &'static str,
    /// The median row's sample count, where every row has one.
    typical_samples: Option<u32>,
}

impl Dwells {
    /// Whether the rows' samples make their dwells differ.
    pub fn differ(&self) -> bool {
        self.each_s.iter().any(|d| *d != self.nominal_s)
    }

    /// The dwell of a row of `samples` samples.
    fn of_samples(&self, samples: u32) -> f64 {
        match self.typical_samples {
            Some(typical) => {
                let ratio = f64::from(samples) / f64::from(typical);
                if (ratio - 1.0).abs() <= SAME_WITHIN {
                    self.nominal_s
                } else {
                    self.nominal_s * ratio
                }
            }
            None => self.nominal_s,
        }
    }

    /// The shortest and longest dwell, where they differ.
    pub fn range_s(&self) -> Option<(f64, f64)> {
        let lo = self.each_s.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self.each_s.iter().copied().fold(0.0, f64::max);
        self.differ().then_some((lo, hi))
    }
}

/// The dwells of `rec`: the nominal one from the metadata, else the typical row's samples over
/// the sample rate, else 80 % of the shortest spacing of the dwell centres; each row's scaled
/// by its samples against the typical row's, where every row has them.
pub fn of(rec: &Recording) -> Dwells {
    let meta = |k: &str| rec.meta.get(k).and_then(|v| v.parse::<f64>().ok()).filter(|v| *v > 0.0);
    let mut counts: Vec<u32> = rec.rows.iter().filter_map(|r| r.samples).filter(|s| *s > 0).collect();
    counts.sort_unstable();
    let typical = counts.get(counts.len() / 2).copied();
    let every_row = counts.len() == rec.rows.len();
    let (nominal_s, from) = if let Some(d) = meta("dwell_s") {
        (d, FROM_METADATA)
    } else if let (Some(rate), Some(s)) = (meta("sample_rate_hz"), typical) {
        (f64::from(s) / rate, "samples / sample_rate_hz")
    } else {
        by_spacing(rec)
    };
    let mut d = Dwells {
        each_s: Vec::new(),
        nominal_s,
        from,
        typical_samples: typical.filter(|_| every_row),
    };
    d.each_s = rec
        .rows
        .iter()
        .map(|r| r.samples.map_or(nominal_s, |s| d.of_samples(s)))
        .collect();
    d
}

fn by_spacing(rec: &Recording) -> (f64, &'static str) {
    let mut t: Vec<f64> = rec.rows.iter().map(|r| r.t_s).collect();
    t.sort_by(f64::total_cmp);
    let gap = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .fold(f64::MAX, f64::min);
    if gap < f64::MAX {
        (0.8 * gap, "80 % of the shortest spacing (no dwell_s metadata)")
    } else {
        (1.0, "assumed 1 s (no dwell_s metadata, no time spacing)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(meta: &str, samples: &[u32]) -> Recording {
        let mut text = format!("# format = northfinder-recording/1\n# latitude_deg = 45\n{meta}");
        text += "index,t_s,encoder_deg,rate_dph,samples\n";
        for (i, s) in samples.iter().enumerate() {
            text += &format!("{i},{},{},1.0,{s}\n", 10.0 * i as f64, 90 * (i % 4));
        }
        Recording::parse(&text).unwrap()
    }

    #[test]
    fn equal_samples_give_every_row_the_nominal_dwell() {
        let d = of(&rec("# dwell_s = 2\n", &[400, 400, 399, 400, 401]));
        assert_eq!((d.nominal_s, d.from, d.differ()), (2.0, FROM_METADATA, false));
        assert_eq!((d.range_s(), d.each_s), (None, vec![2.0; 5]));
    }

    #[test]
    fn differing_samples_scale_each_dwell() {
        let d = of(&rec("# sample_rate_hz = 200\n", &[100, 1600, 100, 1600, 1600]));
        assert_eq!((d.nominal_s, d.from), (8.0, "samples / sample_rate_hz"));
        assert_eq!(d.each_s, vec![0.5, 8.0, 0.5, 8.0, 8.0]);
        assert_eq!(d.of_samples(400), 2.0);
        let d = of(&rec("# dwell_s = 4\n", &[100, 200, 200, 200]));
        assert_eq!(d.each_s, vec![2.0, 4.0, 4.0, 4.0]);
        assert_eq!(d.range_s(), Some((2.0, 4.0)));
    }

    #[test]
    fn a_row_without_samples_leaves_every_dwell_nominal() {
        let mut r = rec("# dwell_s = 1\n", &[100, 1600, 100]);
        r.rows[1].samples = None;
        assert_eq!(of(&r).each_s, vec![1.0; 3]);
        r.meta.clear();
        let d = of(&r);
        assert_eq!((d.nominal_s, d.each_s.len()), (8.0, 3), "{}", d.from);
    }
}
