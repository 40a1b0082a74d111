//! The optimal assignment of detections to tracks: the rectangular linear sum assignment
//! problem (as SciPy's `linear_sum_assignment`), by the Hungarian method with potentials
//! (shortest augmenting paths, O(n² m) for n ≤ m).

use crate::error::{Error, Result};

/// Pairs `(row, column)` that minimise the summed `cost[row * cols + column]` with every row or
/// every column used once (whichever there are fewer of), rows increasing. Costs must be finite.
pub fn linear_assignment(cost: &[f64], rows: usize, cols: usize) -> Result<Vec<(usize, usize)>> {
    let mut solver = Assignment::default();
    Ok(solver.solve(cost, rows, cols)?.to_vec())
}

/// The solver with its working memory, for callers that solve one problem per frame: buffers
/// grow to the largest problem seen and are reused, so that a steady stream of problems no
/// larger than that allocates nothing.
///
/// ```
/// use torso_core::Assignment;
/// let mut solver = Assignment::with_capacity(2, 3);
/// // Two tracks, three detections: each track takes its nearest, one detection is left over.
/// let cost = [0.1, 5.0, 0.9, 4.0, 0.2, 3.0];
/// assert_eq!(solver.solve(&cost, 2, 3).unwrap(), &[(0, 0), (1, 1)]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Assignment {
    u: Vec<f64>,
    v: Vec<f64>,
    /// Column -> row assigned to it (0: none); 1-based as in the classic formulation.
    owner: Vec<usize>,
    way: Vec<usize>,
    min_to: Vec<f64>,
    used: Vec<bool>,
    pairs: Vec<(usize, usize)>,
}

impl Assignment {
    /// A solver with room for problems up to `rows` x `cols` (either way round).
    pub fn with_capacity(rows: usize, cols: usize) -> Self {
        let n = rows.max(cols) + 1;
        Self {
            u: Vec::with_capacity(n),
            v: Vec::with_capacity(n),
            owner: Vec::with_capacity(n),
            way: Vec::with_capacity(n),
            min_to: Vec::with_capacity(n),
            used: Vec::with_capacity(n),
            pairs: Vec::with_capacity(n),
        }
    }

    /// As [`linear_assignment`], borrowing the pairs from the solver.
    pub fn solve(&mut self, cost: &[f64], rows: usize, cols: usize) -> Result<&[(usize, usize)]> {
        if cost.len() != rows.saturating_mul(cols) {
            return Err(Error::LengthMismatch {
                name: "cost",
                expected: rows.saturating_mul(cols),
                got: cost.len(),
            });
        }
        if let Some(index) = cost.iter().position(|c| !c.is_finite()) {
            return Err(Error::NonFinite {
                name: "cost",
                index,
            });
        }
        self.pairs.clear();
        if rows == 0 || cols == 0 {
            return Ok(&self.pairs);
        }
        // The method assigns every row of an n x m problem with n <= m: transpose a tall one.
        let transposed = rows > cols;
        let (n, m) = if transposed {
            (cols, rows)
        } else {
            (rows, cols)
        };
        let at = |i: usize, j: usize| {
            if transposed {
                cost[j * cols + i]
            } else {
                cost[i * cols + j]
            }
        };
        let Self {
            u,
            v,
            owner,
            way,
            min_to,
            used,
            pairs,
        } = self;
        reset(u, n + 1, 0.0);
        reset(v, m + 1, 0.0);
        reset(owner, m + 1, 0);
        reset(way, m + 1, 0);
        reset(min_to, m + 1, 0.0);
        reset(used, m + 1, false);
        for i in 1..=n {
            owner[0] = i;
            let mut j0 = 0;
            min_to.fill(f64::INFINITY);
            used.fill(false);
            loop {
                used[j0] = true;
                let i0 = owner[j0];
                let mut delta = f64::INFINITY;
                let mut j1 = 0;
                for j in 1..=m {
                    if !used[j] {
                        let reduced = at(i0 - 1, j - 1) - u[i0] - v[j];
                        if reduced < min_to[j] {
                            min_to[j] = reduced;
                            way[j] = j0;
                        }
                        if min_to[j] < delta {
                            delta = min_to[j];
                            j1 = j;
                        }
                    }
                }
                for j in 0..=m {
                    if used[j] {
                        u[owner[j]] += delta;
                        v[j] -= delta;
                    } else {
                        min_to[j] -= delta;
                    }
                }
                j0 = j1;
                if owner[j0] == 0 {
                    break;
                }
            }
            loop {
                let j1 = way[j0];
                owner[j0] = owner[j1];
                j0 = j1;
                if j0 == 0 {
                    break;
                }
            }
        }
        pairs.extend((1..=m).filter(|&j| owner[j] != 0).map(|j| {
            let (i, j) = (owner[j] - 1, j - 1);
            if transposed {
                (j, i)
            } else {
                (i, j)
            }
        }));
        pairs.sort_unstable();
        Ok(pairs)
    }
}

/// `buffer` as `len` copies of `value`, reusing its memory.
fn reset<T: Copy>(buffer: &mut Vec<T>, len: usize, value: T) {
    buffer.clear();
    buffer.resize(len, value);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(cost: &[f64], cols: usize, pairs: &[(usize, usize)]) -> f64 {
        pairs.iter().map(|&(i, j)| cost[i * cols + j]).sum()
    }

    /// Every assignment of min(rows, cols) pairs, for checking small problems by brute force.
    fn best_by_enumeration(cost: &[f64], rows: usize, cols: usize) -> f64 {
        fn go(
            cost: &[f64],
            rows: usize,
            cols: usize,
            i: usize,
            used: &mut Vec<bool>,
            left: usize,
        ) -> f64 {
            if left == 0 {
                return 0.0;
            }
            if i == rows {
                return f64::INFINITY;
            }
            // Row i takes a column, or (when rows outnumber what is left) none.
            let mut best = if rows - i > left {
                go(cost, rows, cols, i + 1, used, left)
            } else {
                f64::INFINITY
            };
            for j in 0..cols {
                if !used[j] {
                    used[j] = true;
                    best =
                        best.min(cost[i * cols + j] + go(cost, rows, cols, i + 1, used, left - 1));
                    used[j] = false;
                }
            }
            best
        }
        go(cost, rows, cols, 0, &mut vec![false; cols], rows.min(cols))
    }

    #[test]
    fn small_problems_match_brute_force() {
        let mut next = crate::testing::uniform(12345);
        for rows in 1..=5 {
            for cols in 1..=5 {
                for _ in 0..20 {
                    let cost: Vec<f64> =
                        (0..rows * cols).map(|_| (next() * 10.0).round()).collect();
                    let pairs = linear_assignment(&cost, rows, cols).unwrap();
                    assert_eq!(pairs.len(), rows.min(cols));
                    let (mut r, mut c) = (vec![false; rows], vec![false; cols]);
                    for &(i, j) in &pairs {
                        assert!(!r[i] && !c[j]);
                        r[i] = true;
                        c[j] = true;
                    }
                    let want = best_by_enumeration(&cost, rows, cols);
                    assert!(
                        (total(&cost, cols, &pairs) - want).abs() < 1e-9,
                        "{rows}x{cols} {cost:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn bad_costs_are_typed_errors_and_empty_problems_have_no_pairs() {
        assert!(linear_assignment(&[1.0, f64::NAN], 1, 2).is_err());
        assert!(linear_assignment(&[1.0, 2.0, 3.0], 2, 2).is_err());
        assert!(linear_assignment(&[], 0, 3).unwrap().is_empty());
    }
}
