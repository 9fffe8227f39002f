//! The text of `nf fit`: the azimuth, the noise model, the white-noise fit, the tilt and the
//! budgets, a few lines each.

use super::super::angle5;
use super::super::noise_args::{STATIC_LOG_HINT, colour_text};
use crate::analysis::{Analysis, TiltMethod};
use crate::noise_fit::{NoiseFit, NoiseSource, lines_text};
use nf_model::angle::surveying_azimuth_deg;
use nf_model::fit::Drift;
use std::io::{Result, Write};

/// The whole text of a fit of `rows` positions read from `recording`; `drift` as asked.
pub(super) fn write(out: &mut impl Write, recording: &str, rows: usize, an: &Analysis, drift: Drift) -> Result<()> {
    writeln!(
        out,
        "recording      {recording} ({rows} positions, latitude {} deg)",
        an.latitude_deg
    )?;
    azimuth(out, an)?;
    noise(out, an)?;
    white_fit(out, an)?;
    tilt(out, rows, an)?;
    for w in &an.wild {
        let what = if w.held_out {
            "off the fit of the others: held out of this fit (a glitch or a fill value; `nf diagnose` tests it as an outlier)"
        } else {
            "off the fit: kept, as more than a tenth of the dwells lie this far off, which is the data (a model the fit lacks, heavy tails), not glitches, or the rest would leave the fit no degree of freedom"
        };
        writeln!(
            out,
            "far off        line {} (index {}): rate_dph {} lies {:.0} robust sigmas {what}",
            w.line, w.index, w.rate_dph, w.sigmas
        )?;
    }
    if drift != Drift::None {
        let (d1, d2) = an.fit.drift();
        writeln!(out, "drift          {d1:.3e} deg/h/s, {d2:.3e} deg/h/s^2")?;
    }
    for (name, b) in [("Eq. 31 (paper)", &an.budget_paper), ("exact model", &an.budget_exact)] {
        writeln!(
            out,
            "{name:<14} total {:.2}\" = gyro {:.2}\" (+) encoder {:.2}\" (+) tilt {:.2}\"",
            b.total_arcsec, b.gyro_arcsec, b.encoder_arcsec, b.tilt_arcsec
        )?;
    }
    Ok(())
}

/// The azimuth and its sigma, or why there is none.
fn azimuth(out: &mut impl Write, an: &Analysis) -> Result<()> {
    let g = &an.gls;
    if let Some(why) = g.unresolved(an.amplitude_predicted_dph) {
        writeln!(
            out,
            "NOT RESOLVED   the Earth rate is not resolved: {why}; no azimuth can be given"
        )?;
        return writeln!(
            out,
            "               (the fit's numbers, not an azimuth: psi {:.3} deg +- {:.3} deg)",
            g.psi_deg, g.sigma_psi_deg
        );
    }
    writeln!(
        out,
        "azimuth psi    {} deg  (Eq. 7: rate = WE cos(lat) cos(gamma + psi))",
        angle5(g.psi_deg)
    )?;
    writeln!(
        out,
        "surveying az.  {} deg  (clockwise from true north, of the gamma = 0 direction)",
        angle5(surveying_azimuth_deg(g.psi_deg))
    )?;
    writeln!(
        out,
        "sigma          {:.2} arcsec  (1 sigma, generalised least squares under the noise model{}{})",
        g.sigma_psi_deg * 3600.0,
        widened(g),
        match an.sigma_inclinometer_deg * 3600.0 {
            s if s >= 0.005 => format!(", with {s:.2} arcsec from the tilt circle's uncertainty"),
            _ => String::new(),
        }
    )
}

/// What the gyro's sigma holds beyond GLS under the printed model alone, when it is more.
fn widened(g: &NoiseFit) -> String {
    match g.source {
        NoiseSource::Residuals { dof, .. } => format!(
            ", widened {:.2} times: Student's t of {dof} dof, 95 % within 1.96 sigma",
            g.widening
        ),
        NoiseSource::Given { scatter: Some(_), .. } => format!(
            ", widened {:.2} times: the recording scatters beyond the given model",
            g.widening
        ),
        _ if g.widening < 1.005 => String::new(),
        _ => format!(
            ", widened {:.2} times for the noise models this run cannot rule out",
            g.widening
        ),
    }
}

