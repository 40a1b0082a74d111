//! Cholesky factorisation and solve for symmetric positive-definite band matrices.
//!
//! The spline normal equations `(BᵀWB + λΩ) c = BᵀW y` (thesis eq. 3.12) couple each coefficient
//! with its `p` neighbours on either side only, so the `O(n p²)` band factorisation replaces the
//! `O(n³)` dense one. faer has no band solver; this one is written for that single purpose and
//! never allocates.
//!
//! Storage is "lower band, row-major": entry `A[i][j]` with `j ≤ i ≤ j + p` lives at
//! `band[i * (p + 1) + (i - j)]`, so `band[i * (p + 1)]` is the diagonal. After [`factor`], that
//! slot holds `1 / L_ii` instead of `L_ii`: the substitutions then multiply where they would
//! divide, and a division's latency sits on their critical path once per row.

use crate::error::{Error, Result};

/// Index of `A[i][j]` (`j ≤ i`, `i - j ≤ p`) in lower band storage.
#[inline(always)]
pub fn at(i: usize, j: usize, p: usize) -> usize {
    i * (p + 1) + (i - j)
}

/// Calls `f::<N + 1>(args)`: the per-sample loops below are generic over the basis width, so
/// they unroll and lose their bounds checks (at widths of 2 to 4, those cost as much as the
/// arithmetic).
macro_rules! by_width {
    ($degree:expr, $f:ident($($arg:expr),*)) => {
        match $degree {
            0 => $f::<1>($($arg),*),
            1 => $f::<2>($($arg),*),
            2 => $f::<3>($($arg),*),
            3 => $f::<4>($($arg),*),
            4 => $f::<5>($($arg),*),
            _ => unreachable!("degree is checked against MAX_DEGREE at construction"),
        }
    };
}
pub(crate) use by_width;

/// Overwrites the band of `A` (`n` rows, half-bandwidth `p`) with its Cholesky factor `L`
/// (`A = L Lᵀ`), diagonal stored as reciprocals. Fails when a pivot is not clearly positive,
/// relative to the original diagonal.
pub fn factor(band: &mut [f64], n: usize, p: usize) -> Result<()> {
    debug_assert!(band.len() >= n * (p + 1));
    by_width!(p, factor_width(&mut band[..n * (p + 1)], n))
}

fn factor_width<const W: usize>(band: &mut [f64], n: usize) -> Result<()> {
    let p = W - 1;
    for j in 0..n {
        let original = band[j * W];
        let mut s = original;
        for k in j.saturating_sub(p)..j {
            let l = band[at(j, k, p)];
            s -= l * l;
        }
        // A pivot eaten by cancellation down to rounding level means the matrix is singular in
        // floating point: refuse it rather than return coefficients amplified by 1e16.
        if !(s > 1e-13 * original.abs()) || !s.is_finite() {
            return Err(Error::NotPositiveDefinite { pivot: j });
        }
        let inverse = 1.0 / s.sqrt();
        band[j * W] = inverse;
        for i in (j + 1)..n.min(j + W) {
            let mut s = band[at(i, j, p)];
            for k in i.saturating_sub(p)..j {
                s -= band[at(i, k, p)] * band[at(j, k, p)];
            }
            band[at(i, j, p)] = s * inverse;
        }
    }
    Ok(())
}

/// Solves `L Lᵀ x = b` in place for one right-hand side, with `L` from [`factor`].
pub fn solve(factor: &[f64], n: usize, p: usize, b: &mut [f64]) {
    solve_many(factor, n, p, &mut b[..n], 1);
}

/// Solves `L Lᵀ X = B` in place for `k` right-hand sides stored one after another
/// (`b[c * n + i]`): one sweep over the factor serves them all.
pub fn solve_many(factor: &[f64], n: usize, p: usize, b: &mut [f64], k: usize) {
    solve_many_from(factor, n, p, b, k, 0);
}

