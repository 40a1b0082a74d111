//! Penalised B-spline smoothing.

use crate::arrays::{contiguous, expect_ndim, vector, ArrayPair};
use crate::errors::to_py;
use numpy::{AllowTypeChange, PyArray1, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// fit_smoothing_spline(x, y, w=None, lam=1.0, degree=3) -> (knots, coefficients)
#[pyfunction]
#[pyo3(signature = (x, y, w=None, lam=1.0, degree=3))]
pub fn fit_smoothing_spline<'py>(
    py: Python<'py>,
    x: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    y: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    w: Option<PyArrayLikeDyn<'py, f64, AllowTypeChange>>,
    lam: f64,
    degree: usize,
) -> ArrayPair<'py, PyArray1<f64>, PyArray1<f64>> {
    expect_ndim("x", x.shape(), 1, "(n,)")?;
    expect_ndim("y", y.shape(), 1, "(n,)")?;
    if let Some(w) = &w {
        expect_ndim("w", w.shape(), 1, "(n,)")?;
    }
    let (x, y) = (contiguous(x.as_array()), contiguous(y.as_array()));
    let w = w.map(|w| contiguous(w.as_array()));
    let (knots, coeffs) =
        torso_core::fit_smoothing_spline(&x, &y, w.as_deref(), lam, degree).map_err(to_py)?;
    Ok((vector(py, &knots), vector(py, &coeffs)))
}