/// The noise model, where it came from, and the shocks read.
fn noise(out: &mut impl Write, an: &Analysis) -> Result<()> {
    let g = &an.gls;
    let m = &g.model;
    writeln!(out, "noise model    {}", g.source.describe())?;
    // The dwell, where no metadata gives it, is a guess: say whence.
    let mut from = match g.dwell_from {
        crate::dwells::FROM_METADATA => String::new(),
        from => format!(", {from}"),
    };
    if let Some((lo, hi)) = g.dwell_range_s {
        from += &format!("; the dwells are {lo:.3}-{hi:.3} s by their samples, each mean weighed by its own");
    }
    // A sensor's short filter tail is also each dwell's own noise (`nf plan` budgets it so).
    let tail = match m.gm_within(g.dwell_s) {
        true => format!(", {:.5} with its Gauss-Markov tail", m.own_mean_sd_dph(g.dwell_s)),
        false => String::new(),
    };
    writeln!(
        out,
        "               N {:.3e} deg/sqrt(h) (a {:.3} s dwell mean{from}: {:.5} deg/h{tail}), {}; chi2 {:.1} on {} dof",
        m.arw_deg_rth,
        g.dwell_s,
        m.white_mean_sd_dph(g.dwell_s),
        colour_text(m),
        g.chi2,
        g.dof
    )?;
    if matches!(g.source, NoiseSource::Estimated { .. } | NoiseSource::Residuals { .. }) {
        writeln!(out, "               {STATIC_LOG_HINT}")?;
    }
    if let Some(s) = &g.shocks {
        writeln!(
            out,
            "shocks         {} of {} dwells read as struck (a share of {:.2}, a shift of sd {:.5} deg/h; lines {}): each dwell weighed by how likely a shock struck it",
            s.struck.len(),
            an.fit.n,
            s.share,
            s.shift_dph,
            lines_text(&s.struck)
        )?;
    }
    Ok(())
}

/// White least squares beside the result: its azimuth, amplitude, bias and residuals.
fn white_fit(out: &mut impl Write, an: &Analysis) -> Result<()> {
    let (f, g) = (&an.fit, &an.gls);
    if f.dof == 0 {
        writeln!(
            out,
            "white LS       psi {:.5} deg (no sigma from the residuals: as many positions as unknowns leave none)",
            f.psi_deg
        )?;
    } else {
        writeln!(
            out,
            "white LS       psi {:.5} deg +- {:.2} arcsec (sigma from the residuals, {} dof: too small when the noise is coloured)",
            f.psi_deg,
            f.sigma_psi_deg * 3600.0,
            f.dof
        )?;
    }
    writeln!(
        out,
        "amplitude      {:.5} +- {:.5} deg/h  (latitude predicts {:.5}: scale factor {:.5})",
        g.amplitude_dph,
        g.sigma_amplitude_dph,
        an.amplitude_predicted_dph,
        g.amplitude_dph / an.amplitude_predicted_dph
    )?;
    if let Some(w) = an.amplitude_warning() {
        writeln!(out, "               WARNING: {w}")?;
    }
    if f.dof == 0 {
        writeln!(out, "bias (offset)  {:.5} deg/h", f.offset_dph)?;
        return writeln!(out, "residuals      none: the fit passes through every position");
    }
    writeln!(
        out,
        "bias (offset)  {:.5} +- {:.5} deg/h",
        f.offset_dph, f.sigma_offset_dph
    )?;
    writeln!(
        out,
        "residuals      RSS {:.6e} (deg/h)^2, sd {:.5} deg/h (over {} dof)",
        f.rss, an.sigma_gyro_dph, f.dof
    )
}

/// How the tilt was corrected, with its warnings, over `rows` positions.
fn tilt(out: &mut impl Write, rows: usize, an: &Analysis) -> Result<()> {
    match (an.method, an.shaft) {
        (TiltMethod::Exact, Some(s)) => writeln!(
            out,
            "tilt           corrected with the exact model, iterated to convergence: shaft tilt {:.4} deg towards {:.1} deg (the inclinometer's {} on {} positions)",
            s.tilt_deg,
            s.tilt_dir_deg,
            match (s.offset_x_deg.is_finite(), s.offset_y_deg.is_finite()) {
                (true, true) => "X and Y",
                (true, false) => "X alone",
                _ => "Y alone",
            },
            rows - an.tilt_bridged
        )?,
        (TiltMethod::FirstOrder, _) => {
            writeln!(out, "tilt           corrected per position from tilt_x (first order)")?
        }
        _ => writeln!(
            out,
            "tilt           not corrected (no inclinometer columns, or --tilt none): a shaft tilt eta moves psi by up to eta tan(lat), the exact model's tilt term below ({:.2}\"), which the sigma above leaves out",
            an.budget_exact.tilt_arcsec
        )?,
    }
    if let Some(w) = &an.tilt_warning {
        writeln!(out, "               WARNING: {w}")?;
    }
    if an.tilt_bridged > 0 {
        writeln!(
            out,
            "tilt           {} positions without an inclinometer reading: corrected from the tilt circle of the others",
            an.tilt_bridged
        )?;
    }
    Ok(())
}