/// [`solve_many`] for right-hand sides that are zero before row `first`: the forward sweep
/// leaves those rows zero, so it starts at `first`.
pub fn solve_many_from(factor: &[f64], n: usize, p: usize, b: &mut [f64], k: usize, first: usize) {
    by_width!(
        p,
        solve_width(&factor[..n * (p + 1)], n, &mut b[..k * n], first)
    )
}

fn solve_width<const W: usize>(factor: &[f64], n: usize, b: &mut [f64], first: usize) {
    let p = W - 1;
    // Forward: L z = b, row i of L is factor[i*W..] = [1/L_ii, L_i,i-1, ..., L_i,i-p].
    for i in first..n {
        let row: &[f64; W] = factor[i * W..(i + 1) * W].try_into().expect("W entries");
        let reach = p.min(i - first);
        for x in b.chunks_exact_mut(n) {
            let mut s = x[i];
            for d in 1..=reach {
                s -= row[d] * x[i - d];
            }
            x[i] = s * row[0];
        }
    }
    // Backward: Lᵀ x = z, column i of L below the diagonal is factor[(i+d)*W + d].
    for i in (0..n).rev() {
        let reach = p.min(n - 1 - i);
        let inverse = factor[i * W];
        for x in b.chunks_exact_mut(n) {
            let mut s = x[i];
            for d in 1..=reach {
                s -= factor[(i + d) * W + d] * x[i + d];
            }
            x[i] = s * inverse;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense reference: the band written out as a full matrix.
    fn dense(band: &[f64], n: usize, p: usize) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i.saturating_sub(p)..=i {
                a[i][j] = band[at(i, j, p)];
                a[j][i] = band[at(i, j, p)];
            }
        }
        a
    }

    #[test]
    fn solves_a_tridiagonal_system_exactly() {
        // The 1-D Laplacian plus identity: a well-known SPD band matrix with p = 1.
        let (n, p) = (7, 1);
        let mut band = vec![0.0; n * (p + 1)];
        for i in 0..n {
            band[at(i, i, p)] = 3.0;
            if i > 0 {
                band[at(i, i - 1, p)] = -1.0;
            }
        }
        let a = dense(&band, n, p);
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 0.5).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| a[i][j] * x_true[j]).sum())
            .collect();
        factor(&mut band, n, p).unwrap();
        solve(&band, n, p, &mut b);
        for i in 0..n {
            assert!(
                (b[i] - x_true[i]).abs() < 1e-13,
                "{i}: {} vs {}",
                b[i],
                x_true[i]
            );
        }
    }

    #[test]
    fn matches_faer_dense_cholesky_on_a_wide_band() {
        use faer::linalg::solvers::Solve;
        let (n, p) = (40, 4);
        let mut band = vec![0.0; n * (p + 1)];
        for i in 0..n {
            for j in i.saturating_sub(p)..=i {
                let d = (i - j) as f64;
                band[at(i, j, p)] = if i == j {
                    10.0 + (i as f64 * 0.37).cos()
                } else {
                    (0.3 * i as f64 + d).sin() / (1.0 + d)
                };
            }
        }
        let a = dense(&band, n, p);
        let fa = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i][j]);
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).exp().ln_1p()).collect();
        let fb = faer::Mat::<f64>::from_fn(n, 1, |i, _| rhs[i]);
        let reference = fa.llt(faer::Side::Lower).unwrap().solve(&fb);
        let mut x = rhs.clone();
        factor(&mut band, n, p).unwrap();
        solve(&band, n, p, &mut x);
        for i in 0..n {
            assert!((x[i] - reference[(i, 0)]).abs() < 1e-12);
        }
    }

    #[test]
    fn rejects_a_singular_matrix() {
        // [[1, 1], [1, 1]] is positive semi-definite but singular.
        let mut band = vec![1.0, 0.0, 1.0, 1.0];
        assert_eq!(
            factor(&mut band, 2, 1),
            Err(Error::NotPositiveDefinite { pivot: 1 })
        );
    }
}
