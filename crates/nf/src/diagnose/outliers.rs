//! `outliers`: one disturbed position. The largest externally studentised residual of the
//! whitened fit, Bonferroni over the positions; judged under every tail the noise allows
//! ([`super::tails::TailLaw`]), so that heavy-tailed noise is not read as a string of outliers.

use super::effect::{Change, Draws, Effect, Proposal, State, param};
use super::kind::Kind;
use super::scan::{Shape, scan};

pub struct Outliers;

impl Effect for Outliers {
    fn kind(&self) -> Kind {
        Kind::Outliers
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        let d = s.data;
        let n = d.n();
        if s.main.fit.dof < 3 {
            return Vec::new();
        }
        let fits = scan(s.main, Shape::Indicator);
        let best = (0..n)
            .filter_map(|i| {
                let big = fits[i]?;
                let t = ((s.main.fit.rss - big.rss).max(0.0) / big.s2()).sqrt();
                Some((t, i, big))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((t, i, big)) = best else { return Vec::new() };
        let p_one = s.tails.sf2(t, big.dof as f64);
        let row = &d.rec.rows[i];
        vec![Proposal {
            kind: Kind::Outliers,
            p: (p_one * n as f64).min(1.0),
            change: Change::Columns(vec![d.indicator(i)]),
            parameters: vec![
                param("index", row.index as f64, None),
                param("size_dph", big.coef, Some(big.sigma())),
            ],
            location: format!(
                "position {} (line {}, gamma {:.2} deg)",
                row.index, row.line, d.gamma[i]
            ),
            scanned: 1,
            own_p: None,
            draws: Draws::No,
        }]
    }
}
