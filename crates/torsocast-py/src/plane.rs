//! Torso plane and shoulder heading.

use crate::arrays::{contiguous, expect_last, expect_ndim, matrix, points, sequence, vector};
use crate::errors::{shape_error, to_py};
use numpy::{AllowTypeChange, PyArray1, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use torso_core::{Error, Side};

fn parse_sides(sides: &str) -> PyResult<Vec<Side>> {
    sides
        .chars()
        .map(|c| Side::from_code(c).map_err(to_py))
        .collect()
}

/// A fitted torso plane (SI units, radians).
#[pyclass(module = "torsocast._core", frozen, get_all)]
pub struct TorsoPlane {
    pub centre: Py<PyArray1<f64>>,
    pub normal: Py<PyArray1<f64>>,
    pub azimuth: f64,
    pub elevation: f64,
    pub rms_residual: f64,
    pub joints_used: usize,
}

#[pymethods]
impl TorsoPlane {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "TorsoPlane(centre={}, azimuth={:.4}, elevation={:.4}, rms_residual={:.4}, joints_used={})",
            self.centre.bind(py).repr().map(|r| r.to_string()).unwrap_or_default(),
            self.azimuth,
            self.elevation,
            self.rms_residual,
            self.joints_used
        )
    }
}

/// fit_plane(joints, sides, weights=None)
#[pyfunction]
#[pyo3(signature = (joints, sides, weights=None))]
pub fn fit_plane(
    py: Python<'_>,
    joints: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
    sides: &str,
    weights: Option<PyArrayLikeDyn<'_, f64, AllowTypeChange>>,
) -> PyResult<TorsoPlane> {
    expect_ndim("joints", joints.shape(), 2, "(joints, 3)")?;
    expect_last("joints", joints.shape(), 3, "(joints, 3)")?;
    if let Some(w) = &weights {
        expect_ndim("weights", w.shape(), 1, "(joints,)")?;
    }
    let pts = points(&contiguous(joints.as_array()));
    let w = weights.map(|w| contiguous(w.as_array()));
    let plane =
        torso_core::fit_torso_plane(&pts, &parse_sides(sides)?, w.as_deref()).map_err(to_py)?;
    Ok(TorsoPlane {
        centre: vector(py, &plane.centre).unbind(),
        normal: vector(py, &plane.normal).unbind(),
        azimuth: plane.azimuth,
        elevation: plane.elevation,
        rms_residual: plane.rms_residual,
        joints_used: plane.joints_used,
    })
}

/// Status code of one frame of `fit_planes`.
fn status(result: &Result<torso_core::TorsoPlane, Error>) -> u8 {
    torso_core::plane::PlaneStatus::of(result) as u8
}

/// fit_planes(joints, sides, weights=None, min_orientation_cosine=None) -> dict of arrays, one row
/// per frame; `min_orientation_cosine` defaults to the core's `MIN_ORIENTATION_COSINE`
#[pyfunction]
#[pyo3(signature = (joints, sides, weights=None, min_orientation_cosine=None))]
pub fn fit_planes<'py>(
    py: Python<'py>,
    joints: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    sides: &str,
    weights: Option<PyArrayLikeDyn<'py, f64, AllowTypeChange>>,
    min_orientation_cosine: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let min_orientation_cosine =
        min_orientation_cosine.unwrap_or(torso_core::MIN_ORIENTATION_COSINE);
    let shape = joints.shape().to_vec();
    expect_ndim("joints", &shape, 3, "(frames, joints, 3)")?;
    expect_last("joints", &shape, 3, "(frames, joints, 3)")?;
    let sides = parse_sides(sides)?;
    if shape[1] != sides.len() {
        return Err(shape_error("joints", "(frames, len(sides), 3)", &shape));
    }
    let pts = points(&contiguous(joints.as_array()));
    let w = match weights {
        Some(w) if w.shape() != &shape[..2] => {
            return Err(shape_error("weights", "(frames, joints)", w.shape()))
        }
        Some(w) => Some(contiguous(w.as_array())),
        None => None,
    };
    let n = shape[0];
    let nan3 = [f64::NAN; 3];
    let (mut centre, mut normal) = (vec![nan3; n], vec![nan3; n]);
    let (mut azimuth, mut elevation, mut rms) =
        (vec![f64::NAN; n], vec![f64::NAN; n], vec![f64::NAN; n]);
    let mut codes = vec![0u8; n];
    // The frames' fits run without the GIL: other Python threads go on meanwhile.
    py.detach(|| -> torso_core::Result<()> {
        let results =
            torso_core::fit_torso_planes(&pts, &sides, w.as_deref(), min_orientation_cosine)?;
        for (i, result) in results.enumerate() {
            codes[i] = status(&result);
            if let Ok(p) = result {
                (centre[i], normal[i], azimuth[i], elevation[i], rms[i]) =
                    (p.centre, p.normal, p.azimuth, p.elevation, p.rms_residual);
            }
        }
        Ok(())
    })
    .map_err(to_py)?;
    let out = PyDict::new(py);
    out.set_item("centre", matrix(py, &centre))?;
    out.set_item("normal", matrix(py, &normal))?;
    out.set_item("azimuth", vector(py, &azimuth))?;
    out.set_item("elevation", vector(py, &elevation))?;
    out.set_item("rms_residual", vector(py, &rms))?;
    out.set_item("status", PyArray1::from_vec(py, codes))?;
    Ok(out)
}

/// shoulder_heading(left, right) -> (centre, azimuth)
#[pyfunction]
pub fn shoulder_heading<'py>(
    py: Python<'py>,
    left: Vec<f64>,
    right: Vec<f64>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, f64)> {
    let (left, right) = (sequence("left", &left)?, sequence("right", &right)?);
    let h = torso_core::shoulder_heading(left, right).map_err(to_py)?;
    Ok((vector(py, &h.centre), h.azimuth))
}
