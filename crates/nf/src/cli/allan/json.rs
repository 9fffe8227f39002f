//! The JSON of `nf allan --json`, also read back as a noise file (`noise_file::read`).
//!
//! The fields of each struct are in alphabetical order, the order the keys have always had.

use super::Report;
use crate::allan::CI_LEVEL;
use crate::allan_fit::{ALPHA, FTest, Param, Term};
use crate::allan_model::floor;
use serde::Serialize;

/// The whole output: the input, the curve, the fit and each fitted term with its 68 %
/// interval, `_lo` to value plus `_sigma` (a variance estimated from few degrees of freedom:
/// the interval is a chi-square's, wider above). A term the fit dropped has value 0 and a null
/// sigma; the Gauss-Markov keys are there only when the fit kept that term.
#[derive(Serialize)]
pub(super) struct AllanJson<'a> {
    /// N with a kept Gauss-Markov term's tail, deg/sqrt(h): the white level of means much
    /// longer than its time; only with the term.
    #[serde(skip_serializing_if = "Option::is_none")]
    arw_beyond_gm_deg_rth: Option<f64>,
    /// Angle random walk N, deg/sqrt(h).
    arw_deg_rth: f64,
    /// Lower end of N's interval, deg/sqrt(h); null when the term was dropped.
    arw_deg_rth_lo: Option<f64>,
    /// Upper side of N's interval (its 1-sigma uncertainty), deg/sqrt(h); null when dropped.
    arw_deg_rth_sigma: Option<f64>,
    /// Bias instability B, deg/h.
    bias_instability_dph: f64,
    /// Lower end of B's interval, deg/h; null when the term was dropped.
    bias_instability_dph_lo: Option<f64>,
    /// Upper side of B's interval (its 1-sigma uncertainty), deg/h; null when dropped.
    bias_instability_dph_sigma: Option<f64>,
    /// B's Allan variance coefficient over its standard deviation: B is significant from
    /// about 2 on. (Its sigma maps the coefficient's up through the square root, so a small B
    /// can stand several sigmas from zero while its coefficient is within noise of zero.)
    bias_instability_z: Option<f64>,
    /// Probability content of each point's interval (0.683: one sigma).
    ci_level: f64,
    /// The overlapping Allan deviation, one entry per averaging time.
    curve: Vec<CurvePoint>,
    /// Chi-square of the generalised least-squares fit (dimensionless).
    fit_chi2: f64,
    /// Chi-square per degree of freedom (dimensionless).
    fit_chi2_per_dof: f64,
    /// Degrees of freedom of the fit.
    fit_dof: usize,
    /// Relative error each point was also given for what the terms do not describe (0 when
    /// they describe the curve within its scatter).
    fit_model_error: f64,
    /// The floor of the curve, measured and fitted.
    floor: Floor,
    /// Gauss-Markov bias standard deviation, deg/h; only when the fit kept the term.
    #[serde(skip_serializing_if = "Option::is_none")]
    gm_sigma_dph: Option<f64>,
    /// Lower end of the Gauss-Markov standard deviation's interval, deg/h; only with it.
    #[serde(skip_serializing_if = "Option::is_none")]
    gm_sigma_dph_lo: Option<f64>,
    /// Upper side of the Gauss-Markov standard deviation's interval, deg/h; only with it.
    #[serde(skip_serializing_if = "Option::is_none")]
    gm_sigma_dph_sigma: Option<f64>,
    /// Gauss-Markov correlation time, s; only when the fit kept the term.
    #[serde(skip_serializing_if = "Option::is_none")]
    gm_tau_s: Option<f64>,
    /// Quantisation Q, arcsec.
    quantization_arcsec: f64,
    /// Lower end of Q's interval, arcsec; null when the term was dropped.
    quantization_arcsec_lo: Option<f64>,
    /// Upper side of Q's interval (its 1-sigma uncertainty), arcsec; null when dropped.
    quantization_arcsec_sigma: Option<f64>,
    /// Rate ramp R, deg/h per hour: a trend, not noise (it is no term of the noise model
    /// handed on); 0 when the F test drops it.
    rate_ramp_dph_per_h: f64,
    /// Lower end of R's interval, deg/h per hour; null when the term was dropped.
    rate_ramp_dph_per_h_lo: Option<f64>,
    /// Upper side of R's interval (its 1-sigma uncertainty), deg/h per hour; null when dropped.
    rate_ramp_dph_per_h_sigma: Option<f64>,
    /// Rate random walk K, deg/h/sqrt(h).
    rrw_dph_rth: f64,
    /// Lower end of K's interval, deg/h/sqrt(h); null when the term was dropped.
    rrw_dph_rth_lo: Option<f64>,
    /// Upper side of K's interval (its 1-sigma uncertainty), deg/h/sqrt(h); null when dropped.
    rrw_dph_rth_sigma: Option<f64>,
    /// K's Allan variance coefficient over its standard deviation, as `bias_instability_z`.
    rrw_z: Option<f64>,
    /// What was read.
    source: Source<'a>,
    /// The tests of the optional terms.
    tests: Tests,
}

