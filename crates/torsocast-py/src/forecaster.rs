//! Forecaster, its configuration and the batch call.

use crate::arrays::{c_order, matrix, sequence, ArrayPair};
use crate::errors::{count_or, shape_error, to_py, unknown_option, InvalidArgumentError};
use numpy::{
    AllowTypeChange, PyArray1, PyArray2, PyArray3, PyArrayLikeDyn, PyArrayMethods,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use torso_core::forecaster::option_named;
use torso_core::{Extrapolation, FilterMode, FilterSplineConfig, LambdaUnit, Method, Pose};

/// ForecasterConfig(method="filter_spline", *, ...): every forecasting choice, validated.
#[pyclass(module = "torsocast._core", frozen, eq)]
#[derive(Clone)]
pub struct ForecasterConfig {
    pub inner: torso_core::ForecasterConfig,
}

impl PartialEq for ForecasterConfig {
    fn eq(&self, other: &Self) -> bool {
        self.inner == other.inner
    }
}

fn parse<T: Copy>(name: &str, got: &str, options: &[(&'static str, T)]) -> PyResult<T> {
    option_named(got, options).ok_or_else(|| {
        let keys: Vec<&str> = options.iter().map(|(k, _)| *k).collect();
        unknown_option(name, got, &keys.join(", "))
    })
}

/// The extrapolation rule, with `damping` (time constants) only where the rule is "damped".
fn parse_rule(name: &str, damping: Option<[f64; 5]>) -> PyResult<Extrapolation> {
    match (
        parse("extrapolation", name, &Extrapolation::OPTIONS)?,
        damping,
    ) {
        (Extrapolation::Damped { .. }, Some(time_constants)) => {
            Ok(Extrapolation::Damped { time_constants })
        }
        (rule, None) => Ok(rule),
        (_, Some(_)) => Err(unknown_option(
            "extrapolation",
            name,
            "damped (the only rule that takes `damping`)",
        )),
    }
}

#[pymethods]
impl ForecasterConfig {
    #[new]
    #[pyo3(signature = (
        method=None, *, rate_hz=None, history=None, max_gap=None, fast_path=None,
        velocity_window=None, filter=None, filter_order=None, cutoff_hz=None,
        filter_components=None, degree=None, lam=None, lambda_unit=None, extrapolation=None,
        damping=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        method: Option<&str>,
        rate_hz: Option<f64>,
        history: Option<f64>,
        max_gap: Option<f64>,
        fast_path: Option<bool>,
        velocity_window: Option<f64>,
        filter: Option<&str>,
        filter_order: Option<i64>,
        cutoff_hz: Option<f64>,
        filter_components: Option<Vec<bool>>,
        degree: Option<i64>,
        lam: Option<f64>,
        lambda_unit: Option<&str>,
        extrapolation: Option<&str>,
        damping: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let filter_components: Option<[bool; 5]> = filter_components
            .map(|v| sequence("filter_components", &v))
            .transpose()?;
        let damping: Option<[f64; 5]> = damping.map(|v| sequence("damping", &v)).transpose()?;
        // Every default is the core's (`ForecasterConfig::default()`).
        let d = torso_core::ForecasterConfig::default();
        let Method::FilterSpline(ds) = d.method else {
            unreachable!("the default method is filter + spline")
        };
        let spline = FilterSplineConfig {
            filter: filter.map_or(Ok(ds.filter), |f| parse("filter", f, &FilterMode::OPTIONS))?,
            filter_order: count_or("filter_order", filter_order, ds.filter_order)?,
            cutoff_hz: cutoff_hz.unwrap_or(ds.cutoff_hz),
            filter_components: filter_components.unwrap_or(ds.filter_components),
            degree: count_or("degree", degree, ds.degree)?,
            lam: lam.unwrap_or(ds.lam),
            lambda_unit: lambda_unit.map_or(Ok(ds.lambda_unit), |u| {
                parse("lambda_unit", u, &LambdaUnit::OPTIONS)
            })?,
            extrapolation: parse_rule(extrapolation.unwrap_or(ds.extrapolation.as_str()), damping)?,
        };
        let method = match method.unwrap_or(d.method.as_str()) {
            "filter_spline" => Method::FilterSpline(spline),
            "const" => Method::Const,
            "constant_velocity" => Method::ConstantVelocity {
                window: velocity_window,
            },
            other => return Err(unknown_option("method", other, &Method::NAMES.join(", "))),
        };
        // A setting of another method would be silently ignored: refuse it instead.
        let spline_given = [
            ("filter", filter.is_some()),
            ("filter_order", filter_order.is_some()),
            ("cutoff_hz", cutoff_hz.is_some()),
            ("filter_components", filter_components.is_some()),
            ("degree", degree.is_some()),
            ("lam", lam.is_some()),
            ("lambda_unit", lambda_unit.is_some()),
            ("extrapolation", extrapolation.is_some()),
            ("damping", damping.is_some()),
        ];
        let misplaced = match method {
            Method::FilterSpline(_) => velocity_window.is_some().then_some("velocity_window"),
            _ => spline_given
                .iter()
                .find(|(_, given)| *given)
                .map(|(n, _)| *n),
        }
        .or_else(|| {
            (velocity_window.is_some() && !matches!(method, Method::ConstantVelocity { .. }))
                .then_some("velocity_window")
        });
        if let Some(name) = misplaced {
            return Err(InvalidArgumentError::new_err(format!(
                "`{name}` is not a setting of method {:?}",
                method.as_str()
            )));
        }
        let (rate_hz, history, max_gap, fast_path) = (
            rate_hz.unwrap_or(d.rate_hz),
            history.unwrap_or(d.history),
            max_gap.unwrap_or(d.max_gap),
            fast_path.unwrap_or(d.fast_path),
        );
        let inner = torso_core::ForecasterConfig {
            rate_hz,
            history,
            max_gap,
            method,
            fast_path,
        };
        inner.validate().map_err(to_py)?;
        Ok(Self { inner })
    }

    #[getter]
    fn method(&self) -> &'static str {
        self.inner.method.as_str()
    }

    /// options() -> dict of each option's names: method, filter, lambda_unit, extrapolation
    /// (the core's vocabulary, for command lines and forms).
    #[staticmethod]
    fn options(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        fn names<T>(options: &[(&'static str, T)]) -> Vec<&'static str> {
            options.iter().map(|(k, _)| *k).collect()
        }
        let dict = PyDict::new(py);
        dict.set_item("method", Method::NAMES.to_vec())?;
        dict.set_item("filter", names(&FilterMode::OPTIONS))?;
        dict.set_item("lambda_unit", names(&LambdaUnit::OPTIONS))?;
        dict.set_item("extrapolation", names(&Extrapolation::OPTIONS))?;
        Ok(dict)
    }
    #[getter]
    fn rate_hz(&self) -> f64 {
        self.inner.rate_hz
    }
    #[getter]
    fn history(&self) -> f64 {
        self.inner.history
    }
    #[getter]
    fn max_gap(&self) -> f64 {
        self.inner.max_gap
    }
    #[getter]
    fn fast_path(&self) -> bool {
        self.inner.fast_path
    }
    /// The constant-velocity window (s); None for the whole history or another method.
    #[getter]
    fn velocity_window(&self) -> Option<f64> {
        match self.inner.method {
            Method::ConstantVelocity { window } => window,
            _ => None,
        }
    }
    // The filter + spline settings: None for the other methods, which have none.
    #[getter]
    fn filter(&self) -> Option<&'static str> {
        self.spline().map(|s| s.filter.as_str())
    }
    #[getter]
    fn filter_order(&self) -> Option<usize> {
        self.spline().map(|s| s.filter_order)
    }
    #[getter]
    fn cutoff_hz(&self) -> Option<f64> {
        self.spline().map(|s| s.cutoff_hz)
    }
    #[getter]
    fn filter_components(&self) -> Option<[bool; 5]> {
        self.spline().map(|s| s.filter_components)
    }
    #[getter]
    fn degree(&self) -> Option<usize> {
        self.spline().map(|s| s.degree)
    }
    #[getter]
    fn lam(&self) -> Option<f64> {
        self.spline().map(|s| s.lam)
    }
    #[getter]
    fn lambda_unit(&self) -> Option<&'static str> {
        self.spline().map(|s| s.lambda_unit.as_str())
    }
    #[getter]
    fn extrapolation(&self) -> Option<&'static str> {
        self.spline().map(|s| s.extrapolation.as_str())
    }
    /// Time constants (s) of the damped trend per component; None for the other rules.
    #[getter]
    fn damping(&self) -> Option<[f64; 5]> {
        match self.spline()?.extrapolation {
            Extrapolation::Damped { time_constants } => Some(time_constants),
            _ => None,
        }
    }
    /// Samples in a full history.
    #[getter]
    fn capacity(&self) -> usize {
        self.inner.capacity()
    }

    /// live() -> ForecasterConfig: the thesis' forecaster with the low-pass on all five
    /// components at 1 Hz, for poses from a keypoint detector (what tracking uses).
    #[staticmethod]
    fn live() -> Self {
        Self::live_config()
    }

    /// Pickling by keywords: every setting the method has, as `__new__` takes them.
    fn __getnewargs_ex__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        crate::config::newargs(py, self.fields(py)?)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        crate::config::repr("ForecasterConfig", self.fields(py)?)
    }
}

