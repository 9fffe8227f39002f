//! `nf allan`: the overlapping Allan deviation of a static log (or a recording's dwell means),
//! its confidence intervals, and the IEEE Std 952 noise terms fitted to it.

use super::Fail;
use crate::allan::{CI_LEVEL, Point, adev_interval};
use crate::allan_fit::{ALPHA, AllanFit, Term, fit_series};
use crate::allan_model::{curve_taus, floor};
use crate::allan_source::Source;
use crate::noise_file;
use crate::plot::{self, Panel, Series, Style};
use crate::range::above;
use crate::report::Page;
use crate::stats::chi2_quantile;
use nf_model::noise::{NoiseModel, flicker_floor_factor};
use std::io::Write;

mod json;

#[derive(clap::Args)]
pub struct AllanArgs {
    /// A static log (northfinder-static/1) or a recording (northfinder-recording/1).
    file: String,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
    /// Log-log chart: the curve with its intervals, the fit and each term (*.svg or *.png).
    #[arg(long, value_parser = super::plot_file)]
    plot: Option<String>,
    /// Write a self-contained HTML report: the fitted terms, the table, the Allan plot.
    #[arg(long)]
    report: Option<String>,
    /// Write the fitted model as a noise file (for --noise of simulate and fit).
    #[arg(long)]
    out: Option<String>,
    /// Sample rate, Hz: overrides the step of the time column.
    #[arg(long, allow_hyphen_values = true, value_parser = above(0.0, 1e9))]
    sample_rate: Option<f64>,
    /// Keep a static log's spikes (samples beyond 100 robust sigmas of the noise: fill values,
    /// glitches), which are otherwise left out and listed.
    #[arg(long)]
    keep_spikes: bool,
}

/// What is reported: the input, the curve and its intervals, the fit.
struct Report<'a> {
    file: &'a str,
    src: &'a Source,
    points: &'a [Point],
    /// Each point's interval of the deviation.
    ci: Vec<(f64, f64)>,
    fit: &'a AllanFit,
}

/// Four significant digits, scientific where that is shorter to read.
fn g(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{x:.3e}");
    }
    format!("{x:.*}", (3 - mag).max(0) as usize)
}

