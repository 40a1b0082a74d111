//! A torso pose as a REP-155 body frame.

use crate::arrays::{sequence, vector};
use crate::errors::to_py;
use numpy::PyArray1;
use pyo3::prelude::*;

/// A frame's translation and rotation quaternion `[x, y, z, w]`.
type Transform<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// body_frame(pose) -> (translation, rotation)
#[pyfunction]
pub fn body_frame<'py>(py: Python<'py>, pose: Vec<f64>) -> PyResult<Transform<'py>> {
    let frame = torso_core::BodyFrame::of(&sequence("pose", &pose)?).map_err(to_py)?;
    Ok((vector(py, &frame.translation), vector(py, &frame.rotation)))
}
