//! Heavy-tailed samples (a ring-laser gyro's dither, say) that the simulation lacks or has
//! alone: the samples' excess kurtosis, as the spread of the dwells' sample variances shows
//! it, against the replays'. Their mean dwell is Gaussian all the same (thousands of samples),
//! so only the samples' spread tells.

use super::compare::Comparison;
use super::profile::Quantity;
use crate::instrument_file::InstrumentFile;

/// Standard errors of the kurtosis of Gaussian samples below which samples are taken for
/// Gaussian: over `n` dwells it is `2 sqrt(2 / n)` (each dwell's term is `2 (chi2_1 - 1)`).
const GAUSSIAN_WITHIN: f64 = 2.0;

/// The excess kurtosis of a Student-t of `dof` samples (0: Gaussian); `None` where it has no
/// fourth moment.
fn kurtosis_of(dof: f64) -> Option<f64> {
    if dof == 0.0 {
        Some(0.0)
    } else {
        (dof > 4.0).then(|| 6.0 / (dof - 4.0))
    }
}

/// Whether a kurtosis `k` measured over `dwells` is a Gaussian's.
fn gaussian(k: f64, dwells: usize) -> bool {
    k <= GAUSSIAN_WITHIN * 2.0 * (2.0 / dwells.max(1) as f64).sqrt()
}

/// The Student-t degrees of freedom of samples of excess kurtosis `k` (0: none).
fn dof_of(k: f64) -> f64 {
    if k <= 0.0 { 0.0 } else { 4.0 + 6.0 / k }
}

/// `file` with its samples' tails set to the recording's where `cmp` (the recording against
/// replays of `file`) finds their kurtosis apart. A heavier recording adds its excess over the
/// replays to the file's samples' kurtosis (the replays' beyond it, from a settling
/// transient or shocks within a dwell, is kept out); a lighter one scales it by the ratio of
/// the two, since the measured kurtosis of heavy-tailed samples falls short of their law's
/// (5 dof: about 4.5 of 6).
/// `dwells`: how many dwells the recording's kurtosis is measured over.
pub fn fix(file: &InstrumentFile, cmp: &Comparison, dwells: usize) -> (InstrumentFile, Option<String>) {
    let Some(l) = cmp.line(Quantity::SampleKurtosis).filter(|l| l.mismatch) else {
        return (file.clone(), None);
    };
    let (r, s) = (l.recording, l.simulated);
    let own = kurtosis_of(file.noise.student_t_dof).unwrap_or(s);
    let k = if r >= s || s <= 0.0 {
        own + r - s
    } else {
        own * r.max(0.0) / s
    };
    let dof = if gaussian(r, dwells) || gaussian(k, dwells) {
        0.0
    } else {
        dof_of(k)
    };
    let mut f = file.clone();
    f.noise.student_t_dof = dof;
    let to = if dof == 0.0 {
        "Gaussian".to_string()
    } else {
        format!("Student-t of {dof:.2} dof")
    };
    let note = format!(
        "noise: samples {to} (their excess kurtosis {:.2} against the replays' {:.2})",
        l.recording, l.simulated
    );
    (f, Some(note))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kurtosis_and_dof_are_inverse_where_the_fourth_moment_exists() {
        for dof in [4.5, 5.0, 8.0, 30.0] {
            let k = kurtosis_of(dof).unwrap();
            assert!((dof_of(k) - dof).abs() < 1e-9, "{dof}");
        }
        assert_eq!(kurtosis_of(3.0), None);
        assert_eq!(dof_of(-0.3), 0.0);
        // Within two standard errors of a Gaussian's over 72 dwells (0.33 each).
        assert!(gaussian(0.6, 72) && !gaussian(0.7, 72));
    }
}