pub fn cmd_allan(a: AllanArgs) -> Result<(), Fail> {
    super::folders_exist(&[&a.plot, &a.report, &a.out])?;
    let text = crate::textfile::read_text(&a.file).map_err(|e| Fail(e.at(&a.file), 2))?;
    let src = Source::parse(&text, a.sample_rate, a.keep_spikes).map_err(|e| Fail(e.at(&a.file), 2))?;
    // A log the terms cannot be fitted to (one that does not vary) is bad input, as a
    // malformed one is.
    let (points, fit) = fit_series(&src.segments(), src.sampling, src.removed.as_ref())
        .map_err(|e| Fail(format!("{}: {e}", a.file), 2))?;
    let mut src = src;
    // Said in the text and written into `--out`'s file, which plan and fit read.
    let units = (fit.model.arw_deg_rth > 0.0 && fit.model.arw_deg_rth < IMPLAUSIBLE_ARW).then(|| {
        format!(
            "N {} deg/sqrt(h) is below any gyro's (the best ring lasers and HRGs are near 1e-4): is rate_dph in deg/s or rad/s? deg/h is deg/s times 3600",
            g(fit.model.arw_deg_rth)
        )
    });
    src.notes.extend(units.clone());
    let r = Report {
        file: &a.file,
        src: &src,
        points: &points,
        ci: points
            .iter()
            .zip(&fit.edf)
            .map(|(p, &e)| adev_interval(p.avar, e))
            .collect(),
        fit: &fit,
    };
    if let Some(path) = &a.plot {
        plot::write(path, &[r.panel()])?;
    }
    if let Some(path) = &a.out {
        let mut comment = format!(
            "fitted by nf allan to {} ({} values); chi2/dof {}",
            a.file,
            src.rates.len(),
            g(fit.chi2 / fit.dof as f64)
        );
        if fit.model_error > 0.0 {
            comment += &format!(" with a relative model error of {:.1} %", 100.0 * fit.model_error);
        }
        if let Some(r) = fit.ramp() {
            comment += &format!(
                "; a rate ramp of {} deg/h/h was fitted too, a trend, not noise, so not here",
                g(r.value)
            );
        }
        // Each term's interval beside it: a reader of the file sees which are only bounds.
        let mut comments: Vec<String> = std::iter::once(comment).chain(units).collect();
        comments.extend(
            TERMS
                .iter()
                .filter(|t| t.0 != Term::Ramp)
                .map(|(term, label, unit)| format!("{label}: {}", term_text(&fit, *term, unit))),
        );
        let tau = |p: Option<&Point>| p.map_or(f64::NAN, |p| p.tau_s);
        comments.push(format!(
            "measured at averaging times {} to {} s; nf fit, nf diagnose and nf plan take the values below as known: a term not significant above is a best estimate within its bound, not a measurement",
            g(tau(points.first())),
            g(tau(points.last()))
        ));
        std::fs::write(path, noise_file::write(&fit.model, &comments))
            .map_err(|e| Fail(format!("cannot write {path}: {e}"), 1))?;
    }
    if let Some(report) = &a.report {
        // Each term as the text gives it: a bound or a term not significant is said so.
        let mut headline = TERMS[..3]
            .iter()
            .map(|(term, label, unit)| format!("{}: {}", &label[..1], term_text(&fit, *term, unit)))
            .collect::<Vec<_>>()
            .join("; ");
        if let Some(r) = fit.ramp() {
            headline += &format!(", a ramp R {} deg/h/h", g(r.value));
        }
        let page = Page {
            title: &format!("nf allan: {}", a.file),
            headline: &headline,
            text: &r.text(),
            svgs: &[plot::render_svg(&[r.panel()])],
            notes: &[],
        };
        page.write(report)?;
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&r.json()).unwrap_or_default())?;
    } else {
        write!(out, "{}", r.text())?;
    }
    Ok(())
}

/// The terms as (term, label, unit).
const TERMS: [(Term, &str, &str); 5] = [
    (Term::Arw, "N (angle random walk)", "deg/sqrt(h)"),
    (Term::BiasInstability, "B (bias instability)", "deg/h"),
    (Term::Rrw, "K (rate random walk)", "deg/h/sqrt(h)"),
    (Term::Quantization, "Q (quantisation)", "arcsec"),
    (Term::Ramp, "R (rate ramp, a trend)", "deg/h/h"),
];

/// An angle random walk below this (deg/sqrt(h)) is a unit mistake, not a gyro.
const IMPLAUSIBLE_ARW: f64 = 1e-5;

/// The level of the bound on B stated where the curve has not bottomed out.
const BOUND_LEVEL: f64 = 0.95;

/// A term's value and 68 % interval as the text and the noise file's comments give it.
fn term_text(fit: &AllanFit, term: Term, unit: &str) -> String {
    match fit.param(term) {
        // The sigma maps the variance coefficient's up through the square root: a size some
        // sigmas from zero can be a coefficient within noise of zero.
        Some(p) if p.value > 0.0 && p.consistent_with_zero(2.0) => format!(
            "{} +{} -{} {unit} (not significant: its Allan variance coefficient is {:.1} sd from zero)",
            g(p.value),
            g(p.sigma),
            g(p.value - p.lo),
            p.coef / p.coef_sd
        ),
        Some(p) if p.value > 0.0 => format!("{} +{} -{} {unit}", g(p.value), g(p.sigma), g(p.value - p.lo)),
        Some(p) => format!("0 (1-sigma bound {} {unit})", g(p.sigma)),
        None => match (term, fit.q_test, fit.ramp_test) {
            (Term::Quantization, Some(t), _) | (Term::Ramp, _, Some(t)) => {
                format!("not significant (F test p = {}, kept below {ALPHA})", g(t.p_value))
            }
            _ => "not fitted".into(),
        },
    }
}

