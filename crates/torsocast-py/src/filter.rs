//! Butterworth design and filtering.

use crate::arrays::{contiguous, matrix, vector};
use crate::errors::to_py;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1};
use pyo3::prelude::*;
use torso_core::{design_lowpass, SosFilter, ZeroPhase};

/// butter_lowpass(order, cutoff_hz, rate_hz) -> sos array (sections, 6)
#[pyfunction]
pub fn butter_lowpass(
    py: Python<'_>,
    order: usize,
    cutoff_hz: f64,
    rate_hz: f64,
) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let f = design_lowpass(order, cutoff_hz, rate_hz).map_err(to_py)?;
    matrix(py, f.sections())
}

/// The designed filter and the finite-checked signal, shared by the window filters.
fn design_and_signal(
    x: PyArrayLike1<'_, f64, AllowTypeChange>,
    order: usize,
    cutoff_hz: f64,
    rate_hz: f64,
) -> PyResult<(SosFilter, Vec<f64>)> {
    let f = design_lowpass(order, cutoff_hz, rate_hz).map_err(to_py)?;
    Ok((f, signal(x)?))
}

fn signal(x: PyArrayLike1<'_, f64, AllowTypeChange>) -> PyResult<Vec<f64>> {
    let x = contiguous(x.as_array());
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(to_py(torso_core::Error::NonFinite { name: "x", index }));
    }
    Ok(x)
}

/// lowpass_causal(x, order=2, cutoff_hz=5.0, rate_hz=25.0)
#[pyfunction]
#[pyo3(signature = (x, order=2, cutoff_hz=5.0, rate_hz=25.0))]
pub fn lowpass_causal<'py>(
    py: Python<'py>,
    x: PyArrayLike1<'py, f64, AllowTypeChange>,
    order: usize,
    cutoff_hz: f64,
    rate_hz: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (f, mut y) = design_and_signal(x, order, cutoff_hz, rate_hz)?;
    f.filter_from_steady_state(&mut y);
    Ok(vector(py, &y))
}

/// lowpass_zero_phase(x, order=2, cutoff_hz=5.0, rate_hz=25.0)
#[pyfunction]
#[pyo3(signature = (x, order=2, cutoff_hz=5.0, rate_hz=25.0))]
pub fn lowpass_zero_phase<'py>(
    py: Python<'py>,
    x: PyArrayLike1<'py, f64, AllowTypeChange>,
    order: usize,
    cutoff_hz: f64,
    rate_hz: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (f, x) = design_and_signal(x, order, cutoff_hz, rate_hz)?;
    let mut y = vec![0.0; x.len()];
    ZeroPhase::new(f, x.len())
        .apply(&x, &mut y)
        .map_err(to_py)?;
    Ok(vector(py, &y))
}

/// LowPass(order=2, cutoff_hz=5.0, rate_hz=25.0): streaming causal low-pass.
#[pyclass(module = "torsocast._core")]
pub struct LowPass {
    inner: torso_core::LowPass,
}

#[pymethods]
impl LowPass {
    #[new]
    #[pyo3(signature = (order=2, cutoff_hz=5.0, rate_hz=25.0))]
    fn new(order: usize, cutoff_hz: f64, rate_hz: f64) -> PyResult<Self> {
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
        x: PyArrayLike1<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut y = signal(x)?;
        for v in y.iter_mut() {
            *v = self.inner.step(*v).map_err(to_py)?;
        }
        Ok(vector(py, &y))
    }

    fn reset(&mut self) {
        self.inner.reset();
    }

    #[getter]
    fn sos<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.inner.filter().sections())
    }
}
