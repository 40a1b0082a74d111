//! `torsocast._core`: PyO3 bindings of `torso_core`. Only argument conversion, shape checks and
//! error mapping live here; every computation is in the core crate.

mod arrays;
mod assignment;
mod body_frame;
mod config;
mod errors;
mod filter;
mod forecaster;
mod gating;
mod person;
mod plane;
mod spline;
mod tracker;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<plane::TorsoPlane>()?;
    m.add_function(wrap_pyfunction!(plane::fit_plane, m)?)?;
    m.add_function(wrap_pyfunction!(plane::fit_planes, m)?)?;
    m.add_function(wrap_pyfunction!(plane::shoulder_heading, m)?)?;
    m.add_function(wrap_pyfunction!(body_frame::body_frame, m)?)?;
    m.add_class::<gating::JointGate>()?;
    m.add_function(wrap_pyfunction!(filter::butter_lowpass, m)?)?;
    m.add_function(wrap_pyfunction!(filter::lowpass_causal, m)?)?;
    m.add_function(wrap_pyfunction!(filter::lowpass_zero_phase, m)?)?;
    m.add_class::<filter::LowPass>()?;
    m.add_function(wrap_pyfunction!(spline::fit_smoothing_spline, m)?)?;
    m.add_class::<forecaster::ForecasterConfig>()?;
    m.add_class::<forecaster::Forecaster>()?;
    m.add_function(wrap_pyfunction!(forecaster::forecast_batch, m)?)?;
    m.add_function(wrap_pyfunction!(assignment::linear_assignment, m)?)?;
    m.add_class::<person::Person>()?;
    m.add_class::<person::Observation>()?;
    m.add_class::<config::PersonConfig>()?;
    m.add_class::<config::DepthLookup>()?;
    m.add_class::<config::TrackerConfig>()?;
    m.add_class::<tracker::Tracker>()?;
    m.add_class::<tracker::TrackOutcome>()?;
    m.add_class::<tracker::TrackState>()?;
    m.add("MAX_DEGREE", torso_core::bspline::MAX_DEGREE)?;
    m.add("MIN_ORIENTATION_COSINE", torso_core::MIN_ORIENTATION_COSINE)?;
    m.add("MAX_HORIZON", torso_core::forecaster::MAX_HORIZON)?;
    // The status codes' names, from the core (the Python enums are compared with these).
    let codes = |names: &[(&str, u8)]| -> PyResult<Bound<'_, pyo3::types::PyDict>> {
        let dict = pyo3::types::PyDict::new(m.py());
        for (name, code) in names {
            dict.set_item(name, code)?;
        }
        Ok(dict)
    };
    m.add(
        "PLANE_STATUS",
        codes(&torso_core::plane::PlaneStatus::NAMES.map(|(k, v)| (k, v as u8)))?,
    )?;
    m.add(
        "JOINT_STATUS",
        codes(&torso_core::JointStatus::NAMES.map(|(k, v)| (k, v as u8)))?,
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
