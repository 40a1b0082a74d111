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

use crate::banded::{self, by_width};
use crate::bspline::{self, MAX_DEGREE};
use crate::butterworth::check_samples;
use crate::error::{check_len, check_weights, Error, Result};

/// A reusable fitting workspace for up to `capacity` samples at one degree. All buffers are sized
/// at construction; [`SmoothingSpline::set_abscissae`] and [`SmoothingSpline::fit`] never allocate.
///
/// ```
/// use torso_core::SmoothingSpline;
/// let x: Vec<f64> = (0..20).map(|k| k as f64).collect();
/// let y: Vec<f64> = x.iter().map(|t| 2.0 * t + 1.0).collect();
/// let mut spline = SmoothingSpline::new(3, 20).unwrap();
/// spline.set_abscissae(&x).unwrap();
/// let mut coeffs = vec![0.0; spline.coefficient_count()];
/// spline.fit(&vec![1.0; 20], 1.0, &y, &mut coeffs).unwrap();
/// // A straight line has no curvature to penalise: the fit is the line.
/// assert!((spline.evaluate(&coeffs, 7.5) - 16.0).abs() < 1e-9);
/// ```
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
    /// `A⁻¹ a_k` for the end-derivative map, `N + 1` vectors of `m`.
    solved: Vec<f64>,
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
            solved: vec![0.0; m * (degree + 1)],
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
        let n = self.n;
        self.check_fit_inputs(weights, lam)?;
        if ys.is_empty() || ys.len() % n != 0 {
            return Err(Error::LengthMismatch {
                name: "y",
                expected: n,
                got: ys.len(),
            });
        }
        check_samples("y", ys)?;
        let (p, k, m) = (self.degree, ys.len() / n, self.coefficient_count());
        check_len("coeffs", coeffs.len(), k * m)?;
        self.factor_normal_matrix(weights, lam)?;
        // BᵀW y, one component at a time so every access is contiguous.
        let coeffs = &mut coeffs[..k * m];
        coeffs.fill(0.0);
        for (y, rhs) in ys.chunks_exact(n).zip(coeffs.chunks_exact_mut(m)) {
            for (((&w, &yi), &span), v) in weights
                .iter()
                .zip(y)
                .zip(&self.spans[..n])
                .zip(self.colloc.chunks_exact(p + 1))
            {
                let wy = w * yi;
                for (r, &vr) in v.iter().enumerate() {
                    rhs[span - p + r] += wy * vr;
                }
            }
        }
        banded::solve_many(&self.band, m, p, coeffs, k);
        // Samples within ±MAX_SAMPLE with weights and λ large enough can still overflow the
        // normal equations: said, not given out as a fit.
        if let Some(index) = coeffs.iter().position(|c| !c.is_finite()) {
            return Err(Error::NonFinite {
                name: "coefficients (the fit overflowed: weights or y too large)",
                index,
            });
        }
        Ok(())
    }

    /// The linear map from data to end derivatives: after this call, `map[k * n + i]` holds
    /// `h_k[i]` such that the fit to any `y` with these weights and λ has
    /// `f^(k)(x_last) = Σ_i h_k[i] y_i` for `k = 0..=N`. `map` has `(N + 1) · n` entries.
    ///
    /// `f^(k)(x_last) = a_kᵀ c` with `a_k` the basis derivatives at the last sample and
    /// `c = A⁻¹ BᵀW y`, so `h_k = W B A⁻¹ a_k`: N + 1 banded solves, however many components
    /// share the weights, and the components then cost one dot product per derivative. A
    /// forecast needs nothing but these derivatives.
    pub fn end_derivative_map(&mut self, weights: &[f64], lam: f64, map: &mut [f64]) -> Result<()> {
        let (n, p) = (self.n, self.degree);
        self.check_fit_inputs(weights, lam)?;
        check_len("map", map.len(), (p + 1) * n)?;
        self.factor_normal_matrix(weights, lam)?;
        let m = self.coefficient_count();
        let (span, ders) = self.end_basis();
        let solved = &mut self.solved[..(p + 1) * m];
        solved.fill(0.0);
        for (k, u) in solved.chunks_exact_mut(m).enumerate() {
            u[span - p..=span].copy_from_slice(&ders[k][..=p]);
        }
        banded::solve_many_from(&self.band, m, p, solved, p + 1, span - p);
        for (h, u) in map.chunks_exact_mut(n).zip(solved.chunks_exact(m)) {
            by_width!(
                p,
                weighted_basis_products(h, u, weights, &self.spans, &self.colloc)
            );
        }
        Ok(())
    }

    /// Argument checks shared by the fits (the data are checked by the caller).
    fn check_fit_inputs(&self, weights: &[f64], lam: f64) -> Result<()> {
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
        Ok(())
    }

    /// Assembles `BᵀWB + λΩ` in `self.band` and factors it in place.
    fn factor_normal_matrix(&mut self, weights: &[f64], lam: f64) -> Result<()> {
        let (n, p) = (self.n, self.degree);
        let m = self.coefficient_count();
        let w1 = p + 1;
        let band = &mut self.band[..m * w1];
        for (b, &pen) in band.iter_mut().zip(&self.penalty[..m * w1]) {
            *b = lam * pen;
        }
        by_width!(p, add_gram(band, weights, &self.spans[..n], &self.colloc));
        banded::factor(band, m, p)
    }

    /// The last knot span and the basis derivatives of orders `0..=N` at the last sample, where
    /// the forecast's polynomial continuation starts: `ders[k][j]` belongs to coefficient
    /// `span - N + j`.
    fn end_basis(&self) -> (usize, [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1]) {
        let (p, knots) = (self.degree, self.knots());
        let span = bspline::last_span(knots, p);
        // Degree 0 carries one knot past the last sample; every other degree ends on it.
        let t_end = knots[knots.len() - if p == 0 { 2 } else { 1 }];
        let mut ders = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        bspline::basis_derivatives(knots, p, span, t_end, p, &mut ders);
        (span, ders)
    }

    /// Value of the fitted spline at `t` (polynomial continuation outside the samples).
    pub fn evaluate(&self, coeffs: &[f64], t: f64) -> f64 {
        bspline::evaluate(self.knots(), self.degree, coeffs, t)
    }

    /// Derivatives `f^(k)(x_last)` for `k = 0..=N` of the last polynomial piece at the last
    /// sample: with them, `f(x_last + τ) = Σ_k f^(k) τ^k / k!` is the polynomial continuation.
    pub fn end_derivatives(&self, coeffs: &[f64], out: &mut [f64; MAX_DEGREE + 1]) {
        let p = self.degree;
        let (span, ders) = self.end_basis();
        out.fill(0.0);
        for (k, o) in out.iter_mut().enumerate().take(p + 1) {
            *o = (0..=p).map(|j| coeffs[span - p + j] * ders[k][j]).sum();
        }
    }
}