/// One averaging time of the curve.
#[derive(Serialize)]
struct CurvePoint {
    /// Overlapping Allan deviation, deg/h.
    adev_dph: f64,
    /// Non-overlapping clusters behind the point.
    clusters: usize,
    /// Equivalent degrees of freedom under the fitted model.
    edf: f64,
    /// Upper end of the interval, deg/h.
    hi_dph: f64,
    /// Lower end of the interval, deg/h.
    lo_dph: f64,
    /// Averaging time, s.
    tau_s: f64,
}

/// The lowest point of the curve, measured and fitted.
#[derive(Serialize)]
struct Floor {
    /// Deviation of the fitted curve at its floor, deg/h.
    fitted_adev_dph: f64,
    /// Averaging time of the fitted curve's floor, s.
    fitted_tau_s: f64,
    /// Lowest measured deviation, deg/h.
    measured_adev_dph: f64,
    /// Averaging time of the lowest measured deviation, s.
    measured_tau_s: f64,
}

/// The input file and how it was read.
#[derive(Serialize)]
struct Source<'a> {
    /// The path as given.
    file: &'a str,
    /// Gaps in the time column.
    gaps: Vec<Gap>,
    /// `static_log` or `recording`.
    kind: &'static str,
    /// What the reader noticed.
    notes: &'a [String],
    /// Values read (samples, or dwell means of a recording).
    samples: usize,
    /// Contiguous segments between the gaps.
    segments: usize,
    /// Time between values, s.
    step_s: f64,
    /// Averaging window of each value, s.
    window_s: f64,
}

/// A gap in the time column.
#[derive(Serialize)]
struct Gap {
    /// Time before the gap, s.
    from_s: f64,
    /// Line of the first sample after the gap (0 when not read from a file).
    line: usize,
    /// Time after the gap, s.
    to_s: f64,
}

/// The F tests that keep or drop the optional terms.
#[derive(Serialize)]
struct Tests {
    /// Significance level of each test.
    alpha: f64,
    /// The best Gauss-Markov term's test; null when there were too few points.
    gauss_markov: Option<GmTest>,
    /// Quantisation's test; null when there were too few points or the series has gaps.
    quantization: Option<Test>,
    /// The rate ramp's test; null when there were too few points.
    rate_ramp: Option<Test>,
}

/// An F test.
#[derive(Serialize)]
struct Test {
    /// The F statistic (dimensionless).
    f: f64,
    /// Its p-value.
    p_value: f64,
}

/// The F test of a Gauss-Markov term.
#[derive(Serialize)]
struct GmTest {
    /// The F statistic (dimensionless).
    f: f64,
    /// Its p-value.
    p_value: f64,
    /// The correlation time tried, s.
    tau_s: f64,
}

