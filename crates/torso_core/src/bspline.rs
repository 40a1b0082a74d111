//! B-spline bases with knots at the samples (thesis eqs. 3.5 to 3.9) and the roughness-penalty
//! Gram matrix `Ω_jk = ∫ B_j''(t) B_k''(t) dt` of eq. 3.10.
//!
//! Knot rule. For degree `N ≥ 1` the knots are the sample abscissae with each end repeated `N`
//! more times (`N + 1` in all), as in `scipy.interpolate.make_smoothing_spline` for `N = 3`:
//! `n` samples give `n + N - 1` basis functions. Degree 0 has one constant piece per sample (the
//! last piece extends one sample step past the end), so its fit is the data itself and its
//! forecast the last value: the thesis' "N = 0" row equals Const.

use crate::error::{Error, Result};

/// Highest supported spline degree. Fixed so that every per-frame temporary lives on the stack.
/// Higher degrees are refused because they cannot be extrapolated in double precision: 2 s (50
/// samples) ahead, rounding in the N-th derivative is multiplied by 50^N / N!, which for N = 5
/// turned a constant input into a forecast 2e-6 off (measured; N = 4: 4e-9).
pub const MAX_DEGREE: usize = 4;

/// Number of knots for `n_samples` samples at degree `degree`.
pub fn knot_count(n_samples: usize, degree: usize) -> usize {
    if degree == 0 {
        n_samples + 1
    } else {
        n_samples + 2 * degree
    }
}

/// Number of basis functions (spline coefficients) for `n_samples` samples.
pub fn basis_count(n_samples: usize, degree: usize) -> usize {
    knot_count(n_samples, degree) - degree - 1
}

/// The fewest samples a fit of this degree accepts: a constant needs one, anything else two
/// (the roughness penalty decides the remaining freedom).
pub fn min_samples(degree: usize) -> usize {
    if degree == 0 {
        1
    } else {
        2
    }
}

/// Writes the knot vector for abscissae `x` (strictly increasing, finite) into `knots`.
pub fn knots_at_samples(x: &[f64], degree: usize, knots: &mut [f64]) -> Result<()> {
    check_abscissae(x, degree)?;
    let n = x.len();
    let count = knot_count(n, degree);
    if knots.len() < count {
        return Err(Error::LengthMismatch {
            name: "knots",
            expected: count,
            got: knots.len(),
        });
    }
    if degree == 0 {
        knots[..n].copy_from_slice(x);
        let step = if n > 1 { x[n - 1] - x[n - 2] } else { 1.0 };
        knots[n] = x[n - 1] + step;
    } else {
        knots[..degree].fill(x[0]);
        knots[degree..degree + n].copy_from_slice(x);
        knots[degree + n..count].fill(x[n - 1]);
    }
    Ok(())
}

/// Checks degree, sample count and that `x` is finite and strictly increasing.
pub fn check_abscissae(x: &[f64], degree: usize) -> Result<()> {
    if degree > MAX_DEGREE {
        return Err(Error::InvalidArgument {
            name: "degree",
            expected: "a spline degree from 0 to 4",
            value: degree as f64,
        });
    }
    if x.len() < min_samples(degree) {
        return Err(Error::NotEnoughHistory {
            have: x.len(),
            need: min_samples(degree),
        });
    }
    for (i, pair) in x.windows(2).enumerate() {
        if !(pair[1] > pair[0]) {
            return Err(Error::InvalidArgument {
                name: "x",
                expected: "strictly increasing sample abscissae",
                value: pair[1],
            });
        }
        if !pair[1].is_finite() {
            return Err(Error::NonFinite {
                name: "x",
                index: i + 1,
            });
        }
    }
    if !x[0].is_finite() {
        return Err(Error::NonFinite {
            name: "x",
            index: 0,
        });
    }
    Ok(())
}