/// Adds `BᵀWB` to `band` (half-bandwidth `W - 1`): sample `i` touches the `W` basis functions
/// ending at `spans[i]`, with values `colloc[i * W..]`.
fn add_gram<const W: usize>(band: &mut [f64], weights: &[f64], spans: &[usize], colloc: &[f64]) {
    for ((&w, &span), v) in weights.iter().zip(spans).zip(colloc.chunks_exact(W)) {
        if w == 0.0 {
            continue;
        }
        let v: &[f64; W] = v.try_into().expect("chunks of W");
        let first = span + 1 - W;
        let rows: &mut [f64] = &mut band[first * W..(first + W) * W];
        for r in 0..W {
            let wv = w * v[r];
            for c in 0..=r {
                rows[r * W + r - c] += wv * v[c];
            }
        }
    }
}

/// `h[i] = w_i Σ_r B_{span_i - W + 1 + r}(x_i) u[span_i - W + 1 + r]`, i.e. `h = W B u`.
fn weighted_basis_products<const W: usize>(
    h: &mut [f64],
    u: &[f64],
    weights: &[f64],
    spans: &[usize],
    colloc: &[f64],
) {
    for (((hi, &w), &span), v) in h
        .iter_mut()
        .zip(weights)
        .zip(spans)
        .zip(colloc.chunks_exact(W))
    {
        let v: &[f64; W] = v.try_into().expect("chunks of W");
        let u: &[f64; W] = u[span + 1 - W..=span].try_into().expect("W coefficients");
        let mut sum = 0.0;
        for r in 0..W {
            sum += v[r] * u[r];
        }
        *hi = w * sum;
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
        // As λ → ∞ the cubic smoothing spline tends to the straight-line least-squares fit; at
        // λ = 1e6 SciPy is 1e-7 from it, and beyond, the normal equations lose digits to conditioning.
        let x: Vec<f64> = (0..12).map(|i| i as f64 * 0.5).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|t| 0.3 * t - 1.0 + (3.0 * t).sin() * 0.2)
            .collect();
        let (knots, c) = fit_smoothing_spline(&x, &y, None, 1e6, 3).unwrap();
        let n = x.len() as f64;
        let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
        let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
        let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
        let slope = sxy / sxx;
        for &t in &[0.0, 2.2, 5.5] {
            let line = my + slope * (t - mx);
            let got = bspline::evaluate(&knots, 3, &c, t);
            assert!((got - line).abs() < 1e-6, "t {t}: {got} vs {line}");
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
    fn end_derivative_map_equals_fitting_then_differentiating() {
        let x: Vec<f64> = (0..11).map(|i| 0.3 * i as f64).collect();
        let y: Vec<f64> = x.iter().map(|t| (1.3 * t).sin() + 0.2 * t * t).collect();
        let w: Vec<f64> = (0..11).map(|i| 0.5 + (i % 3) as f64 * 0.7).collect();
        for degree in 0..=4 {
            let mut s = SmoothingSpline::new(degree, 11).unwrap();
            s.set_abscissae(&x).unwrap();
            let mut c = vec![0.0; s.coefficient_count()];
            s.fit(&w, 0.2, &y, &mut c).unwrap();
            let mut expected = [0.0; MAX_DEGREE + 1];
            s.end_derivatives(&c, &mut expected);
            let mut map = vec![0.0; (degree + 1) * 11];
            s.end_derivative_map(&w, 0.2, &mut map).unwrap();
            for k in 0..=degree {
                let got: f64 = map[k * 11..(k + 1) * 11]
                    .iter()
                    .zip(&y)
                    .map(|(h, v)| h * v)
                    .sum();
                let tolerance = 1e-9 * (1.0 + expected[k].abs());
                assert!(
                    (got - expected[k]).abs() < tolerance,
                    "degree {degree}, k {k}"
                );
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
