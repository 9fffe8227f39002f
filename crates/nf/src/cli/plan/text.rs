//! The text of `nf plan`: the planned run and its budgets, then what was asked beside them;
//! with a target, its answer first and the run of `--n`, `--dwell` and `--order` after it.

use super::{PlanArgs, Planned, describe, unreachable};
use crate::plan_noise;
use crate::textfile::short;
use nf_model::uncertainty::tilt_arcsec;
use std::io::{Result, Write};

pub(super) fn write(out: &mut impl Write, a: &PlanArgs, p: &Planned) -> Result<()> {
    let tail = match p.model.gm_within(a.ref_dwell) {
        true => format!(
            " with its {} s Gauss-Markov tail",
            crate::cli::noise_args::three_figures(p.model.gm_tau_s)
        ),
        false => String::new(),
    };
    let visits = if p.visits_per_position == 1.0 {
        String::new()
    } else {
        format!(
            ", {} visits and {} s of dwell per position",
            short(p.visits_per_position),
            short(p.inp.dwell_s)
        )
    };
    let asked = match (a.target, &p.search) {
        (Some(t), Some(search)) => {
            target(out, a, t, search)?;
            "the run of --n, --dwell and --order"
        }
        _ => "planned run",
    };
    writeln!(
        out,
        "{asked}: n = {}, dwell {} s, {} order (gyro {:.5} deg/h per position{tail}{visits}), {:.0} s to north with levelling and moves",
        a.n,
        a.dwell,
        p.order.name(),
        p.sigmas.gyro_dph,
        p.time_s
    )?;
    budgets(out, p)?;
    if let Some(t) = a.target {
        at_n(out, a, p, t)?;
    }
    if let Some((c, stated, k)) = &p.twin {
        writeln!(
            out,
            "twin check, {} runs of the {}: RMS error {:.2}\" against the stated gyro term {stated:.2}\" ({:+.1}%), RMS error/sigma {:.2}",
            k.runs,
            describe(c),
            k.rms_error_arcsec,
            (k.rms_error_arcsec / stated - 1.0) * 100.0,
            k.rms_z
        )?;
    }
    if let Some((m, f)) = p.mc {
        writeln!(
            out,
            "Monte Carlo (white noise), {} runs: sd {m:.2}\" against the formula {f:.2}\" ({:+.1}%)",
            a.mc_runs,
            (m / f - 1.0) * 100.0
        )?;
    }
    Ok(())
}

/// The planned run's budgets: the paper's, the exact white-noise ones and the noise model's.
fn budgets(out: &mut impl Write, p: &Planned) -> Result<()> {
    writeln!(
        out,
        "{:<22} {:>9} {:>9} {:>9} {:>9}",
        "budget (arcsec)", "gyro", "encoder", "tilt", "total"
    )?;
    for (name, b) in [
        ("Eq. 31 (paper)", &p.paper),
        ("exact, white noise", &p.exact),
        ("exact, numerical", &p.numerical),
    ] {
        writeln!(
            out,
            "{name:<22} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
            b.gyro_arcsec, b.encoder_arcsec, b.tilt_arcsec, b.total_arcsec
        )?;
    }
    if let (Some(g), Some(t)) = (p.noise_gyro, p.noise_total) {
        writeln!(
            out,
            "{:<22} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
            "noise model (GLS)", g, p.exact.encoder_arcsec, p.exact.tilt_arcsec, t
        )?;
    }
    Ok(())
}

/// The runs that reach the target `t` arcsec, or why none does.
fn target(out: &mut impl Write, a: &PlanArgs, t: f64, search: &plan_noise::Plan) -> Result<()> {
    match &search.fastest {
        Some(c) => writeln!(out, "target {t}\": fastest run under the noise model: {}", describe(c))?,
        None if tilt_arcsec(a.tilt, a.lat) >= t => writeln!(
            out,
            "target {t}\": not reachable: the levelling residue alone (tilt {} deg, left uncorrected) gives {:.2}\"; the firmware and nf fit correct the tilt from the inclinometer: --tilt 0 plans such a run",
            a.tilt,
            tilt_arcsec(a.tilt, a.lat)
        )?,
        None => writeln!(
            out,
            "target {t}\": not reachable with this gyro and motor {}",
            unreachable(search, &super::space(a))
        )?,
    }
    for c in &search.per_order {
        writeln!(out, "  fastest {}", describe(c))?;
    }
    if search.fastest.is_some() {
        // A longer dwell than the search's can still gain in an order short of the target.
        let longest = plan_noise::Space::default().dwells_s.into_iter().fold(0.0, f64::max);
        for c in &search.short_of {
            writeln!(
                out,
                "  never reaches it: {} (its best with dwells up to {longest} s in runs up to {:.0} s)",
                describe(c),
                a.max_time
            )?;
        }
        // An outside audit fitted a planned 5" run without the model: a median 5.4" stated,
        // over 6" in 47 % of runs, for errors of 4.9".
        writeln!(
            out,
            "  these sigmas are GLS's under the noise model given: fit the run with it (nf fit REC --noise FILE, or the same noise flags); estimated from the run alone, the model is uncertain and the sigma comes out wider"
        )?;
    }
    Ok(())
}

/// What the target asks of the run of `--n` and `--dwell`: the allowances and the paper's n.
fn at_n(out: &mut impl Write, a: &PlanArgs, p: &Planned, t: f64) -> Result<()> {
    if let Some(s) = p.allowance {
        writeln!(
            out,
            "target {t}\" at n = {}: allowances of a third of the variance each (the gyro's as white noise of a position's mean): gyro {:.5} deg/h per position, encoder {:.5} deg, levelling {:.5} deg",
            a.n, s.gyro_dph, s.encoder_deg, s.tilt_deg
        )?;
    }
    match p.paper_n {
        Some(n) => writeln!(
            out,
            "target {t}\": the paper's Eq. 31 (white noise) asks for n = {n} at {} s of dwell per position",
            short(p.inp.dwell_s)
        ),
        None => writeln!(
            out,
            "target {t}\": the paper's Eq. 31 (white noise, {} s of dwell per position) reaches it with no n",
            short(p.inp.dwell_s)
        ),
    }
}
