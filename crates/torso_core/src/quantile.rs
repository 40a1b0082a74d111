//! A quantile of recent values, old ones forgotten, in fixed memory.
//!
//! A forecast interval is the track's recent errors' root mean square scaled to cover 80 % of
//! them; how far the errors reach beyond their root mean square depends on the motion (a
//! walker's are a small scatter with a few outliers that swell the mean square; a soccer
//! player's grow as the play changes). The quantile of the errors in units of the spread says
//! which multiple covers them. Values are kept as masses in bins evenly spaced on a log scale
//! from [`LOWEST`] to [`HIGHEST`] (outside, in the end bins), so a quantile is read to within a
//! bin's width, about an eighth of its value.

/// Smallest value told apart from smaller ones.
pub const LOWEST: f64 = 1.0 / 16.0;
/// Largest value told apart from larger ones.
pub const HIGHEST: f64 = 16.0;
/// Bins between [`LOWEST`] and [`HIGHEST`].
pub const BINS: usize = 48;

/// Masses of recent values per log-spaced bin.
///
/// ```
/// use torso_core::quantile::RecentQuantile;
/// let mut q = RecentQuantile::default();
/// for k in 1..=100 {
///     q.add(Some(k as f64 / 100.0), 1.0); // evenly from 0.01 to 1
/// }
/// assert!((q.quantile(0.8, 1.0, 0.0) - 0.8).abs() < 0.1);
/// // With nothing seen, the prior is the answer.
/// assert_eq!(RecentQuantile::default().quantile(0.8, 2.0, 3.0), 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecentQuantile {
    /// The masses over `scale`: forgetting scales one number, not every bin.
    mass: [f64; BINS],
    scale: f64,
}

impl Default for RecentQuantile {
    fn default() -> Self {
        Self {
            mass: [0.0; BINS],
            scale: 1.0,
        }
    }
}

/// Where `value` lies on the bins' scale: bin `i` spans `[i, i + 1)`.
fn position(value: f64) -> f64 {
    let u = (value / LOWEST).ln() / (HIGHEST / LOWEST).ln() * BINS as f64;
    if u.is_nan() {
        0.0
    } else {
        u.clamp(0.0, BINS as f64 - 1e-9)
    }
}

impl RecentQuantile {
    /// Scales every mass kept by `decay` (how much of an old value is remembered), then adds
    /// `value` with mass one; `None`, and a value that is negative or NaN, only forget.
    pub fn add(&mut self, value: Option<f64>, decay: f64) {
        self.scale *= decay;
        if !(self.scale > 1e-200) {
            // Long forgotten (or `decay` zero): what is left is below rounding.
            *self = Self::default();
        }
        if let Some(v) = value.filter(|v| *v >= 0.0) {
            self.mass[position(v) as usize] += 1.0 / self.scale;
        }
    }

    /// Total mass kept.
    pub fn total(&self) -> f64 {
        self.mass.iter().sum::<f64>() * self.scale
    }

    /// The value below which a share `level` of the mass lies, with `prior` counted as a value
    /// of mass `prior_weight` among those kept (so that a few values move it only so far).
    /// Within a bin the mass is spread evenly on the log scale.
    pub fn quantile(&self, level: f64, prior: f64, prior_weight: f64) -> f64 {
        let kept = self.total();
        if !(kept > 0.0) {
            return prior;
        }
        let target = level * (kept + prior_weight);
        let p = position(prior);
        let at = |u: f64| LOWEST * (HIGHEST / LOWEST).powf(u / BINS as f64);
        let mut below = 0.0;
        for (i, &m) in self.mass.iter().enumerate() {
            let m = m * self.scale;
            let start = i as f64;
            if p as usize != i {
                // The bin's mass spread evenly over it.
                if m > 0.0 && below + m >= target {
                    return at(start + (target - below) / m);
                }
                below += m;
                continue;
            }
            // The prior's bin: its mass spread evenly, the prior's at its place inside it.
            for (piece, (from, to)) in [(start, p), (p, start + 1.0)].iter().enumerate() {
                let mass = m * (to - from);
                if mass > 0.0 && below + mass >= target {
                    return at(from + (target - below) / m);
                }
                below += mass;
                if piece == 0 {
                    below += prior_weight;
                    if below >= target {
                        return prior;
                    }
                }
            }
        }
        at(BINS as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact weighted quantile: the smallest value with at least `level` of the mass at or
    /// below it.
    fn exact(values: &[(f64, f64)], level: f64) -> f64 {
        let mut v = values.to_vec();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        let total: f64 = v.iter().map(|x| x.1).sum();
        let mut below = 0.0;
        for (x, w) in v {
            below += w;
            if below >= level * total {
                return x;
            }
        }
        f64::NAN
    }

    #[test]
    fn the_quantile_of_many_values_matches_the_exact_one_within_a_bin() {
        // Exponentially distributed values (quantiles -ln(1 - u)) in a shuffled order, forgotten a
        // little at every step.
        let n: usize = 2000;
        let decay: f64 = 0.999;
        let mut q = RecentQuantile::default();
        let mut kept = Vec::new();
        for k in 0..n {
            let u = ((k * 7919) % n) as f64 / n as f64 + 0.5 / n as f64;
            let value = -(1.0 - u).ln();
            q.add(Some(value), decay);
            kept.push((value, decay.powi((n - 1 - k) as i32)));
        }
        let width = (HIGHEST / LOWEST).powf(1.0 / BINS as f64);
        for level in [0.5, 0.8, 0.9] {
            let (got, want) = (q.quantile(level, 1.0, 0.0), exact(&kept, level));
            assert!(
                got / want < width && want / got < width,
                "{level}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn the_prior_counts_as_one_value_of_its_mass() {
        let mut q = RecentQuantile::default();
        q.add(Some(0.5), 1.0);
        // Half the mass at 0.5 and half at 2: the 80 % quantile is the prior, the 40 % one
        // within the first value's bin.
        assert_eq!(q.quantile(0.8, 2.0, 1.0), 2.0);
        let low = q.quantile(0.4, 2.0, 1.0);
        assert!(low < 0.6 && low > 0.4, "{low}");
        // Far more mass than the prior's: the values decide.
        for _ in 0..99 {
            q.add(Some(0.5), 1.0);
        }
        assert!((q.quantile(0.8, 2.0, 3.0) - 0.5).abs() < 0.1);
    }

    #[test]
    fn values_beyond_the_range_land_in_the_end_bins_and_forgetting_empties() {
        let mut q = RecentQuantile::default();
        q.add(Some(1e6), 1.0);
        assert!(q.quantile(0.5, 1.0, 0.0) <= HIGHEST);
        q.add(Some(0.0), 1.0);
        assert!(q.quantile(0.1, 1.0, 0.0) >= LOWEST);
        // Not a value: only forgotten with.
        let before = q.total();
        q.add(Some(f64::NAN), 1.0);
        q.add(Some(-1.0), 1.0);
        assert_eq!(q.total(), before);
        q.add(None, 0.0);
        assert_eq!(q.total(), 0.0);
        assert_eq!(q.quantile(0.8, 1.5, 3.0), 1.5);
    }
}
