//! Butterworth design and filtering.

use crate::arrays::{contiguous, expect_ndim, matrix, vector};
use crate::errors::{count, count_or, to_py};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use torso_core::{design_lowpass, SosFilter, ZeroPhase};

/// butter_lowpass(order, cutoff_hz, rate_hz) -> sos array (sections, 6)
#[pyfunction]
pub fn butter_lowpass(
    py: Python<'_>,
    order: i64,
    cutoff_hz: f64,
    rate_hz: f64,
) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let f = design_lowpass(count("order", order)?, cutoff_hz, rate_hz).map_err(to_py)?;
    Ok(matrix(py, f.sections()))
}

/// The designed filter and the finite-checked signal, shared by the window filters.
fn design_and_signal(
    x: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
    order: Option<i64>,
    cutoff_hz: Option<f64>,
    rate_hz: Option<f64>,
) -> PyResult<(SosFilter, Vec<f64>)> {
    let (order, cutoff_hz, rate_hz) = thesis_filter(order, cutoff_hz, rate_hz)?;
    let f = design_lowpass(order, cutoff_hz, rate_hz).map_err(to_py)?;
    Ok((f, signal(x)?))
}

fn signal(x: PyArrayLikeDyn<'_, f64, AllowTypeChange>) -> PyResult<Vec<f64>> {
    expect_ndim("x", x.shape(), 1, "(samples,)")?;
    Ok(contiguous(x.as_array()))
}

/// The thesis' filter as the core's defaults give it: order, cut-off (Hz), grid rate (Hz).
fn thesis_filter(
    order: Option<i64>,
    cutoff_hz: Option<f64>,
    rate_hz: Option<f64>,
) -> PyResult<(usize, f64, f64)> {
    let spline = torso_core::FilterSplineConfig::default();
    Ok((
        count_or("order", order, spline.filter_order)?,
        cutoff_hz.unwrap_or(spline.cutoff_hz),
        rate_hz.unwrap_or(torso_core::ForecasterConfig::default().rate_hz),
    ))
}

/// lowpass_causal(x, order=None, cutoff_hz=None, rate_hz=None): the thesis' filter (2nd order,
/// 5 Hz at 25 Hz) for what is left out
#[pyfunction]
#[pyo3(signature = (x, order=None, cutoff_hz=None, rate_hz=None))]
pub fn lowpass_causal<'py>(
    py: Python<'py>,
    x: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    order: Option<i64>,
    cutoff_hz: Option<f64>,
    rate_hz: Option<f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (f, mut y) = design_and_signal(x, order, cutoff_hz, rate_hz)?;
    f.filter_window(&mut y).map_err(to_py)?;
    Ok(vector(py, &y))
}

/// lowpass_zero_phase(x, order=None, cutoff_hz=None, rate_hz=None): the thesis' filter for
/// what is left out
#[pyfunction]
#[pyo3(signature = (x, order=None, cutoff_hz=None, rate_hz=None))]
pub fn lowpass_zero_phase<'py>(
    py: Python<'py>,
    x: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    order: Option<i64>,
    cutoff_hz: Option<f64>,
    rate_hz: Option<f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (f, x) = design_and_signal(x, order, cutoff_hz, rate_hz)?;
    let mut y = vec![0.0; x.len()];
    ZeroPhase::new(f, x.len())
        .apply(&x, &mut y)
        .map_err(to_py)?;
    Ok(vector(py, &y))
}

/// LowPass(order=None, cutoff_hz=None, rate_hz=None): streaming causal low-pass (the thesis'
/// filter for what is left out).
#[pyclass(module = "torsocast._core")]
pub struct LowPass {
    inner: torso_core::LowPass,
}

#[pymethods]
impl LowPass {
    #[new]
    #[pyo3(signature = (order=None, cutoff_hz=None, rate_hz=None))]
    fn new(order: Option<i64>, cutoff_hz: Option<f64>, rate_hz: Option<f64>) -> PyResult<Self> {
        let (order, cutoff_hz, rate_hz) = thesis_filter(order, cutoff_hz, rate_hz)?;
        let f: SosFilter = design_lowpass(order, cutoff_hz, rate_hz).map_err(to_py)?;
        Ok(Self {
            inner: torso_core::LowPass::new(f),
        })
    }

    /// step(x) -> filtered sample
    fn step(&mut self, x: f64) -> PyResult<f64> {
        self.inner.step(x).map_err(to_py)
    }

    /// filter(x) -> filtered samples, continuing from the current state
    fn filter<'py>(
        &mut self,
        py: Python<'py>,
        x: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut y = signal(x)?;
        self.inner.filter_window(&mut y).map_err(to_py)?;
        Ok(vector(py, &y))
    }

    fn reset(&mut self) {
        self.inner.reset();
    }

    #[getter]
    fn sos<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, self.inner.filter().sections())
    }
}