fn config_or_default(config: Option<PyRef<'_, ForecasterConfig>>) -> torso_core::ForecasterConfig {
    config.map_or_else(torso_core::ForecasterConfig::default, |c| c.inner)
}

impl ForecasterConfig {
    /// The thesis defaults, as `ForecasterConfig()` gives them.
    fn default_config() -> Self {
        Self::from_core(torso_core::ForecasterConfig::default())
    }

    /// The core's configuration for detector input, as `ForecasterConfig.live()` gives it.
    pub fn live_config() -> Self {
        Self::from_core(torso_core::ForecasterConfig::live())
    }

    pub fn from_core(inner: torso_core::ForecasterConfig) -> Self {
        Self { inner }
    }

    /// Every setting the method has, by its keyword (the repr and pickling list these).
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<crate::config::Fields<'py>> {
        let mut fields = vec![
            ("method", self.method().into_pyobject(py)?.into_any()),
            ("rate_hz", self.rate_hz().into_pyobject(py)?.into_any()),
            ("history", self.history().into_pyobject(py)?.into_any()),
            ("max_gap", self.max_gap().into_pyobject(py)?.into_any()),
            (
                "fast_path",
                self.fast_path().into_pyobject(py)?.to_owned().into_any(),
            ),
        ];
        if let Method::ConstantVelocity { window } = self.inner.method {
            fields.push(("velocity_window", window.into_pyobject(py)?.into_any()));
        }
        if let Some(s) = self.spline() {
            fields.extend([
                ("filter", s.filter.as_str().into_pyobject(py)?.into_any()),
                ("filter_order", s.filter_order.into_pyobject(py)?.into_any()),
                ("cutoff_hz", s.cutoff_hz.into_pyobject(py)?.into_any()),
                (
                    "filter_components",
                    s.filter_components.into_pyobject(py)?.into_any(),
                ),
                ("degree", s.degree.into_pyobject(py)?.into_any()),
                ("lam", s.lam.into_pyobject(py)?.into_any()),
                (
                    "lambda_unit",
                    s.lambda_unit.as_str().into_pyobject(py)?.into_any(),
                ),
                (
                    "extrapolation",
                    s.extrapolation.as_str().into_pyobject(py)?.into_any(),
                ),
            ]);
            if let Extrapolation::Damped { time_constants } = s.extrapolation {
                fields.push(("damping", time_constants.into_pyobject(py)?.into_any()));
            }
        }
        Ok(fields)
    }

    fn spline(&self) -> Option<&FilterSplineConfig> {
        match &self.inner.method {
            Method::FilterSpline(s) => Some(s),
            _ => None,
        }
    }
}

