//! Penalised B-spline smoothing (thesis eqs. 3.10 to 3.12):
//!
//! `min_c Σ_i w_i (y_i - Σ_j c_j B_j(x_i))² + λ ∫ (Σ_j c_j B_j''(t))² dt`
//!
//! solved through the normal equations `(BᵀWB + λΩ) c = BᵀW y`, assembled as a band of
//! half-bandwidth `N` and factored once by [`crate::banded`]; the factor then serves every
//! component that shares the weights (the five pose components of a frame).
//!
//! For `N = 3` the minimiser over the knots-at-samples cubic space is the natural smoothing
//! spline, i.e. `scipy.interpolate.make_smoothing_spline(x, y, w, lam)`. For `N ≤ 1` the penalty
//! vanishes and the fit interpolates the samples, as the thesis notes.

use crate::banded;
use crate::bspline::{self, MAX_DEGREE};
use crate::error::{check_len, check_weights, Error, Result};

/// A reusable fitting workspace for up to `capacity` samples at one degree. All buffers are sized
/// at construction; [`SmoothingSpline::set_abscissae`] and [`SmoothingSpline::fit`] never allocate.
#[derive(Clone, Debug)]
pub struct SmoothingSpline {
    degree: usize,
    capacity: usize,
    n: usize,
    knots: Vec<f64>,
    /// Basis values at each sample: `colloc[i * (N + 1) + r]` is `B_{span_i - N + r}(x_i)`.
    colloc: Vec<f64>,
    spans: Vec<usize>,
    /// λ-free penalty band `Ω` for the current abscissae.
    penalty: Vec<f64>,
    /// Working band: normal matrix, then its Cholesky factor.
    band: Vec<f64>,
}

impl SmoothingSpline {
    /// A workspace for fits of `degree` (0 to [`MAX_DEGREE`]) to at most `capacity` samples.
    pub fn new(degree: usize, capacity: usize) -> Result<Self> {
        if degree > MAX_DEGREE {
            return Err(Error::InvalidArgument {
                name: "degree",
                expected: "a spline degree from 0 to 4",
                value: degree as f64,
            });
        }
        if capacity < bspline::min_samples(degree) {
            return Err(Error::InvalidArgument {
                name: "capacity",
                expected: "room for at least the samples the degree needs",
                value: capacity as f64,
            });
        }
        let m = bspline::basis_count(capacity, degree);
        Ok(Self {
            degree,
            capacity,
            n: 0,
            knots: vec![0.0; bspline::knot_count(capacity, degree)],
            colloc: vec![0.0; capacity * (degree + 1)],
            spans: vec![0; capacity],
            penalty: vec![0.0; m * (degree + 1)],
            band: vec![0.0; m * (degree + 1)],
        })
    }

    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Number of samples of the current abscissae (0 before the first call).
    pub fn sample_count(&self) -> usize {
        self.n
    }

    /// Number of spline coefficients for the current abscissae.
    pub fn coefficient_count(&self) -> usize {
        if self.n == 0 {
            0
        } else {
            bspline::basis_count(self.n, self.degree)
        }
    }

    /// The knot vector for the current abscissae.
    pub fn knots(&self) -> &[f64] {
        &self.knots[..bspline::knot_count(self.n.max(1), self.degree).min(self.knots.len())]
    }

    /// Sets the sample abscissae (knots) and precomputes the basis values and `Ω` for them.
    pub fn set_abscissae(&mut self, x: &[f64]) -> Result<()> {
        if x.len() > self.capacity {
            return Err(Error::LengthMismatch {
                name: "x",
                expected: self.capacity,
                got: x.len(),
            });
        }
        bspline::knots_at_samples(x, self.degree, &mut self.knots)?;
        let n = x.len();
        let p = self.degree;
        let knots = &self.knots[..bspline::knot_count(n, p)];
        let mut ders = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        for (i, &t) in x.iter().enumerate() {
            let span = bspline::find_span(knots, p, t);
            bspline::basis_derivatives(knots, p, span, t, 0, &mut ders);
            self.spans[i] = span;
            self.colloc[i * (p + 1)..(i + 1) * (p + 1)].copy_from_slice(&ders[0][..=p]);
        }
        let m = bspline::basis_count(n, p);
        let penalty = &mut self.penalty[..m * (p + 1)];
        penalty.fill(0.0);
        bspline::add_penalty(knots, p, 1.0, penalty);
        self.n = n;
        Ok(())
    }

