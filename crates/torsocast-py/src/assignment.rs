//! The optimal assignment of detections to tracks.

use crate::arrays::{c_order, ArrayPair};
use crate::errors::{shape_error, to_py};
use numpy::{AllowTypeChange, PyArray1, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// linear_assignment(cost (n, m)) -> (rows, cols): the pairs that minimise the summed cost, every
/// row or every column used once, rows increasing (as scipy.optimize.linear_sum_assignment)
#[pyfunction]
pub fn linear_assignment<'py>(
    py: Python<'py>,
    cost: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
) -> ArrayPair<'py, PyArray1<usize>, PyArray1<usize>> {
    let shape = cost.shape().to_vec();
    if shape.len() != 2 {
        return Err(shape_error("cost", "(n, m)", &shape));
    }
    let view = cost.as_array();
    let flat = c_order(&view);
    let pairs = torso_core::linear_assignment(&flat, shape[0], shape[1]).map_err(to_py)?;
    let rows: Vec<usize> = pairs.iter().map(|p| p.0).collect();
    let cols: Vec<usize> = pairs.iter().map(|p| p.1).collect();
    Ok((PyArray1::from_vec(py, rows), PyArray1::from_vec(py, cols)))
}
