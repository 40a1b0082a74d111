//! Per-joint temporal gating.

use crate::arrays::{contiguous, expect_last, expect_ndim, matrix, points, ArrayPair};
use crate::errors::{count, count_or, to_py};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use torso_core::{GateConfig, JointStatus};

/// JointGate(n_joints, threshold=0.1, max_replacements=10)
#[pyclass(module = "torsocast._core")]
pub struct JointGate {
    inner: torso_core::JointGate,
    status: Vec<JointStatus>,
}

#[pymethods]
impl JointGate {
    #[new]
    #[pyo3(signature = (n_joints, threshold=None, max_replacements=None))]
    fn new(n_joints: i64, threshold: Option<f64>, max_replacements: Option<i64>) -> PyResult<Self> {
        let n_joints: usize = count("n_joints", n_joints)?;
        // Left out: the core's defaults (the thesis' 10 cm and 10 frames).
        let d = GateConfig::default();
        let config = GateConfig {
            threshold: threshold.unwrap_or(d.threshold),
            max_replacements: count_or("max_replacements", max_replacements, d.max_replacements)?,
        };
        Ok(Self {
            inner: torso_core::JointGate::new(n_joints, config).map_err(to_py)?,
            status: vec![JointStatus::Lost; n_joints],
        })
    }

    #[getter]
    fn n_joints(&self) -> usize {
        self.inner.n_joints()
    }

    #[getter]
    fn threshold(&self) -> f64 {
        self.inner.config().threshold
    }

    #[getter]
    fn max_replacements(&self) -> u32 {
        self.inner.config().max_replacements
    }

    /// update(joints) -> (gated joints, status codes)
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        joints: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> ArrayPair<'py, PyArray2<f64>, PyArray1<u8>> {
        expect_ndim("joints", joints.shape(), 2, "(n_joints, 3)")?;
        expect_last("joints", joints.shape(), 3, "(n_joints, 3)")?;
        let mut pts = points(&contiguous(joints.as_array()));
        self.inner
            .update(&mut pts, &mut self.status)
            .map_err(to_py)?;
        let codes: Vec<u8> = self.status.iter().map(|s| *s as u8).collect();
        Ok((matrix(py, &pts), PyArray1::from_vec(py, codes)))
    }

    fn reset(&mut self) {
        self.inner.reset();
    }
}