    /// Fits `k = ys.len() / n` components at once. `ys` is component-major (`ys[c * n + i]`),
    /// `weights` has one entry per sample, and the coefficients go to `coeffs[c * m + j]`.
    pub fn fit(&mut self, weights: &[f64], lam: f64, ys: &[f64], coeffs: &mut [f64]) -> Result<()> {
        let (n, p) = (self.n, self.degree);
        if n == 0 {
            return Err(Error::NotEnoughHistory {
                have: 0,
                need: bspline::min_samples(p),
            });
        }
        check_len("weights", weights.len(), n)?;
        check_weights("weights", weights)?;
        if !(lam.is_finite() && lam >= 0.0) {
            return Err(Error::InvalidArgument {
                name: "lam",
                expected: "a finite, non-negative smoothing weight",
                value: lam,
            });
        }
        if p >= 2 && lam == 0.0 {
            return Err(Error::InvalidArgument {
                name: "lam",
                expected: "lam > 0 for degree >= 2 (with knots at the samples the fit is under-determined without the penalty)",
                value: lam,
            });
        }
        if ys.is_empty() || ys.len() % n != 0 {
            return Err(Error::LengthMismatch {
                name: "y",
                expected: n,
                got: ys.len(),
            });
        }
        if let Some(index) = ys.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite { name: "y", index });
        }
        let k = ys.len() / n;
        let m = bspline::basis_count(n, p);
        check_len("coeffs", coeffs.len(), k * m)?;

        let w1 = p + 1;
        let band = &mut self.band[..m * w1];
        for (b, &pen) in band.iter_mut().zip(&self.penalty[..m * w1]) {
            *b = lam * pen;
        }
        // BᵀWB: sample i touches basis functions span_i - p ..= span_i.
        for ((&w, &span), v) in weights
            .iter()
            .zip(&self.spans[..n])
            .zip(self.colloc.chunks_exact(w1))
        {
            if w == 0.0 {
                continue;
            }
            let first = span - p;
            for r in 0..=p {
                let row = &mut band[(first + r) * w1..(first + r + 1) * w1];
                let wv = w * v[r];
                for c in 0..=r {
                    row[r - c] += wv * v[c];
                }
            }
        }
        // BᵀW y, one component at a time so every access is contiguous.
        let coeffs = &mut coeffs[..k * m];
        coeffs.fill(0.0);
        for (y, rhs) in ys.chunks_exact(n).zip(coeffs.chunks_exact_mut(m)) {
            for (((&w, &yi), &span), v) in weights
                .iter()
                .zip(y)
                .zip(&self.spans[..n])
                .zip(self.colloc.chunks_exact(w1))
            {
                let wy = w * yi;
                for (r, &vr) in v.iter().enumerate() {
                    rhs[span - p + r] += wy * vr;
                }
            }
        }
        banded::factor(band, m, p)?;
        banded::solve_many(band, m, p, coeffs, k);
        Ok(())
    }

    /// Value of the fitted spline at `t` (polynomial continuation outside the samples).
    pub fn evaluate(&self, coeffs: &[f64], t: f64) -> f64 {
        bspline::evaluate(self.knots(), self.degree, coeffs, t)
    }

    /// Derivatives `f^(k)(x_last)` for `k = 0..=N` of the last polynomial piece at the last
    /// sample: with them, `f(x_last + τ) = Σ_k f^(k) τ^k / k!` is the polynomial continuation.
    pub fn end_derivatives(&self, coeffs: &[f64], out: &mut [f64; MAX_DEGREE + 1]) {
        let p = self.degree;
        let knots = self.knots();
        let span = bspline::last_span(knots, p);
        // Degree 0 carries one knot past the last sample; every other degree ends on it.
        let t_end = knots[knots.len() - if p == 0 { 2 } else { 1 }];
        let mut ders = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        bspline::basis_derivatives(knots, p, span, t_end, p, &mut ders);
        out.fill(0.0);
        for (k, o) in out.iter_mut().enumerate().take(p + 1) {
            *o = (0..=p).map(|j| coeffs[span - p + j] * ders[k][j]).sum();
        }
    }
}

