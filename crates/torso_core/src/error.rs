//! The one error type of the crate. Every public entry point returns it instead of panicking or
//! producing NaN; the Python binding maps each variant to its own exception class.

use std::fmt;

/// What went wrong, with the name of the offending argument where there is one.
///
/// Variants carry only `Copy` data so that building an error never allocates: a rejected frame
/// stays as cheap as an accepted one.
///
/// ```
/// use torso_core::{Error, Forecaster, ForecasterConfig};
/// let mut f = Forecaster::new(ForecasterConfig::default()).unwrap();
/// let refused = f.update([f64::NAN, 0.0, 0.0, 0.0, 0.0], 0.0, 1.0);
/// assert!(matches!(refused, Err(Error::NonFinite { name: "pose", .. })));
/// assert_eq!(f.len(), 0); // a refused call changes nothing
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Error {
    /// An argument or configuration value outside its domain.
    InvalidArgument {
        name: &'static str,
        expected: &'static str,
        value: f64,
    },
    /// A slice or array whose length does not match what the call needs.
    LengthMismatch {
        name: &'static str,
        expected: usize,
        got: usize,
    },
    /// A value that must be finite (a pose component, a time stamp) is NaN or infinite.
    NonFinite { name: &'static str, index: usize },
    /// Fewer valid joints than the estimate needs.
    TooFewJoints { valid: usize, needed: usize },
    /// The valid torso joints lie (nearly) on a line, so no plane is defined.
    CollinearJoints { planarity: f64, minimum: f64 },
    /// The normal's sign cannot be chosen: no left or right joint, or the body's left-right axis
    /// (nearly) parallel to gravity, or a torso plane (nearly) horizontal.
    AmbiguousOrientation,
    /// The banded normal equations are not positive definite (for example all weights zero).
    NotPositiveDefinite { pivot: usize },
    /// The forecaster has fewer samples than its method needs.
    NotEnoughHistory { have: usize, need: usize },
    /// A time stamp that is not after the previous one, or that lands on the previous sample's slot
    /// of the fixed-rate grid.
    TimeNotIncreasing { previous: f64, got: f64 },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidArgument {
                name,
                expected,
                value,
            } => write!(f, "invalid `{name}` = {}: expected {expected}", Number(value)),
            Error::LengthMismatch {
                name,
                expected,
                got,
            } => write!(f, "`{name}` has length {got}, expected {expected}"),
            Error::NonFinite { name, index } => {
                write!(f, "`{name}` holds a NaN or infinite value at index {index}")
            }
            Error::TooFewJoints { valid, needed } => write!(
                f,
                "`joints`: {valid} valid joint(s), at least {needed} finite joints with positive weight are needed"
            ),
            Error::CollinearJoints { planarity, minimum } => write!(
                f,
                "`joints` are (nearly) collinear: second/largest scatter eigenvalue ratio {planarity:.3e} is below {minimum:.0e}, so no torso plane is defined"
            ),
            Error::AmbiguousOrientation => write!(
                f,
                "`sides`: cannot orient the torso normal: it needs at least one valid left and one valid right joint, a left-right axis that is not vertical and a torso plane that is not horizontal"
            ),
            Error::NotPositiveDefinite { pivot } => write!(
                f,
                "`weights`: the spline's normal equations are not positive definite (pivot {pivot}); give more samples positive weight or a positive `lam`"
            ),
            Error::NotEnoughHistory { have, need } => write!(
                f,
                "`history` holds {have} sample(s), the method needs at least {need}"
            ),
            Error::TimeNotIncreasing { previous, got } => write!(
                f,
                "`t` = {got} s is not after the previous time stamp {previous} s (a forecaster also needs it on a later slot of its fixed-rate grid: at least half a grid step later)"
            ),
        }
    }
}

impl std::error::Error for Error {}

/// Shorthand used throughout the crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Rejects a slice whose length differs from `expected`.
pub(crate) fn check_len(name: &'static str, got: usize, expected: usize) -> Result<()> {
    if got == expected {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            name,
            expected,
            got,
        })
    }
}

/// Rejects a value that is not finite and strictly positive.
pub(crate) fn check_positive(name: &'static str, value: f64, expected: &'static str) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidArgument {
            name,
            expected,
            value,
        })
    }
}

/// Rejects weights that are negative, NaN or infinite (zero is allowed: it means "ignore").
pub(crate) fn check_weights(name: &'static str, weights: &[f64]) -> Result<()> {
    match weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        None => Ok(()),
        Some(&value) => Err(Error::InvalidArgument {
            name,
            expected: "finite, non-negative weights",
            value,
        }),
    }
}

/// A value as a person reads it in one line: plain for everyday magnitudes, in exponent form
/// for huge or tiny ones (`{}` would spell 1e308 with 308 digits).
struct Number(f64);

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}
