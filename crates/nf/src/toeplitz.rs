//! The product of a symmetric Toeplitz matrix with vectors in O(n log n): the matrix embedded
//! in a circulant of a power-of-two size, which a discrete Fourier transform diagonalises.

/// Vectors held as their transforms, to be multiplied by many Toeplitz matrices.
#[derive(Debug, Clone, PartialEq)]
pub struct Vectors {
    n: usize,
    spectra: Vec<Vec<(f64, f64)>>,
}

impl Vectors {
    pub fn of(xs: &[Vec<f64>]) -> Vectors {
        let n = xs.first().map_or(0, Vec::len);
        let size = (2 * n).next_power_of_two().max(2);
        let spectra = xs
            .iter()
            .map(|x| {
                let mut v = vec![(0.0, 0.0); size];
                for (slot, x) in v.iter_mut().zip(x) {
                    slot.0 = *x;
                }
                fft(&mut v, false);
                v
            })
            .collect();
        Vectors { n, spectra }
    }

    /// `y_i = sum_j g[|i - j|] x_j` for each vector `x` (`g` as long as they are).
    pub fn times(&self, g: &[f64]) -> Vec<Vec<f64>> {
        let Some(size) = self.spectra.first().map(Vec::len) else {
            return Vec::new();
        };
        // The circulant's first column: g, then g mirrored (zero between).
        let mut c = vec![(0.0, 0.0); size];
        for (k, v) in g.iter().enumerate().take(self.n) {
            c[k].0 = *v;
            if k > 0 {
                c[size - k].0 = *v;
            }
        }
        fft(&mut c, false);
        self.spectra
            .iter()
            .map(|x| {
                let mut v: Vec<(f64, f64)> = x
                    .iter()
                    .zip(&c)
                    .map(|(a, b)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0))
                    .collect();
                fft(&mut v, true);
                v[..self.n].iter().map(|z| z.0 / size as f64).collect()
            })
            .collect()
    }
}

/// In-place radix-2 transform of a power-of-two length; `inverse` conjugates the twiddles
/// (the caller divides by the length).
fn fft(a: &mut [(f64, f64)], inverse: bool) {
    let n = a.len();
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            a.swap(i, j);
        }
    }
    let sign = if inverse { 1.0 } else { -1.0 };
    let mut len = 2;
    while len <= n {
        let ang = sign * core::f64::consts::TAU / len as f64;
        let twiddles: Vec<(f64, f64)> = (0..len / 2).map(|k| (ang * k as f64).sin_cos()).collect();
        for start in (0..n).step_by(len) {
            for (k, &(s, c)) in twiddles.iter().enumerate() {
                let (u, v) = (a[start + k], a[start + k + len / 2]);
                let t = (v.0 * c - v.1 * s, v.0 * s + v.1 * c);
                a[start + k] = (u.0 + t.0, u.1 + t.1);
                a[start + k + len / 2] = (u.0 - t.0, u.1 - t.1);
            }
        }
        len <<= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equals_the_direct_product() {
        for n in [1usize, 2, 3, 7, 64, 100] {
            let g: Vec<f64> = (0..n).map(|k| 1.0 / (1.0 + k as f64) - 0.01 * k as f64).collect();
            let x: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
            let direct: Vec<f64> = (0..n).map(|i| (0..n).map(|j| g[i.abs_diff(j)] * x[j]).sum()).collect();
            let fast = Vectors::of(std::slice::from_ref(&x)).times(&g);
            for (a, b) in fast[0].iter().zip(&direct) {
                assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "n {n}: {a} vs {b}");
            }
        }
    }
}