impl From<FTest> for Test {
    fn from(t: FTest) -> Test {
        Test {
            f: t.f,
            p_value: t.p_value,
        }
    }
}

/// A term's value (0 when dropped), and its interval's lower end and upper side (none when
/// dropped).
fn term(p: Option<Param>) -> (f64, Option<f64>, Option<f64>) {
    (p.map_or(0.0, |p| p.value), p.map(|p| p.lo), p.map(|p| p.sigma))
}

impl<'a> Report<'a> {
    pub(super) fn json(&self) -> AllanJson<'a> {
        let (src, fit) = (self.src, self.fit);
        let term = |t| term(fit.param(t));
        let z = |t| fit.param(t).map(|p| p.coef / p.coef_sd);
        let (arw, bi, rrw, q) = (
            term(Term::Arw),
            term(Term::BiasInstability),
            term(Term::Rrw),
            term(Term::Quantization),
        );
        let ramp = term(Term::Ramp);
        let gm = fit.gm();
        let ((mt, ma), (ft, fa)) = floor(self.points, &fit.model, src.sampling);
        AllanJson {
            arw_beyond_gm_deg_rth: fit.arw_beyond_gm(),
            arw_deg_rth: arw.0,
            arw_deg_rth_lo: arw.1,
            arw_deg_rth_sigma: arw.2,
            bias_instability_dph: bi.0,
            bias_instability_dph_lo: bi.1,
            bias_instability_dph_sigma: bi.2,
            bias_instability_z: z(Term::BiasInstability),
            ci_level: CI_LEVEL,
            curve: self
                .rows()
                .map(|(p, edf, (lo, hi))| CurvePoint {
                    adev_dph: p.avar.sqrt(),
                    clusters: p.clusters,
                    edf,
                    hi_dph: hi,
                    lo_dph: lo,
                    tau_s: p.tau_s,
                })
                .collect(),
            fit_chi2: fit.chi2,
            fit_chi2_per_dof: fit.chi2 / fit.dof as f64,
            fit_dof: fit.dof,
            fit_model_error: fit.model_error,
            floor: Floor {
                fitted_adev_dph: fa,
                fitted_tau_s: ft,
                measured_adev_dph: ma,
                measured_tau_s: mt,
            },
            gm_sigma_dph: gm.map(|(s, _)| s.value),
            gm_sigma_dph_lo: gm.map(|(s, _)| s.lo),
            gm_sigma_dph_sigma: gm.map(|(s, _)| s.sigma),
            gm_tau_s: gm.map(|(_, tau)| tau),
            quantization_arcsec: q.0,
            quantization_arcsec_lo: q.1,
            quantization_arcsec_sigma: q.2,
            rate_ramp_dph_per_h: ramp.0,
            rate_ramp_dph_per_h_lo: ramp.1,
            rate_ramp_dph_per_h_sigma: ramp.2,
            rrw_dph_rth: rrw.0,
            rrw_dph_rth_lo: rrw.1,
            rrw_dph_rth_sigma: rrw.2,
            rrw_z: z(Term::Rrw),
            source: self.source(),
            tests: Tests {
                alpha: ALPHA,
                gauss_markov: fit.gm_test.map(|(tau_s, t)| GmTest {
                    f: t.f,
                    p_value: t.p_value,
                    tau_s,
                }),
                quantization: fit.q_test.map(Test::from),
                rate_ramp: fit.ramp_test.map(Test::from),
            },
        }
    }

    fn source(&self) -> Source<'a> {
        let src = self.src;
        Source {
            file: self.file,
            gaps: src
                .spacing
                .gaps
                .iter()
                .map(|g| Gap {
                    from_s: g.from_s,
                    line: g.line,
                    to_s: g.to_s,
                })
                .collect(),
            kind: src.kind.name(),
            notes: &src.notes,
            samples: src.rates.len(),
            segments: src.spacing.segments.len(),
            step_s: src.sampling.step_s,
            window_s: src.sampling.window_s,
        }
    }
}
