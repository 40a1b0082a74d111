//! One Python exception per core error variant, all subclasses of `ValueError` through
//! `TorsocastError`, so `except ValueError` keeps working for callers who do not care which.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use torso_core::Error;

create_exception!(
    _core,
    TorsocastError,
    PyValueError,
    "Base class of every torsocast error."
);
create_exception!(
    _core,
    InvalidArgumentError,
    TorsocastError,
    "An argument outside its domain."
);
create_exception!(
    _core,
    ShapeError,
    TorsocastError,
    "An array of the wrong length or shape."
);
create_exception!(
    _core,
    NonFiniteError,
    TorsocastError,
    "A NaN or infinite value where a finite one is needed."
);
create_exception!(
    _core,
    TooFewJointsError,
    TorsocastError,
    "Fewer valid joints than the estimate needs."
);
create_exception!(
    _core,
    CollinearJointsError,
    TorsocastError,
    "Torso joints (nearly) on a line: no plane."
);
create_exception!(
    _core,
    AmbiguousOrientationError,
    TorsocastError,
    "The torso normal's sign cannot be chosen."
);
create_exception!(
    _core,
    NotPositiveDefiniteError,
    TorsocastError,
    "The spline normal equations are singular."
);
create_exception!(
    _core,
    NotEnoughHistoryError,
    TorsocastError,
    "The forecaster holds too few samples."
);
create_exception!(
    _core,
    TimeNotIncreasingError,
    TorsocastError,
    "A time stamp that does not increase (or lands on the previous grid slot)."
);

/// The Python exception for a core error, with the core's message (which names the argument).
pub fn to_py(error: Error) -> PyErr {
    let message = error.to_string();
    match error {
        Error::InvalidArgument { .. } => InvalidArgumentError::new_err(message),
        Error::LengthMismatch { .. } => ShapeError::new_err(message),
        Error::NonFinite { .. } => NonFiniteError::new_err(message),
        Error::TooFewJoints { .. } => TooFewJointsError::new_err(message),
        Error::CollinearJoints { .. } => CollinearJointsError::new_err(message),
        Error::AmbiguousOrientation => AmbiguousOrientationError::new_err(message),
        Error::NotPositiveDefinite { .. } => NotPositiveDefiniteError::new_err(message),
        Error::NotEnoughHistory { .. } => NotEnoughHistoryError::new_err(message),
        Error::TimeNotIncreasing { .. } => TimeNotIncreasingError::new_err(message),
    }
}

/// A count or size from a Python int: a negative or oversized one raises `InvalidArgumentError`
/// naming the argument (pyo3's own conversion raises an `OverflowError` that names nothing).
pub fn count<T: TryFrom<i64>>(name: &str, value: i64) -> PyResult<T> {
    T::try_from(value).map_err(|_| {
        InvalidArgumentError::new_err(format!(
            "invalid `{name}` = {value}: expected a non-negative count"
        ))
    })
}

/// [`count`] for an optional argument.
pub fn count_or<T: TryFrom<i64>>(name: &str, value: Option<i64>, default: T) -> PyResult<T> {
    value.map_or(Ok(default), |v| count(name, v))
}

/// Raises `ShapeError` naming the argument and the shape it should have had.
pub fn shape_error(name: &str, expected: &str, got: &[usize]) -> PyErr {
    ShapeError::new_err(format!("`{name}` has shape {got:?}, expected {expected}"))
}

/// Raises `InvalidArgumentError` for an unknown option string.
pub fn unknown_option(name: &str, got: &str, choices: &str) -> PyErr {
    InvalidArgumentError::new_err(format!(
        "invalid `{name}` = {got:?}: expected one of {choices}"
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TorsocastError", py.get_type::<TorsocastError>())?;
    m.add(
        "InvalidArgumentError",
        py.get_type::<InvalidArgumentError>(),
    )?;
    m.add("ShapeError", py.get_type::<ShapeError>())?;
    m.add("NonFiniteError", py.get_type::<NonFiniteError>())?;
    m.add("TooFewJointsError", py.get_type::<TooFewJointsError>())?;
    m.add(
        "CollinearJointsError",
        py.get_type::<CollinearJointsError>(),
    )?;
    m.add(
        "AmbiguousOrientationError",
        py.get_type::<AmbiguousOrientationError>(),
    )?;
    m.add(
        "NotPositiveDefiniteError",
        py.get_type::<NotPositiveDefiniteError>(),
    )?;
    m.add(
        "NotEnoughHistoryError",
        py.get_type::<NotEnoughHistoryError>(),
    )?;
    m.add(
        "TimeNotIncreasingError",
        py.get_type::<TimeNotIncreasingError>(),
    )?;
    Ok(())
}
