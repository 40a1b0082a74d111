//! The core's configuration structs as frozen Python classes: every keyword left out takes the
//! core's `Default`, so no default number is written in the binding. Each class lists its fields
//! once (`fields`), and its repr, equality, pickling and `replace` are built from that list.

use crate::arrays::sequence;
use crate::errors::{count_or, to_py};
use crate::forecaster::ForecasterConfig;
use numpy::{AllowTypeChange, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use torso_core::depth::DepthImage;
use torso_core::sides::FacingConfig;
use torso_core::GateConfig;

/// The `#[pymethods]` of a frozen configuration class: its own `methods`, and `replace`,
/// `__repr__` and `__getnewargs_ex__` built from its `fields()`.
macro_rules! frozen_config {
    ($class:ident, { $($methods:tt)* }) => {
        #[pymethods]
        impl $class {
            $($methods)*

            /// A copy with the given fields changed (as `dataclasses.replace`).
            #[pyo3(signature = (**changes))]
            fn replace<'py>(
                slf: &Bound<'py, Self>,
                changes: Option<&Bound<'py, PyDict>>,
            ) -> PyResult<Bound<'py, PyAny>> {
                replaced(slf.as_any(), slf.get().fields(slf.py())?, changes)
            }

            fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
                repr(stringify!($class), self.fields(py)?)
            }

            fn __getnewargs_ex__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
                newargs(py, self.fields(py)?)
            }
        }
    };
}

pub type Fields<'py> = Vec<(&'static str, Bound<'py, PyAny>)>;

/// `Name(field=value, ...)` from the class's fields.
pub fn repr(name: &str, fields: Fields<'_>) -> PyResult<String> {
    let parts: PyResult<Vec<String>> = fields
        .iter()
        .map(|(k, v)| Ok(format!("{k}={}", v.repr()?)))
        .collect();
    Ok(format!("{name}({})", parts?.join(", ")))
}

fn as_dict<'py>(py: Python<'py>, fields: Fields<'py>) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (k, v) in fields {
        dict.set_item(k, v)?;
    }
    Ok(dict)
}

/// A new instance of `this`'s class with its fields, some replaced by `changes`.
fn replaced<'py>(
    this: &Bound<'py, PyAny>,
    fields: Fields<'py>,
    changes: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let kwargs = as_dict(this.py(), fields)?;
    if let Some(changes) = changes {
        for (k, _) in changes.iter() {
            if !kwargs.contains(&k)? {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "replace() got an unexpected keyword argument {}",
                    k.repr()?
                )));
            }
        }
        kwargs.update(changes.as_mapping())?;
    }
    this.get_type().call((), Some(&kwargs))
}

/// Pickling by keywords: `(args, kwargs)` for `__new__`.
pub fn newargs<'py>(py: Python<'py>, fields: Fields<'py>) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(
        py,
        [
            PyTuple::empty(py).into_any(),
            as_dict(py, fields)?.into_any(),
        ],
    )
}

/// PersonConfig(forecaster=None, *, gate_threshold, gate_max_replacements, min_score,
/// facing_memory, face_weight, knee_weight, motion_weight, self_check, occlusion_ratio,
/// surface_depth): one
/// track's parameters (`torso_core::PersonConfig`); each left out takes the core's default.
#[pyclass(module = "torsocast._core", frozen, eq)]
#[derive(Clone)]
pub struct PersonConfig {
    pub inner: torso_core::PersonConfig,
    forecaster: ForecasterConfig,
}

impl PartialEq for PersonConfig {
    fn eq(&self, other: &Self) -> bool {
        self.inner == other.inner
    }
}

