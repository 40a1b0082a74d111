//! One tracked person's per-frame chain, one call per person and frame.

use crate::arrays::{contiguous, expect_ndim, fixed, matrix};
use crate::config::PersonConfig;
use crate::errors::{shape_error, to_py};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use torso_core::coco::{Joints, N_JOINTS};
use torso_core::{Estimate, JointStatus, Pose};

/// Person(config=None): one tracked person's per-frame chain (`torso_core::Person`), with
/// `PersonConfig()`'s defaults unless given.
#[pyclass(module = "torsocast._core")]
pub struct Person {
    inner: torso_core::Person,
    scratch: Vec<Pose>,
}

impl Person {
    /// One pose per horizon from the core into a `(len(horizons), 5)` array, or None where the
    /// core has none yet.
    fn per_horizon<'py>(
        &mut self,
        py: Python<'py>,
        horizons: &[f64],
        fill: impl FnOnce(&mut torso_core::Person, &[f64], &mut [Pose]) -> torso_core::Result<bool>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.scratch.resize(horizons.len(), [0.0; 5]);
        if fill(&mut self.inner, horizons, &mut self.scratch).map_err(to_py)? {
            Ok(Some(matrix(py, &self.scratch)))
        } else {
            Ok(None)
        }
    }
}

/// What a person's track made of one frame.
#[pyclass(module = "torsocast._core", frozen)]
pub struct Observation {
    pub inner: torso_core::Observation,
}

#[pymethods]
impl Person {
    #[new]
    #[pyo3(signature = (config=None))]
    fn new(config: Option<PyRef<'_, PersonConfig>>) -> PyResult<Self> {
        let config = config.map_or_else(torso_core::PersonConfig::default, |c| c.inner);
        Ok(Self {
            inner: torso_core::Person::new(config).map_err(to_py)?,
            scratch: Vec::new(),
        })
    }

    #[getter]
    fn config(&self) -> PersonConfig {
        PersonConfig::from_core(*self.inner.config())
    }

    /// update(t, joints (17, 3), scores (17,), camera_position (3,)) -> Observation
    fn update(
        &mut self,
        t: f64,
        joints: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
        scores: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
        camera_position: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
    ) -> PyResult<Observation> {
        if joints.shape() != [N_JOINTS, 3] {
            return Err(shape_error("joints", "(17, 3)", joints.shape()));
        }
        expect_ndim("scores", scores.shape(), 1, "(17,)")?;
        expect_ndim("camera_position", camera_position.shape(), 1, "(3,)")?;
        let flat = contiguous(joints.as_array());
        let joints: Joints =
            std::array::from_fn(|i| [flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]]);
        let scores: [f64; N_JOINTS] =
            fixed("scores", &contiguous(scores.as_array()), scores.shape())?;
        let camera: [f64; 3] = fixed(
            "camera_position",
            &contiguous(camera_position.as_array()),
            camera_position.shape(),
        )?;
        let inner = self
            .inner
            .update(t, &joints, &scores, camera)
            .map_err(to_py)?;
        Ok(Observation { inner })
    }

    /// forecast(horizons) -> array (len(horizons), 5), azimuth wrapped, or None before the
    /// history holds enough samples
    fn forecast<'py>(
        &mut self,
        py: Python<'py>,
        horizons: Vec<f64>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.per_horizon(py, &horizons, torso_core::Person::forecast)
    }

    /// intervals(horizons) -> array (len(horizons), 5) of the half-widths of the central 80 %
    /// intervals around forecast(horizons), or None while the history is too short for a line
    fn intervals<'py>(
        &mut self,
        py: Python<'py>,
        horizons: Vec<f64>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.per_horizon(py, &horizons, |p, h, out| p.intervals(h, out))
    }

    /// Samples in the forecaster's history.
    fn __len__(&self) -> usize {
        self.inner.forecaster().len()
    }

    /// Grid time of the forecaster's newest sample; forecasts count from here.
    #[getter]
    fn last_time(&self) -> Option<f64> {
        self.inner.forecaster().last_time()
    }

    #[getter]
    fn min_samples(&self) -> usize {
        self.inner.forecaster().min_samples()
    }
}

#[pymethods]
impl Observation {
    /// `[x, y, z, azimuth, elevation]` (azimuth wrapped), or None without an estimate.
    #[getter]
    fn pose<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.inner.pose.map(|p| PyArray1::from_slice(py, &p))
    }

    /// "plane", "shoulders" or "none".
    #[getter]
    fn estimate(&self) -> &'static str {
        match self.inner.estimate {
            Estimate::Plane => "plane",
            Estimate::Shoulders => "shoulders",
            Estimate::None => "none",
        }
    }

    #[getter]
    fn swapped(&self) -> bool {
        self.inner.swapped
    }

    #[getter]
    fn reoriented(&self) -> bool {
        self.inner.reoriented
    }

    #[getter]
    fn facing_evidence(&self) -> f64 {
        self.inner.facing_evidence
    }

    #[getter]
    fn heading_confident(&self) -> bool {
        self.inner.heading_confident
    }

    #[getter]
    fn heading_held(&self) -> bool {
        self.inner.heading_held
    }

    /// (17, 3) joints after the swap and the gate, NaN where lost.
    #[getter]
    fn joints<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.joints)
    }

    /// (17,) bool: the joint's depth was completed from the learned pair width (hidden far
    /// shoulder or hip).
    #[getter]
    fn completed<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_slice(py, &self.inner.completed)
    }

    /// Per joint: 0 measured, 1 replaced by its previous position, 2 lost.
    #[getter]
    fn joint_status<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        let codes = self.inner.status.map(|s: JointStatus| s as u8);
        PyArray1::from_slice(py, &codes)
    }

    #[getter]
    fn weight(&self) -> f64 {
        self.inner.weight
    }

    /// {"filled": slots interpolated before this sample, "restarted": history cleared after a
    /// long gap, "skipped": the slot already had a sample}
    #[getter]
    fn grid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = self.inner.grid;
        let dict = PyDict::new(py);
        dict.set_item("filled", g.filled)?;
        dict.set_item("restarted", g.restarted)?;
        dict.set_item("skipped", g.skipped)?;
        Ok(dict)
    }

    fn __repr__(&self) -> String {
        format!(
            "Observation(estimate='{}', pose={:?}, swapped={})",
            self.estimate(),
            self.inner.pose,
            if self.inner.swapped { "True" } else { "False" }
        )
    }
}