/// One-off convenience: fits a single component with knots at `x` and returns
/// `(knots, coefficients)`. Allocates; per-frame code keeps a [`SmoothingSpline`] instead.
pub fn fit_smoothing_spline(
    x: &[f64],
    y: &[f64],
    weights: Option<&[f64]>,
    lam: f64,
    degree: usize,
) -> Result<(Vec<f64>, Vec<f64>)> {
    check_len("y", y.len(), x.len())?;
    let mut spline = SmoothingSpline::new(degree, x.len().max(bspline::min_samples(degree)))?;
    spline.set_abscissae(x)?;
    let ones;
    let w = match weights {
        Some(w) => w,
        None => {
            ones = vec![1.0; x.len()];
            &ones
        }
    };
    let mut coeffs = vec![0.0; spline.coefficient_count()];
    spline.fit(w, lam, y, &mut coeffs)?;
    Ok((spline.knots().to_vec(), coeffs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degree_one_interpolates_and_continues_the_last_segment() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [1.0, 3.0, 2.0, 5.0];
        let (knots, c) = fit_smoothing_spline(&x, &y, None, 1.0, 1).unwrap();
        for (xi, yi) in x.iter().zip(&y) {
            assert!((bspline::evaluate(&knots, 1, &c, *xi) - yi).abs() < 1e-12);
        }
        // The last segment has slope 3: one step ahead is 8.
        assert!((bspline::evaluate(&knots, 1, &c, 4.0) - 8.0).abs() < 1e-12);
    }

    #[test]
    fn huge_lambda_tends_to_the_weighted_least_squares_line() {
        // As λ → ∞ the cubic smoothing spline tends to the straight-line least-squares fit.
        let x: Vec<f64> = (0..12).map(|i| i as f64 * 0.5).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|t| 0.3 * t - 1.0 + (3.0 * t).sin() * 0.2)
            .collect();
        let (knots, c) = fit_smoothing_spline(&x, &y, None, 1e9, 3).unwrap();
        let n = x.len() as f64;
        let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
        let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
        let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
        let slope = sxy / sxx;
        for &t in &[0.0, 2.2, 5.5] {
            let line = my + slope * (t - mx);
            assert!((bspline::evaluate(&knots, 3, &c, t) - line).abs() < 1e-5);
        }
    }

    #[test]
    fn end_derivatives_continue_the_last_piece() {
        let x: Vec<f64> = (0..9).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|t| (0.7 * t).cos()).collect();
        for degree in 0..=4 {
            let mut s = SmoothingSpline::new(degree, 9).unwrap();
            s.set_abscissae(&x).unwrap();
            let mut c = vec![0.0; s.coefficient_count()];
            s.fit(&[1.0; 9], 0.5, &y, &mut c).unwrap();
            let mut d = [0.0; MAX_DEGREE + 1];
            s.end_derivatives(&c, &mut d);
            for tau in [0.0f64, 0.5, 3.0] {
                let mut taylor = 0.0;
                let mut fact = 1.0;
                for (k, dk) in d.iter().enumerate().take(degree + 1) {
                    if k > 0 {
                        fact *= k as f64;
                    }
                    taylor += dk * tau.powi(k as i32) / fact;
                }
                let direct = s.evaluate(&c, 8.0 + tau);
                assert!((taylor - direct).abs() < 1e-10, "degree {degree} tau {tau}");
            }
        }
    }

    #[test]
    fn rejects_zero_lambda_for_quadratic_and_bad_weights() {
        let x = [0.0, 1.0, 2.0];
        assert!(matches!(
            fit_smoothing_spline(&x, &[1.0, 2.0, 3.0], None, 0.0, 2),
            Err(Error::InvalidArgument { name: "lam", .. })
        ));
        assert!(matches!(
            fit_smoothing_spline(&x, &[1.0, 2.0, 3.0], Some(&[1.0, -1.0, 1.0]), 1.0, 3),
            Err(Error::InvalidArgument {
                name: "weights",
                ..
            })
        ));
        assert!(matches!(
            fit_smoothing_spline(&x, &[1.0, 2.0, 3.0], Some(&[0.0, 0.0, 0.0]), 1.0, 3),
            Err(Error::NotPositiveDefinite { .. })
        ));
        assert!(matches!(
            fit_smoothing_spline(&x, &[1.0, f64::NAN, 3.0], None, 1.0, 3),
            Err(Error::NonFinite {
                name: "y",
                index: 1
            })
        ));
    }
}