fn describe_source(file: &str, src: &Source) -> String {
    let n = src.rates.len();
    let step = src.sampling.step_s;
    format!(
        "{file}: {}, {n} values every {} s ({} Hz), {} segment(s), {} h",
        src.kind.name().replace('_', " "),
        g(step),
        g(1.0 / step),
        src.spacing.segments.len(),
        g(n as f64 * step / 3600.0)
    )
}

impl Report<'_> {
    /// The rows of the curve: point, edf, interval.
    fn rows(&self) -> impl Iterator<Item = (&Point, f64, (f64, f64))> {
        self.points
            .iter()
            .zip(&self.fit.edf)
            .zip(&self.ci)
            .map(|((p, e), c)| (p, *e, *c))
    }

    fn text(&self) -> String {
        let (src, fit) = (self.src, self.fit);
        let mut out = format!("source     {}\n", describe_source(self.file, src));
        for n in &src.notes {
            out += &format!("note       {n}\n");
        }
        out += &format!(
            "\n{:>12} {:>12} {:>25} {:>10} {:>9}\n",
            "tau_s",
            "adev_dph",
            format!("{:.0} % interval (deg/h)", CI_LEVEL * 100.0),
            "clusters",
            "edf"
        );
        for (p, edf, (lo, hi)) in self.rows() {
            out += &format!(
                "{:>12} {:>12} {:>25} {:>10} {:>9}\n",
                g(p.tau_s),
                g(p.avar.sqrt()),
                format!("{} .. {}", g(lo), g(hi)),
                p.clusters,
                g(edf)
            );
        }
        out += &format!(
            "\nfit        generalised least squares of sigma^2(tau), points weighted by their covariance under the fitted model\n           chi2 {} on {} dof ({} per dof)\n",
            g(fit.chi2),
            fit.dof,
            g(fit.chi2 / fit.dof as f64)
        );
        if fit.model_error > 0.0 {
            out += &format!(
                "           the terms do not describe this curve within its points' scatter: each point also given a relative error of {:.1} %\n",
                100.0 * fit.model_error
            );
        }
        for (term, label, unit) in TERMS {
            out += &format!("{label:<26} {}\n", term_text(fit, term, unit));
        }
        let gm = match (fit.gm(), fit.gm_test) {
            (Some((s, tau)), _) => format!(
                "sigma {} +{} -{} deg/h, tau {} s",
                g(s.value),
                g(s.sigma),
                g(s.value - s.lo),
                g(tau)
            ),
            (None, Some((tau, t))) => format!("not significant (best tau {} s, F test p = {})", g(tau), g(t.p_value)),
            (None, None) => "not tested (too few points)".into(),
        };
        out += &format!("{:<26} {gm}\n", "Gauss-Markov");
        if let Some(n) = fit.arw_beyond_gm() {
            out += &format!(
                "{:<26} {} deg/sqrt(h) (N with the Gauss-Markov tail: the white level of means much longer than its tau)\n",
                "N beyond tau",
                g(n)
            );
        }
        let ((mt, ma), (ft, fa)) = floor(self.points, &fit.model, src.sampling);
        let longest = self.points.last().map_or(f64::NAN, |p| p.tau_s);
        let read_off = if let Some((p, edf, _)) = self.rows().last().filter(|_| mt >= longest) {
            // The lowest point is the last: every term adds to the Allan variance, so the
            // flicker's floor lies under the true curve there, which that point bounds only
            // as far as its few clusters allow (an outside audit: B = 10 stated below 8.3).
            let upper = (edf * p.avar / chi2_quantile(1.0 - BOUND_LEVEL, edf)).sqrt();
            format!(
                "not reached: lowest at the longest tau, so B is below about {} / {:.3} = {} deg/h, that point's {:.0} % upper bound",
                g(upper),
                flicker_floor_factor(),
                g(upper / flicker_floor_factor()),
                100.0 * BOUND_LEVEL
            )
        } else {
            // White noise and the walk lift the floor above flicker's own: the reading is high,
            // the fit's B the estimate.
            format!(
                "read off as B = floor / {:.3}: {} deg/h, high where white noise or the walk lift the floor; the fitted B above is the estimate",
                flicker_floor_factor(),
                g(ma / flicker_floor_factor())
            )
        };
        out += &format!(
            "\nfloor      measured: {} deg/h at tau {} s ({read_off})\n           fitted curve: {} deg/h at tau {} s\n",
            g(ma),
            g(mt),
            g(fa),
            g(ft)
        );
        out
    }

    fn panel(&self) -> Panel {
        let (src, fit) = (self.src, self.fit);
        let taus = curve_taus(self.points, src.sampling, 200);
        // A ramp is no noise term of the model: its Allan variance (R tau)^2 / 2 is added here.
        let ramp = |r: f64, t: f64| 0.5 * (r * t / 3600.0).powi(2);
        let line = |name: String, m: &NoiseModel, r: f64| Series {
            name,
            points: taus
                .iter()
                .map(|&t| (t, (src.sampling.expected_at(m, t) + ramp(r, t)).max(0.0).sqrt()))
                .collect(),
            style: Style::Line,
        };
        let mut series = vec![
            Series {
                name: "measured (overlapping ADEV)".into(),
                points: self.points.iter().map(|p| (p.tau_s, p.avar.sqrt())).collect(),
                style: Style::Points,
            },
            Series {
                name: format!("{:.0} % interval", CI_LEVEL * 100.0),
                points: self
                    .rows()
                    .flat_map(|(p, _, (lo, hi))| [(p.tau_s, lo), (p.tau_s, hi)])
                    .collect(),
                style: Style::Bars,
            },
            line("fit: all terms".into(), &fit.model, fit.ramp().map_or(0.0, |r| r.value)),
        ];
        // What the points were fitted to: the model less what the removed harmonic took.
        if let Some(removed) = &src.removed {
            let ms: Vec<usize> = self.points.iter().map(|p| p.m).collect();
            let lost = removed.loss(&fit.model, src.sampling, &ms);
            let r = fit.ramp().map_or(0.0, |r| r.value);
            series.push(Series {
                name: "fit less what the harmonic took (as measured)".into(),
                points: self
                    .points
                    .iter()
                    .zip(&lost)
                    .map(|(p, l)| {
                        let avar = src.sampling.expected_avar(&fit.model, p.m) + ramp(r, p.tau_s) - l;
                        (p.tau_s, avar.max(0.0).sqrt())
                    })
                    .collect(),
                style: Style::Line,
            });
        }
        for (term, p) in &fit.terms {
            if p.value > 0.0 {
                let mut m = NoiseModel::WHITE_NONE;
                term.set(&mut m, p.value);
                let r = if *term == Term::Ramp { p.value } else { 0.0 };
                let name = match term {
                    Term::Ramp => "R: rate ramp".to_string(),
                    Term::Arw => "N: white".to_string(),
                    Term::BiasInstability => "B: flicker".into(),
                    Term::Rrw => "K: random walk".into(),
                    Term::Quantization => "Q: quantisation".into(),
                    Term::GaussMarkov { tau_s } => format!("Gauss-Markov, tau {} s", g(*tau_s)),
                };
                // A term far below every measured point is not drawn there: it would
                // stretch the axis by decades of nothing.
                let floor = self.points.iter().map(|p| p.avar.sqrt()).fold(f64::INFINITY, f64::min) / 5.0;
                let mut term_line = line(name, &m, r);
                for q in term_line.points.iter_mut().filter(|q| q.1 < floor) {
                    q.1 = f64::NAN;
                }
                series.push(term_line);
            }
        }
        Panel {
            title: format!("Allan deviation of {}", self.file),
            x_label: "averaging time tau (s)".into(),
            y_label: "Allan deviation (deg/h)".into(),
            series,
            log_x: true,
            log_y: true,
        }
    }
}