impl PersonConfig {
    pub fn from_core(inner: torso_core::PersonConfig) -> Self {
        Self {
            forecaster: ForecasterConfig::from_core(inner.forecaster),
            inner,
        }
    }

    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Fields<'py>> {
        let c = &self.inner;
        Ok(vec![
            (
                "forecaster",
                Bound::new(py, self.forecaster.clone())?.into_any(),
            ),
            (
                "gate_threshold",
                c.gate.threshold.into_pyobject(py)?.into_any(),
            ),
            (
                "gate_max_replacements",
                c.gate.max_replacements.into_pyobject(py)?.into_any(),
            ),
            ("min_score", c.min_score.into_pyobject(py)?.into_any()),
            (
                "facing_memory",
                c.facing.memory.into_pyobject(py)?.into_any(),
            ),
            (
                "face_weight",
                c.facing.face_weight.into_pyobject(py)?.into_any(),
            ),
            (
                "knee_weight",
                c.facing.knee_weight.into_pyobject(py)?.into_any(),
            ),
            (
                "motion_weight",
                c.facing.motion_weight.into_pyobject(py)?.into_any(),
            ),
            (
                "self_check",
                c.self_check.into_pyobject(py)?.to_owned().into_any(),
            ),
            (
                "occlusion_ratio",
                c.occlusion_ratio.into_pyobject(py)?.into_any(),
            ),
            (
                "surface_depth",
                (c.surface_depth[0], c.surface_depth[1])
                    .into_pyobject(py)?
                    .into_any(),
            ),
        ])
    }
}

frozen_config!(PersonConfig, {
    #[new]
    #[pyo3(signature = (
        forecaster=None, *, gate_threshold=None, gate_max_replacements=None, min_score=None,
        facing_memory=None, face_weight=None, knee_weight=None, motion_weight=None,
        self_check=None, occlusion_ratio=None, surface_depth=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        forecaster: Option<PyRef<'_, ForecasterConfig>>,
        gate_threshold: Option<f64>,
        gate_max_replacements: Option<i64>,
        min_score: Option<f64>,
        facing_memory: Option<f64>,
        face_weight: Option<f64>,
        knee_weight: Option<f64>,
        motion_weight: Option<f64>,
        self_check: Option<bool>,
        occlusion_ratio: Option<f64>,
        surface_depth: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let surface_depth: Option<[f64; 2]> = surface_depth
            .map(|v| sequence("surface_depth", &v))
            .transpose()?;
        let d = torso_core::PersonConfig::default();
        let inner = torso_core::PersonConfig {
            forecaster: forecaster.map_or(d.forecaster, |f| f.inner),
            gate: GateConfig {
                threshold: gate_threshold.unwrap_or(d.gate.threshold),
                max_replacements: count_or(
                    "gate_max_replacements",
                    gate_max_replacements,
                    d.gate.max_replacements,
                )?,
            },
            min_score: min_score.unwrap_or(d.min_score),
            facing: FacingConfig {
                memory: facing_memory.unwrap_or(d.facing.memory),
                face_weight: face_weight.unwrap_or(d.facing.face_weight),
                knee_weight: knee_weight.unwrap_or(d.facing.knee_weight),
                motion_weight: motion_weight.unwrap_or(d.facing.motion_weight),
            },
            self_check: self_check.unwrap_or(d.self_check),
            occlusion_ratio: occlusion_ratio.unwrap_or(d.occlusion_ratio),
            surface_depth: surface_depth.unwrap_or(d.surface_depth),
        };
        inner.validate().map_err(to_py)?;
        Ok(Self::from_core(inner))
    }

    /// The live tracking forecaster (`ForecasterConfig.live()` unless given).
    #[getter]
    fn forecaster(&self) -> ForecasterConfig {
        self.forecaster.clone()
    }
    /// Largest accepted joint displacement between frames relative to the body's (m).
    #[getter]
    fn gate_threshold(&self) -> f64 {
        self.inner.gate.threshold
    }
    /// Frames a joint may be held over before it is lost; at a frame rate under 25 Hz, fewer:
    /// no longer than these frames last at 25 Hz (10: 0.4 s).
    #[getter]
    fn gate_max_replacements(&self) -> u32 {
        self.inner.gate.max_replacements
    }
    /// Keypoints scored below this are missing (the one seen-keypoint rule of every stage).
    #[getter]
    fn min_score(&self) -> f64 {
        self.inner.min_score
    }
    /// Time constant (s) over which the recent evidence for which way the chest faces is
    /// forgotten: what makes a heading confident (``heading_confident``, ``facing_evidence``).
    /// The side itself is decided on evidence forgotten as the heading moves, and only slowly
    /// with time; while the torso goes unseen, both are forgotten over this time constant.
    #[getter]
    fn facing_memory(&self) -> f64 {
        self.inner.facing.memory
    }
    /// Weight of the nose standing in front of the shoulders, relative to the labels'.
    #[getter]
    fn face_weight(&self) -> f64 {
        self.inner.facing.face_weight
    }
    /// Weight of the knees standing in front of their legs, relative to the labels'.
    #[getter]
    fn knee_weight(&self) -> f64 {
        self.inner.facing.knee_weight
    }
    /// Weight of the walking direction, relative to the labels'.
    #[getter]
    fn motion_weight(&self) -> f64 {
        self.inner.facing.motion_weight
    }
    /// The track checks its forecasts against its own later samples and mixes the candidates.
    #[getter]
    fn self_check(&self) -> bool {
        self.inner.self_check
    }
    /// A pair shorter than this fraction of its learned width has its far joint's depth
    /// completed; 0 turns it off.
    #[getter]
    fn occlusion_ratio(&self) -> f64 {
        self.inner.occlusion_ratio
    }
    /// How far (m) the shoulders' and the hips' joint centres lie behind the body's surface the
    /// depth camera sees, along its rays: (shoulders, hips); (0, 0) for joints that are joint
    /// centres already (mocap, a skeleton tracker's).
    #[getter]
    fn surface_depth(&self) -> (f64, f64) {
        (self.inner.surface_depth[0], self.inner.surface_depth[1])
    }
});