/// The knot span `s` (with `knots[s] ≤ t < knots[s + 1]`) used to evaluate at `t`. Points before
/// the first or after the last span use the end spans: that is polynomial continuation, the
/// extrapolation of `scipy.interpolate.BSpline(extrapolate=True)`.
pub fn find_span(knots: &[f64], degree: usize, t: f64) -> usize {
    let m = knots.len() - degree - 1; // basis count
    if t >= knots[m] {
        return last_span(knots, degree);
    }
    if t <= knots[degree] {
        return first_span(knots, degree);
    }
    // Binary search in [degree, m): knots[lo] <= t < knots[hi].
    let (mut lo, mut hi) = (degree, m);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if t < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

/// The last span of non-zero length (the one that holds the last sample).
pub fn last_span(knots: &[f64], degree: usize) -> usize {
    let mut s = knots.len() - degree - 2;
    while s > degree && knots[s] >= knots[s + 1] {
        s -= 1;
    }
    s
}

fn first_span(knots: &[f64], degree: usize) -> usize {
    let m = knots.len() - degree - 1;
    let mut s = degree;
    while s + 1 < m && knots[s] >= knots[s + 1] {
        s += 1;
    }
    s
}

/// Values and derivatives of the `degree + 1` basis functions that are non-zero on span `span`,
/// evaluated at `t` (The NURBS Book, algorithm A2.3). `ders[k][j]` is the `k`-th derivative of
/// `B_{span - degree + j}`; derivatives above `n_deriv` are left untouched.
pub fn basis_derivatives(
    knots: &[f64],
    degree: usize,
    span: usize,
    t: f64,
    n_deriv: usize,
    ders: &mut [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1],
) {
    const W: usize = MAX_DEGREE + 1;
    let p = degree;
    let mut ndu = [[0.0f64; W]; W];
    let mut left = [0.0f64; W];
    let mut right = [0.0f64; W];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let n_deriv = n_deriv.min(p);
    let mut a = [[0.0f64; W]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=n_deriv {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=n_deriv {
        for j in 0..=p {
            ders[k][j] *= factor;
        }
        factor *= (p - k) as f64;
    }
}

/// Gauss-Legendre nodes and weights on [-1, 1] with `q` points (exact for degree `2q - 1`).
fn gauss_legendre(q: usize) -> (&'static [f64], &'static [f64]) {
    const X1: [f64; 1] = [0.0];
    const W1: [f64; 1] = [2.0];
    const X2: [f64; 2] = [-0.577_350_269_189_625_8, 0.577_350_269_189_625_8];
    const W2: [f64; 2] = [1.0, 1.0];
    const X3: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W3: [f64; 3] = [
        0.555_555_555_555_556,
        0.888_888_888_888_889,
        0.555_555_555_555_556,
    ];
    const X4: [f64; 4] = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    const W4: [f64; 4] = [
        0.347_854_845_137_453_85,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_85,
    ];
    match q {
        0 | 1 => (&X1, &W1),
        2 => (&X2, &W2),
        3 => (&X3, &W3),
        _ => (&X4, &W4),
    }
}

/// Adds `scale · Ω` into a lower band (half-bandwidth `degree`) of `basis_count` rows, where
/// `Ω_jk = ∫ B_j'' B_k''` over the knot range. Exact: on each span `B''` is a polynomial of degree
/// `N - 2`, integrated by Gauss-Legendre with `N - 1` points. Zero for `N ≤ 1`.
pub fn add_penalty(knots: &[f64], degree: usize, scale: f64, band: &mut [f64]) {
    if degree < 2 || scale == 0.0 {
        return;
    }
    let p = degree;
    let m = knots.len() - degree - 1;
    let (nodes, weights) = gauss_legendre(degree - 1);
    let mut ders = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    for span in degree..m {
        let (a, b) = (knots[span], knots[span + 1]);
        if b <= a {
            continue;
        }
        let half = 0.5 * (b - a);
        for (x, w) in nodes.iter().zip(weights) {
            let t = a + half * (x + 1.0);
            basis_derivatives(knots, degree, span, t, 2, &mut ders);
            for r in 0..=p {
                for c in 0..=r {
                    let (i, j) = (span - p + r, span - p + c);
                    band[crate::banded::at(i, j, p)] += scale * half * w * ders[2][r] * ders[2][c];
                }
            }
        }
    }
}

/// Evaluates the spline with coefficients `coeffs` at `t` (polynomial continuation outside).
pub fn evaluate(knots: &[f64], degree: usize, coeffs: &[f64], t: f64) -> f64 {
    let span = find_span(knots, degree, t);
    let mut ders = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    basis_derivatives(knots, degree, span, t, 0, &mut ders);
    (0..=degree)
        .map(|j| coeffs[span - degree + j] * ders[0][j])
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knots(x: &[f64], degree: usize) -> Vec<f64> {
        let mut k = vec![0.0; knot_count(x.len(), degree)];
        knots_at_samples(x, degree, &mut k).unwrap();
        k
    }

    #[test]
    fn basis_is_a_partition_of_unity_with_zero_derivative_sum() {
        let x = [0.0, 0.4, 1.1, 1.5, 2.7, 3.0];
        for degree in 1..=MAX_DEGREE {
            let k = knots(&x, degree);
            let mut ders = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
            for &t in &[0.0, 0.2, 1.3, 2.999, 3.0] {
                let span = find_span(&k, degree, t);
                basis_derivatives(&k, degree, span, t, degree, &mut ders);
                let sum: f64 = ders[0][..=degree].iter().sum();
                assert!((sum - 1.0).abs() < 1e-13, "degree {degree} t {t}: {sum}");
                for d in 1..=degree {
                    let s: f64 = ders[d][..=degree].iter().sum();
                    assert!(s.abs() < 1e-9, "degree {degree} derivative {d}: {s}");
                }
            }
        }
    }

    #[test]
    fn reproduces_a_polynomial_of_its_degree() {
        // Marsden's identity: a cubic B-spline space holds every cubic. Coefficients of t³ are the
        // symmetric products of three consecutive interior knots; check value and derivatives.
        let x = [0.0, 0.5, 1.25, 2.0, 3.5];
        let k = knots(&x, 3);
        let m = basis_count(x.len(), 3);
        let coeffs: Vec<f64> = (0..m).map(|i| k[i + 1] * k[i + 2] * k[i + 3]).collect();
        for &t in &[0.1, 1.0, 3.4, 4.0] {
            let v = evaluate(&k, 3, &coeffs, t);
            assert!((v - t * t * t).abs() < 1e-12, "t {t}: {v}");
        }
    }

    #[test]
    fn cubic_penalty_of_a_quadratic_is_its_curvature_squared() {
        // f(t) = t² has f'' = 2, so ∫ f''² over [0, L] = 4 L; with coefficients from Marsden's
        // identity the quadratic form cᵀΩc must give exactly that.
        let x = [0.0, 0.3, 0.9, 1.0, 1.7, 2.5];
        let degree = 3;
        let k = knots(&x, degree);
        let m = basis_count(x.len(), degree);
        // Coefficients of t² in the cubic basis: mean of pairwise products of the 3 inner knots.
        let c: Vec<f64> = (0..m)
            .map(|i| (k[i + 1] * k[i + 2] + k[i + 1] * k[i + 3] + k[i + 2] * k[i + 3]) / 3.0)
            .collect();
        let p = degree;
        let mut band = vec![0.0; m * (p + 1)];
        add_penalty(&k, degree, 1.0, &mut band);
        let mut q = 0.0;
        for i in 0..m {
            for j in i.saturating_sub(p)..=i {
                let v = band[crate::banded::at(i, j, p)];
                q += if i == j {
                    v * c[i] * c[i]
                } else {
                    2.0 * v * c[i] * c[j]
                };
            }
        }
        assert!((q - 4.0 * 2.5).abs() < 1e-10, "{q}");
    }

    #[test]
    fn degree_zero_owns_one_piece_per_sample() {
        let x = [0.0, 1.0, 2.0];
        let k = knots(&x, 0);
        assert_eq!(k, vec![0.0, 1.0, 2.0, 3.0]);
        let c = [5.0, 6.0, 7.0];
        assert_eq!(evaluate(&k, 0, &c, 2.0), 7.0);
        assert_eq!(evaluate(&k, 0, &c, 10.0), 7.0);
        assert_eq!(evaluate(&k, 0, &c, 1.5), 6.0);
    }

    #[test]
    fn rejects_bad_abscissae() {
        assert!(matches!(
            check_abscissae(&[0.0, 0.0, 1.0], 1),
            Err(Error::InvalidArgument { name: "x", .. })
        ));
        assert!(matches!(
            check_abscissae(&[0.0, f64::INFINITY], 1),
            Err(Error::InvalidArgument { .. }) | Err(Error::NonFinite { .. })
        ));
        assert_eq!(
            check_abscissae(&[1.0], 1),
            Err(Error::NotEnoughHistory { have: 1, need: 2 })
        );
        assert!(check_abscissae(&[0.0, 1.0], 6).is_err());
    }
}
