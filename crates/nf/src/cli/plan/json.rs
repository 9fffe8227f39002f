//! The JSON of `nf plan --json`.
//!
//! The fields of each struct are in alphabetical order, the order the keys have always had.

use super::super::json::BudgetJson;
use crate::plan_noise::Candidate;
use crate::twin_check::TwinCheck;
use nf_model::noise::NoiseModel;
use nf_model::uncertainty::Sigmas;
use serde::Serialize;

/// The planned run's budgets, and with a target the fastest runs reaching it; the parts that
/// were not asked for (no target, no twin runs, no Monte Carlo) are null.
#[derive(Serialize)]
pub(super) struct PlanJson {
    /// Allowances of a third of the variance each for the target at the planned n; null
    /// without a target.
    pub allowance_for_target: Option<AllowanceJson>,
    /// The paper's budget (Eq. 31) of the planned run.
    pub budget_eq31_paper: BudgetJson,
    /// The exact model's budget under white noise.
    pub budget_exact: BudgetJson,
    /// The budget under the noise model (generalised least squares).
    pub budget_noise_model: NoiseBudgetJson,
    /// The exact model's budget, computed numerically.
    pub budget_numerical: BudgetJson,
    /// Dwell of the planned run, s.
    pub dwell_s: f64,
    /// The fastest run reaching the target; null without a target or when none reaches it.
    pub fastest: Option<CandidateJson>,
    /// Each order's fastest run reaching the target; null without a target.
    pub fastest_per_order: Option<Vec<CandidateJson>>,
    /// When no run reaches the target, the smallest uncertainty any run reaches; else null.
    pub floor: Option<CandidateJson>,
    /// Each order that does not reach the target, at its smallest uncertainty; null without a
    /// target.
    pub floor_per_order_short_of_target: Option<Vec<CandidateJson>>,
    /// White gyro noise of one position's mean, deg/h.
    pub gyro_dph_per_position: f64,
    /// The Monte Carlo check of the formula; null with --mc-runs 0.
    pub monte_carlo: Option<MonteCarloJson>,
    /// Positions of the planned run.
    pub n: u32,
    /// The gyro noise model.
    pub noise_model: NoiseModelJson,
    /// Visiting order of the planned run.
    pub order: &'static str,
    /// Positions the paper's Eq. 31 asks for the target; null without a target or when it
    /// cannot reach it.
    pub paper_n_for_target: Option<u32>,
    /// Target uncertainty, arcsec; null without one.
    pub target_arcsec: Option<f64>,
    /// Time to north of the planned run with levelling and moves, s.
    pub time_s: f64,
    /// The twin's check of the stated sigma; null with --twin-runs 0.
    pub twin_check: Option<TwinCheckJson>,
}

/// A run: order, positions and dwell, its time and uncertainty.
#[derive(Serialize)]
pub(super) struct CandidateJson {
    /// Dwell per position, s.
    dwell_s: f64,
    /// Positions.
    n: usize,
    /// Visiting order.
    order: &'static str,
    /// Azimuth uncertainty under the noise model, arcsec.
    sigma_arcsec: f64,
    /// Levelling plus the positions, s.
    time_s: f64,
}

impl From<&Candidate> for CandidateJson {
    fn from(c: &Candidate) -> CandidateJson {
        CandidateJson {
            dwell_s: c.dwell_s,
            n: c.n,
            order: c.order,
            sigma_arcsec: c.sigma_arcsec,
            time_s: c.time_s,
        }
    }
}

/// The gyro noise model's terms.
#[derive(Serialize)]
pub(super) struct NoiseModelJson {
    /// Angle random walk N, deg/sqrt(h).
    arw_deg_rth: f64,
    /// Bias instability B, deg/h.
    bias_instability_dph: f64,
    /// Gauss-Markov bias standard deviation, deg/h.
    gm_sigma_dph: f64,
    /// Gauss-Markov correlation time, s.
    gm_tau_s: f64,
    /// Quantisation Q, arcsec.
    quantization_arcsec: f64,
    /// Rate random walk K, deg/h/sqrt(h).
    rrw_dph_rth: f64,
}

impl From<&NoiseModel> for NoiseModelJson {
    fn from(m: &NoiseModel) -> NoiseModelJson {
        NoiseModelJson {
            arw_deg_rth: m.arw_deg_rth,
            bias_instability_dph: m.bias_instability_dph,
            gm_sigma_dph: m.gm_sigma_dph,
            gm_tau_s: m.gm_tau_s,
            quantization_arcsec: m.quantization_arcsec,
            rrw_dph_rth: m.rrw_dph_rth,
        }
    }
}

/// The budget under the noise model: null parts where the run's covariance is singular.
#[derive(Serialize)]
pub(super) struct NoiseBudgetJson {
    /// The gyro's part, arcsec.
    pub gyro_arcsec: Option<f64>,
    /// With the encoder and tilt parts, arcsec.
    pub total_arcsec: Option<f64>,
}

/// What each source of error may contribute for the target.
#[derive(Serialize)]
pub(super) struct AllowanceJson {
    /// Encoder error per position, deg.
    encoder_deg: f64,
    /// Gyro noise of one position's mean, deg/h.
    gyro_dph: f64,
    /// Shaft tilt left after levelling, deg.
    tilt_deg: f64,
}

impl From<Sigmas<f64>> for AllowanceJson {
    fn from(s: Sigmas<f64>) -> AllowanceJson {
        AllowanceJson {
            encoder_deg: s.encoder_deg,
            gyro_dph: s.gyro_dph,
            tilt_deg: s.tilt_deg,
        }
    }
}

/// Twin runs of a run (the fastest, else the planned one) against its stated gyro term.
#[derive(Serialize)]
pub(super) struct TwinCheckJson {
    /// Dwell per position, s.
    dwell_s: f64,
    /// Mean length of a run in virtual time, s.
    mean_time_s: f64,
    /// Positions.
    n: usize,
    /// Visiting order.
    order: &'static str,
    /// RMS of the azimuth error, arcsec.
    rms_error_arcsec: f64,
    /// RMS of the error over the fit's own sigma (dimensionless).
    rms_error_over_sigma: f64,
    /// Twin runs.
    runs: u32,
    /// The stated gyro term of the run, arcsec.
    stated_gyro_arcsec: f64,
}

impl TwinCheckJson {
    pub(super) fn new(c: &Candidate, stated: f64, k: &TwinCheck) -> TwinCheckJson {
        TwinCheckJson {
            dwell_s: c.dwell_s,
            mean_time_s: k.mean_time_s,
            n: c.n,
            order: c.order,
            rms_error_arcsec: k.rms_error_arcsec,
            rms_error_over_sigma: k.rms_z,
            runs: k.runs,
            stated_gyro_arcsec: stated,
        }
    }
}

/// Monte Carlo runs of the white-noise model against the formula.
#[derive(Serialize)]
pub(super) struct MonteCarloJson {
    /// The formula's uncertainty, arcsec.
    pub formula_arcsec: f64,
    /// Runs.
    pub runs: u32,
    /// Standard deviation of the runs' azimuths, arcsec.
    pub sd_arcsec: f64,
}