/// Forecaster(config=None): one tracked person's torso pose forecaster.
#[pyclass(module = "torsocast._core")]
pub struct Forecaster {
    inner: torso_core::Forecaster,
    /// The config as given, so `config` answers with every field the caller set.
    config: ForecasterConfig,
    scratch: Vec<Pose>,
}

#[pymethods]
impl Forecaster {
    #[new]
    #[pyo3(signature = (config=None))]
    fn new(config: Option<PyRef<'_, ForecasterConfig>>) -> PyResult<Self> {
        let config = config.map_or_else(ForecasterConfig::default_config, |c| c.clone());
        Ok(Self {
            inner: torso_core::Forecaster::new(config.inner).map_err(to_py)?,
            config,
            scratch: Vec::new(),
        })
    }

    /// update(pose, t, weight=1.0) -> (filled, restarted)
    #[pyo3(signature = (pose, t, weight=1.0))]
    fn update(&mut self, pose: Vec<f64>, t: f64, weight: f64) -> PyResult<(usize, bool)> {
        let pose = sequence("pose", &pose)?;
        let r = self.inner.update(pose, t, weight).map_err(to_py)?;
        Ok((r.filled, r.restarted))
    }

    /// forecast(horizons) -> array (len(horizons), 5)
    fn forecast<'py>(
        &mut self,
        py: Python<'py>,
        horizons: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.scratch.resize(horizons.len(), [0.0; 5]);
        self.inner
            .forecast(&horizons, &mut self.scratch)
            .map_err(to_py)?;
        Ok(matrix(py, &self.scratch))
    }

    fn reset(&mut self) {
        self.inner.reset();
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    #[getter]
    fn capacity(&self) -> usize {
        self.inner.capacity()
    }

    #[getter]
    fn min_samples(&self) -> usize {
        self.inner.min_samples()
    }

    #[getter]
    fn last_time(&self) -> Option<f64> {
        self.inner.last_time()
    }

    #[getter]
    fn config(&self) -> ForecasterConfig {
        self.config.clone()
    }

    /// history() -> (poses (n, 5) with azimuth unwrapped, weights (n,))
    fn history<'py>(&self, py: Python<'py>) -> ArrayPair<'py, PyArray2<f64>, PyArray1<f64>> {
        let (p, w): (Vec<Pose>, Vec<f64>) = (0..self.inner.len())
            .filter_map(|i| self.inner.sample(i))
            .unzip();
        Ok((matrix(py, &p), PyArray1::from_vec(py, w)))
    }
}

/// forecast_batch(histories, horizons, config=None) -> array (n, len(horizons), 5)
#[pyfunction]
#[pyo3(signature = (histories, horizons, config=None))]
pub fn forecast_batch<'py>(
    py: Python<'py>,
    histories: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    horizons: Vec<f64>,
    config: Option<PyRef<'py, ForecasterConfig>>,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let shape = histories.shape().to_vec();
    if shape.len() != 3 || shape[2] != 5 || shape[1] == 0 {
        return Err(shape_error("histories", "(n, T, 5) with T >= 1", &shape));
    }
    let view = histories.as_array();
    let flat = c_order(&view);
    let flat: &[f64] = &flat;
    let config = config_or_default(config);
    let h = horizons.len();
    let window_len = shape[1];
    let out = py
        .detach(|| -> Result<Vec<f64>, torso_core::Error> {
            let mut out = vec![0.0; shape[0] * h * 5];
            torso_core::forecast_batch(&config, flat, window_len, &horizons, &mut out)?;
            Ok(out)
        })
        .map_err(to_py)?;
    PyArray1::from_vec(py, out).reshape([shape[0], h, 5])
}
