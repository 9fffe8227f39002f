//! Scans of one added column over every position (an indicator for an outlier, a step for a
//! jump) by a rank-one update of the current fit instead of a fit per candidate: with
//! `x~ = W x` and `M` the projector off the whitened design, adding `x` lowers the RSS by
//! `(x~^T r~)^2 / |M x~|^2`, and `|M x~|^2 = |x~|^2 - g^T (X~^T X~)^-1 g`, `g = X~^T x~`.
//! Every inner product with `x~` is one of `W^T v` with `x` (an element for an indicator, a
//! suffix sum for a step), so the whole scan costs a few adjoint passes: O(n (p + r^2)).

use super::effect::Frame;

/// The fit with one column added.
#[derive(Debug, Clone, Copy)]
pub struct Added {
    /// Whitened residual sum of squares.
    pub rss: f64,
    pub dof: usize,
    /// The new column's coefficient and its variance per unit of `s2`.
    pub coef: f64,
    pub var_unit: f64,
}

impl Added {
    pub fn s2(&self) -> f64 {
        self.rss / self.dof as f64
    }

    pub fn sigma(&self) -> f64 {
        (self.var_unit * self.s2()).sqrt()
    }
}

/// Which column each position adds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// 1 at the position, 0 elsewhere.
    Indicator,
    /// 1 from the position on in time, 0 before.
    Step,
}

/// The fit of `frame` with the column of `shape` at each position added; `None` where the
/// column lies in the design's span or no degree of freedom is left.
pub fn scan(frame: &Frame, shape: Shape) -> Vec<Option<Added>> {
    let w = frame.whitener;
    let fit = &frame.fit;
    let n = fit.resid.len();
    let (ind, step) = w.indicator_and_step_norms(n);
    let read = |v: Vec<f64>| match shape {
        Shape::Indicator => v,
        Shape::Step => suffix_sums(&v),
    };
    let xr = read(w.adjoint(&fit.resid));
    let xg: Vec<Vec<f64>> = frame.model.cols.iter().map(|c| read(w.adjoint(&c.white))).collect();
    let norms = if shape == Shape::Indicator { ind } else { step };
    let p = xg.len();
    (0..n)
        .map(|i| {
            let g: Vec<f64> = xg.iter().map(|v| v[i]).collect();
            let explained: f64 = (0..p)
                .map(|a| g[a] * (0..p).map(|b| fit.cov_unit[a][b] * g[b]).sum::<f64>())
                .sum();
            let m = norms[i] - explained;
            (fit.dof > 1 && m > 1e-10 * norms[i]).then(|| Added {
                rss: (fit.rss - xr[i] * xr[i] / m).max(0.0),
                dof: fit.dof - 1,
                coef: xr[i] / m,
                var_unit: 1.0 / m,
            })
        })
        .collect()
}

fn suffix_sums(v: &[f64]) -> Vec<f64> {
    let mut out = v.to_vec();
    for i in (0..out.len().saturating_sub(1)).rev() {
        out[i] += out[i + 1];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::model::Model;
    use crate::diagnose::whiten::Whitener;
    use crate::gls::Cov;
    use nf_model::noise::NoiseModel;
    use nf_model::rng::Rng;

    /// The rank-one scan against a fit per candidate (the column whitened and appended), under
    /// white noise and under flicker with a random walk.
    #[test]
    fn agrees_with_a_fit_per_candidate() {
        let mut rng = Rng::new(8);
        let n = 80;
        let t: Vec<f64> = (0..n).map(|i| 3.0 * i as f64 + rng.uniform(0.0, 0.5)).collect();
        let gamma: Vec<f64> = (0..n).map(|i| (i as f64 * 4.5).to_radians()).collect();
        let base = vec![
            vec![1.0; n],
            gamma.iter().map(|g| g.cos()).collect(),
            gamma.iter().map(|g| g.sin()).collect(),
        ];
        let y: Vec<f64> = (0..n).map(|i| 2.0 + 10.0 * base[1][i] + 0.01 * rng.gauss()).collect();
        let coloured = NoiseModel {
            bias_instability_dph: 0.01,
            rrw_dph_rth: 0.02,
            ..NoiseModel::white(0.01, 2.0)
        };
        let whiteners = [
            Whitener::identity(),
            Whitener::of(Cov::of_windows(&coloured, &t, &vec![2.0; n]).unwrap()),
        ];
        for w in &whiteners {
            let model = Model::new(base.clone(), y.clone(), w);
            let fit = model.fit().unwrap();
            let frame = Frame {
                whitener: w,
                model: model.clone(),
                fit,
            };
            for shape in [Shape::Indicator, Shape::Step] {
                let fast = scan(&frame, shape);
                for (i, a) in fast.iter().enumerate().skip(1) {
                    let x: Vec<f64> = (0..n)
                        .map(|k| f64::from(u8::from(k == i || (shape == Shape::Step && k > i))))
                        .collect();
                    let big = model.fit_plus(&[w.apply(&x)]).unwrap();
                    let a = a.unwrap();
                    let k = base.len();
                    assert!((a.rss / big.rss - 1.0).abs() < 1e-8, "{shape:?} {i}: rss");
                    assert!(
                        (a.coef - big.coef[k]).abs() < 1e-8 * big.sigma(k),
                        "{shape:?} {i}: coef"
                    );
                    assert!((a.sigma() / big.sigma(k) - 1.0).abs() < 1e-8, "{shape:?} {i}: sigma");
                    assert_eq!(a.dof, big.dof);
                }
                // The step from the first row is the constant: in the design's span.
                if shape == Shape::Step {
                    assert!(fast[0].is_none());
                }
            }
        }
    }
}
