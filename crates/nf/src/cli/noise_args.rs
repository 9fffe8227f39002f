//! The gyro noise model on the command line: a noise file and flags in IEEE Std 952 units,
//! shared by the subcommands that take one.

use super::Fail;
use crate::noise_file;
use crate::range::real;
use nf_model::noise::NoiseModel;

#[derive(clap::Args, Debug, Clone, Default)]
pub struct NoiseArgs {
    /// Angle random walk N, deg/sqrt(h).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e6))]
    pub arw: Option<f64>,
    /// Bias instability B (flicker), deg/h.
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e6))]
    pub bias_instability: Option<f64>,
    /// Rate random walk K, deg/h/sqrt(h).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e6))]
    pub rrw: Option<f64>,
    /// Gauss-Markov bias: standard deviation, deg/h (with --gm-tau).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e6))]
    pub gm_sigma: Option<f64>,
    /// Gauss-Markov bias: correlation time, s.
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e6))]
    pub gm_tau: Option<f64>,
    /// Output quantisation Q, arcsec.
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e6))]
    pub quantization: Option<f64>,
    /// Heavy-tailed sample noise: Student-t degrees of freedom (> 2).
    #[arg(long, allow_hyphen_values = true, value_parser = student_t_dof)]
    pub student_t_dof: Option<f64>,
    /// Noise-model file (`key = value` lines, or the JSON of `nf allan --json`): the base
    /// model, which the flags above override.
    #[arg(long = "noise", value_name = "FILE")]
    pub noise_file: Option<String>,
}

/// Student-t degrees of freedom: 0 (Gaussian) or above 2, where the variance is finite.
fn student_t_dof(s: &str) -> Result<f64, String> {
    match real(0.0, 1e6)(s)? {
        v if v == 0.0 || v > 2.0 => Ok(v),
        _ => Err("must be 0 (Gaussian) or above 2 (a finite variance)".into()),
    }
}

impl NoiseArgs {
    /// Whether a noise file or any term was given.
    pub fn any(&self) -> bool {
        self.noise_file.is_some()
            || [
                self.arw,
                self.bias_instability,
                self.rrw,
                self.gm_sigma,
                self.gm_tau,
                self.quantization,
                self.student_t_dof,
            ]
            .iter()
            .any(Option::is_some)
    }

    /// `base`, or the noise file's model, with the given terms replaced; an unreadable file or
    /// an invalid model is an error (exit code 2).
    pub fn apply(&self, base: NoiseModel) -> Result<NoiseModel, Fail> {
        let base = match &self.noise_file {
            Some(path) => noise_file::read(path).map_err(|e| Fail(e, 2))?,
            None => base,
        };
        let m = NoiseModel {
            arw_deg_rth: self.arw.unwrap_or(base.arw_deg_rth),
            bias_instability_dph: self.bias_instability.unwrap_or(base.bias_instability_dph),
            rrw_dph_rth: self.rrw.unwrap_or(base.rrw_dph_rth),
            gm_sigma_dph: self.gm_sigma.unwrap_or(base.gm_sigma_dph),
            gm_tau_s: self.gm_tau.unwrap_or(base.gm_tau_s),
            quantization_arcsec: self.quantization.unwrap_or(base.quantization_arcsec),
            student_t_dof: self.student_t_dof.unwrap_or(base.student_t_dof),
        };
        if self.gm_sigma.is_some_and(|s| s > 0.0) && m.gm_tau_s == 0.0 {
            return Err(Fail(
                "--gm-sigma needs --gm-tau, the correlation time in s, above 0".into(),
                2,
            ));
        }
        // A time alone adds nothing: said, since the user meant a Gauss-Markov term.
        if self.gm_tau.is_some_and(|t| t > 0.0) && m.gm_sigma_dph == 0.0 {
            return Err(Fail(
                "--gm-tau needs --gm-sigma, the Gauss-Markov bias's sd in deg/h".into(),
                2,
            ));
        }
        m.validate().map_err(|e| Fail(format!("noise model: {e}"), 2))?;
        Ok(m)
    }

    /// The model given to a fit in place of one estimated from the recording: a noise file,
    /// or the flags with the white noise among them (colours alone are no gyro's model, and
    /// fitted as given they would leave the sigma without the white noise's share).
    pub fn given(&self) -> Result<NoiseModel, Fail> {
        if self.noise_file.is_none() && self.arw.is_none() {
            return Err(Fail(
                format!(
                    "{} without --arw: a noise model given to the fit needs the gyro's white noise (--arw, deg/sqrt(h)); give no noise flags to have the model estimated from the recording",
                    self.describe()
                ),
                2,
            ));
        }
        self.apply(NoiseModel::WHITE_NONE)
    }

    /// A short description of the flags given, for reports.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = [
            ("--arw", self.arw),
            ("--bias-instability", self.bias_instability),
            ("--rrw", self.rrw),
            ("--gm-sigma", self.gm_sigma),
            ("--gm-tau", self.gm_tau),
            ("--quantization", self.quantization),
            ("--student-t-dof", self.student_t_dof),
        ]
        .iter()
        .filter_map(|(n, v)| v.map(|v| format!("{n} {v}")))
        .collect();
        let file = self.noise_file.iter().map(|p| format!("--noise {p}"));
        file.chain(parts).collect::<Vec<_>>().join(" ")
    }
}

/// Said where the noise model was estimated from the recording alone.
pub const STATIC_LOG_HINT: &str = "(from this run alone, which cannot show the wander at its own frequency: a static log of the gyro can, `nf allan LOG --out gyro.noise`, then `--noise gyro.noise`)";

/// The coloured terms of `m` for the text output: flicker and walk, and a Gauss-Markov bias
/// where it has one.
pub fn colour_text(m: &NoiseModel) -> String {
    let mut s = format!(
        "B {:.3e} deg/h, K {:.3e} deg/h/sqrt(h)",
        m.bias_instability_dph, m.rrw_dph_rth
    );
    if m.gm_sigma_dph > 0.0 {
        s += &format!(
            ", Gauss-Markov {:.3e} deg/h over {} s",
            m.gm_sigma_dph,
            three_figures(m.gm_tau_s)
        );
    }
    s
}

/// `x` to three significant figures: a Gauss-Markov time of 0.01 s (a sensor's filter, as
/// `nf allan` fits it) read "over 0.0 s" at one decimal.
pub(crate) fn three_figures(x: f64) -> String {
    if x <= 0.0 || !x.is_finite() {
        return crate::textfile::short(x);
    }
    let scale = 10f64.powi(2 - x.log10().floor() as i32);
    crate::textfile::short((x * scale).round() / scale)
}

#[cfg(test)]
mod tests {
    use super::three_figures;

    #[test]
    fn a_time_is_shown_to_three_figures() {
        let shown: Vec<String> = [0.01, 0.012345, 9.84, 123.456, 4567.0].map(three_figures).into();
        assert_eq!(shown, ["0.01", "0.0123", "9.84", "123", "4570"]);
    }
}