/// DepthLookup(*, radius, band, min_valid, min_depth, max_depth): how a keypoint's depth is read
/// from the depth image (`torso_core::depth::DepthLookup`): the median of the valid readings in
/// a `(2 radius + 1)²` window after dropping those more than `band` (m) behind the window's
/// 25th percentile; fewer than `min_valid` readings gives NaN. Called on a depth image in
/// metres and pixels `uv (..., 2)`, gives the depth at each (NaN where none).
#[pyclass(module = "torsocast._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct DepthLookup {
    pub inner: torso_core::depth::DepthLookup,
}

impl DepthLookup {
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Fields<'py>> {
        let c = &self.inner;
        Ok(vec![
            ("radius", c.radius.into_pyobject(py)?.into_any()),
            ("band", c.band.into_pyobject(py)?.into_any()),
            ("min_valid", c.min_valid.into_pyobject(py)?.into_any()),
            ("min_depth", c.min_depth.into_pyobject(py)?.into_any()),
            ("max_depth", c.max_depth.into_pyobject(py)?.into_any()),
        ])
    }
}

frozen_config!(DepthLookup, {
    #[new]
    #[pyo3(signature = (*, radius=None, band=None, min_valid=None, min_depth=None, max_depth=None))]
    fn new(
        radius: Option<i64>,
        band: Option<f64>,
        min_valid: Option<i64>,
        min_depth: Option<f64>,
        max_depth: Option<f64>,
    ) -> PyResult<Self> {
        let d = torso_core::depth::DepthLookup::default();
        let inner = torso_core::depth::DepthLookup {
            radius: count_or("radius", radius, d.radius)?,
            band: band.unwrap_or(d.band),
            min_valid: count_or("min_valid", min_valid, d.min_valid)?,
            min_depth: min_depth.unwrap_or(d.min_depth),
            max_depth: max_depth.unwrap_or(d.max_depth),
        };
        inner.validate().map_err(to_py)?;
        Ok(Self { inner })
    }

    #[getter]
    fn radius(&self) -> usize {
        self.inner.radius
    }
    #[getter]
    fn band(&self) -> f64 {
        self.inner.band
    }
    #[getter]
    fn min_valid(&self) -> usize {
        self.inner.min_valid
    }
    #[getter]
    fn min_depth(&self) -> f64 {
        self.inner.min_depth
    }
    #[getter]
    fn max_depth(&self) -> f64 {
        self.inner.max_depth
    }

    /// __call__(depth (h, w) in metres, uv (..., 2)) -> depth (...,) at each pixel, NaN where none
    fn __call__<'py>(
        &self,
        py: Python<'py>,
        depth: PyArrayLikeDyn<'py, f32, AllowTypeChange>,
        uv: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (height, width) = crate::arrays::depth_size(depth.shape())?;
        let shape = uv.shape().to_vec();
        crate::arrays::expect_last("uv", &shape, 2, "(..., 2)")?;
        let flat = crate::arrays::c_order(&uv.as_array()).into_owned();
        let view = depth.as_array();
        let pixels = crate::arrays::c_order(&view);
        let image = DepthImage::new(&pixels, width, height).map_err(to_py)?;
        let out: Vec<f64> = flat
            .chunks_exact(2)
            .map(|p| self.inner.depth_at(&image, [p[0], p[1]]))
            .collect();
        let array = numpy::PyArray1::from_vec(py, out);
        array.reshape(shape[..shape.len() - 1].to_vec())
    }
});

/// TrackerConfig(*, gate, min_hits, max_missing, capacity, max_detections, person, depth):
/// association, birth and drop rules (`torso_core::tracker::TrackerConfig`), with each track's
/// `PersonConfig` and the `DepthLookup`; each left out takes the core's default.
#[pyclass(module = "torsocast._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct TrackerConfig {
    pub inner: torso_core::TrackerConfig,
}

impl TrackerConfig {
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Fields<'py>> {
        let c = &self.inner;
        Ok(vec![
            ("gate", c.gate.into_pyobject(py)?.into_any()),
            ("min_hits", c.min_hits.into_pyobject(py)?.into_any()),
            ("max_missing", c.max_missing.into_pyobject(py)?.into_any()),
            ("capacity", c.capacity.into_pyobject(py)?.into_any()),
            (
                "max_detections",
                c.max_detections.into_pyobject(py)?.into_any(),
            ),
            (
                "person",
                Bound::new(py, PersonConfig::from_core(c.person))?.into_any(),
            ),
            (
                "depth",
                Bound::new(py, DepthLookup { inner: c.depth })?.into_any(),
            ),
        ])
    }
}

frozen_config!(TrackerConfig, {
    #[new]
    #[pyo3(signature = (
        *, gate=None, min_hits=None, max_missing=None, capacity=None, max_detections=None,
        person=None, depth=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        gate: Option<f64>,
        min_hits: Option<i64>,
        max_missing: Option<f64>,
        capacity: Option<i64>,
        max_detections: Option<i64>,
        person: Option<PyRef<'_, PersonConfig>>,
        depth: Option<PyRef<'_, DepthLookup>>,
    ) -> PyResult<Self> {
        let d = torso_core::TrackerConfig::default();
        let inner = torso_core::TrackerConfig {
            gate: gate.unwrap_or(d.gate),
            min_hits: count_or("min_hits", min_hits, d.min_hits)?,
            max_missing: max_missing.unwrap_or(d.max_missing),
            capacity: count_or("capacity", capacity, d.capacity)?,
            max_detections: count_or("max_detections", max_detections, d.max_detections)?,
            person: person.map_or(d.person, |p| p.inner),
            depth: depth.map_or(d.depth, |l| l.inner),
        };
        inner.validate().map_err(to_py)?;
        Ok(Self { inner })
    }

    /// Largest distance (m) between where a track's person is expected (the last torso
    /// centre, moved on at the track's walking velocity while unseen) and its detection's;
    /// widened by 1 m per second the camera sent no frame (beyond 0.2 s between two frames)
    /// since the track was last matched.
    #[getter]
    fn gate(&self) -> f64 {
        self.inner.gate
    }
    /// Matched frames before a track is confirmed and given an id.
    #[getter]
    fn min_hits(&self) -> u32 {
        self.inner.min_hits
    }
    /// Seconds without a match after which a confirmed track is dropped.
    #[getter]
    fn max_missing(&self) -> f64 {
        self.inner.max_missing
    }
    /// Most tracks alive at once.
    #[getter]
    fn capacity(&self) -> usize {
        self.inner.capacity
    }
    /// Most detections in one frame.
    #[getter]
    fn max_detections(&self) -> usize {
        self.inner.max_detections
    }
    #[getter]
    fn person(&self) -> PersonConfig {
        PersonConfig::from_core(self.inner.person)
    }
    #[getter]
    fn depth(&self) -> DepthLookup {
        DepthLookup {
            inner: self.inner.depth,
        }
    }
});
