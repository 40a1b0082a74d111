//! What a forecaster is configured with: the method, the filter, the spline and its
//! continuation, each option with its name (the vocabulary of the bindings and the command line).

use super::Forecaster;
use crate::error::Result;

/// How the history is low-pass filtered before the spline fit.
///
/// ```
/// use torso_core::forecaster::{option_named, FilterMode};
/// assert_eq!(option_named("causal", &FilterMode::OPTIONS), Some(FilterMode::Causal));
/// assert_eq!(FilterMode::ZeroPhase.as_str(), "zero_phase");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterMode {
    /// No filter (the thesis' "no filter" ablation).
    Off,
    /// Causal filtering of the history window, started in steady state at its first sample.
    /// Lags the signal by the filter's group delay, as a filter running on a robot would.
    Causal,
    /// Forward-backward (`sosfiltfilt`) filtering of the history window: no lag, but the last
    /// samples depend on the odd extension at the window's end.
    ZeroPhase,
}

impl FilterMode {
    /// Every mode with its name, for bindings and command lines.
    pub const OPTIONS: [(&'static str, FilterMode); 3] = [
        ("off", FilterMode::Off),
        ("causal", FilterMode::Causal),
        ("zero_phase", FilterMode::ZeroPhase),
    ];

    pub fn as_str(self) -> &'static str {
        name_of(self, &Self::OPTIONS)
    }
}

/// The time unit of the spline abscissae, which sets what `lam` means: the penalty
/// `λ ∫ f''(t)² dt` scales with the unit cubed.
///
/// ```
/// use torso_core::LambdaUnit;
/// assert_eq!(LambdaUnit::Seconds.as_str(), "seconds");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LambdaUnit {
    /// Knots at 0, 1, 2, ... (sample index).
    Samples,
    /// Knots at the sample times in seconds.
    Seconds,
}

impl LambdaUnit {
    /// Every unit with its name, for bindings and command lines.
    pub const OPTIONS: [(&'static str, LambdaUnit); 2] = [
        ("samples", LambdaUnit::Samples),
        ("seconds", LambdaUnit::Seconds),
    ];

    pub fn as_str(self) -> &'static str {
        name_of(self, &Self::OPTIONS)
    }
}

/// How the fitted spline is continued past the last sample.
///
/// ```
/// use torso_core::Extrapolation;
/// // Hold the azimuth's slope for about 0.2 s, the position's for 2 s.
/// let rule = Extrapolation::Damped { time_constants: [2.0, 2.0, 2.0, 0.2, 0.1] };
/// assert_eq!(rule.as_str(), "damped");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Extrapolation {
    /// Continue the last polynomial piece (what `scipy.interpolate.BSpline` does).
    Polynomial,
    /// Continue the tangent at the last sample (value and slope of the last piece).
    Linear,
    /// A damped trend (not in the thesis): the value and slope at the last sample, the slope
    /// decaying with a time constant `T_c` (seconds) per component, so that
    /// `f_c(τ) = d_c0 + d_c1 · T_c (1 - e^{-τ/T_c})`. `T_c = 0` holds the last value (Const),
    /// `T_c = ∞` is [`Extrapolation::Linear`]. People rarely keep turning or leaning at the
    /// same rate for two seconds; the slope is evidence about the next few hundred ms only.
    Damped { time_constants: [f64; 5] },
}

impl Extrapolation {
    /// Time constants selected on Human3.6M S1 (the training subject; see docs/reproduction.md)
    /// for x, y, z, azimuth and elevation: position keeps its velocity longest, elevation
    /// (leaning) reverts fastest.
    pub const DAMPED_H36M_S1: Extrapolation = Extrapolation::Damped {
        time_constants: [1.5, 1.5, 1.5, 0.5, 0.1],
    };

    /// Every rule with its name ("damped" with the default time constants), for bindings and
    /// command lines.
    pub const OPTIONS: [(&'static str, Extrapolation); 3] = [
        ("polynomial", Extrapolation::Polynomial),
        ("linear", Extrapolation::Linear),
        ("damped", Extrapolation::DAMPED_H36M_S1),
    ];

    /// The rule's name; a damped rule is "damped" whatever its time constants.
    pub fn as_str(self) -> &'static str {
        name_of(self, &Self::OPTIONS)
    }
}

/// The option's name, matched by variant only.
fn name_of<T>(value: T, options: &[(&'static str, T)]) -> &'static str {
    let variant = std::mem::discriminant(&value);
    options
        .iter()
        .find(|(_, v)| std::mem::discriminant(v) == variant)
        .map_or("?", |(k, _)| k)
}

/// The option called `name`, if there is one.
pub fn option_named<T: Copy>(name: &str, options: &[(&'static str, T)]) -> Option<T> {
    options.iter().find(|(k, _)| *k == name).map(|(_, v)| *v)
}

/// `T (1 - e^{-τ/T})`: how far a unit slope decaying with time constant `T` carries in `τ`.
pub(super) fn damped_time(time_constant: f64, tau: f64) -> f64 {
    if time_constant == 0.0 {
        0.0
    } else if time_constant.is_infinite() {
        tau
    } else {
        -time_constant * (-tau / time_constant).exp_m1()
    }
}

/// The thesis' filter + spline forecaster.
///
/// ```
/// use torso_core::{FilterSplineConfig, ForecasterConfig, Method};
/// let cubic = FilterSplineConfig { degree: 3, ..FilterSplineConfig::default() };
/// let config = ForecasterConfig { method: Method::FilterSpline(cubic), ..ForecasterConfig::default() };
/// assert!(config.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSplineConfig {
    pub filter: FilterMode,
    /// Butterworth order. Thesis: 2.
    pub filter_order: usize,
    /// Butterworth cut-off (Hz). Thesis: 5 Hz.
    pub cutoff_hz: f64,
    /// Which of `[x, y, z, azimuth, elevation]` are filtered. Thesis: the two angles.
    pub filter_components: [bool; 5],
    /// Spline degree `N` (0 to 4). Thesis: 1.
    pub degree: usize,
    /// Roughness weight λ. Thesis: 1.
    pub lam: f64,
    pub lambda_unit: LambdaUnit,
    pub extrapolation: Extrapolation,
}

impl Default for FilterSplineConfig {
    fn default() -> Self {
        Self {
            filter: FilterMode::ZeroPhase,
            filter_order: 2,
            cutoff_hz: 5.0,
            filter_components: [false, false, false, true, true],
            degree: 1,
            lam: 1.0,
            lambda_unit: LambdaUnit::Samples,
            // Not the thesis' rule (it continues the last polynomial piece): on Human3.6M the
            // damped trend beats Const and both constant-velocity baselines at 0.4, 1 and 2 s,
            // and the thesis' rule does not (docs/reproduction.md).
            extrapolation: Extrapolation::DAMPED_H36M_S1,
        }
    }
}

/// The forecasting method.
///
/// ```
/// use torso_core::{ForecasterConfig, Method};
/// let config = ForecasterConfig::constant_velocity(Some(0.4));
/// assert_eq!(config.method, Method::ConstantVelocity { window: Some(0.4) });
/// assert_eq!(config.method.as_str(), "constant_velocity");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Zero velocity: the last pose, held ("Const" in the thesis).
    Const,
    /// The mean velocity over the last `window` seconds (`None`: the whole history), integrated.
    ConstantVelocity { window: Option<f64> },
    /// Low-pass filter, penalised spline fit, extrapolation.
    FilterSpline(FilterSplineConfig),
}

impl Method {
    /// The methods' names, for bindings and command lines.
    pub const NAMES: [&'static str; 3] = ["filter_spline", "const", "constant_velocity"];

    pub fn as_str(&self) -> &'static str {
        match self {
            Method::FilterSpline(_) => "filter_spline",
            Method::Const => "const",
            Method::ConstantVelocity { .. } => "constant_velocity",
        }
    }
}

/// Everything a forecaster needs to know; every choice the thesis leaves open is a field.
///
/// ```
/// use torso_core::ForecasterConfig;
/// let live = ForecasterConfig::live(); // for detector input: all five components low-passed
/// assert_eq!(live.capacity(), 50); // 2 s at 25 Hz
/// assert!(ForecasterConfig { rate_hz: 0.0, ..live }.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForecasterConfig {
    /// Rate of the fixed time grid (Hz). Thesis: 25 Hz.
    pub rate_hz: f64,
    /// History length (s). Thesis: 2 s, i.e. 50 samples at 25 Hz.
    pub history: f64,
    /// Longest gap (s) that is bridged by interpolated, zero-weight samples; a longer one
    /// restarts the history.
    pub max_gap: f64,
    pub method: Method,
    /// Use the precomputed linear map when the weights are uniform and the history full.
    pub fast_path: bool,
}

impl Default for ForecasterConfig {
    fn default() -> Self {
        Self {
            rate_hz: 25.0,
            history: 2.0,
            max_gap: 0.4,
            method: Method::FilterSpline(FilterSplineConfig::default()),
            fast_path: true,
        }
    }
}

impl ForecasterConfig {
    /// The zero-velocity baseline on the default grid.
    pub fn constant() -> Self {
        Self {
            method: Method::Const,
            ..Self::default()
        }
    }

    /// The thesis' forecaster with its Butterworth low-pass on all five pose components at 1 Hz,
    /// for poses from a keypoint detector. The thesis filters only the angles (its mocap
    /// positions are clean) at 5 Hz; a detector's centres jitter by centimetres, and with N = 1
    /// the spline interpolates, so the forecast continues the last noisy step. On the bundled CMU
    /// training walks seen through the demo's camera and MoveNet, the median centre error 1 s
    /// ahead drops from 79 to 42 cm (holding still: 100 cm); 0.7 to 2 Hz were tried
    /// (docs/demo.md).
    pub fn live() -> Self {
        Self {
            method: Method::FilterSpline(FilterSplineConfig {
                cutoff_hz: 1.0,
                filter_components: [true; 5],
                ..FilterSplineConfig::default()
            }),
            ..Self::default()
        }
    }

    /// A constant-velocity baseline on the default grid.
    pub fn constant_velocity(window: Option<f64>) -> Self {
        Self {
            method: Method::ConstantVelocity { window },
            ..Self::default()
        }
    }

    /// Samples in a full history.
    pub fn capacity(&self) -> usize {
        (self.history * self.rate_hz).round() as usize
    }

    /// Checks every field, as [`Forecaster::new`] would, without precomputing the fast path.
    pub fn validate(&self) -> Result<()> {
        Forecaster::new(Self {
            fast_path: false,
            ..*self
        })
        .map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_option_is_found_by_its_name() {
        for (name, mode) in FilterMode::OPTIONS {
            assert_eq!(
                (option_named(name, &FilterMode::OPTIONS), mode.as_str()),
                (Some(mode), name)
            );
        }
        for (name, unit) in LambdaUnit::OPTIONS {
            assert_eq!(
                (option_named(name, &LambdaUnit::OPTIONS), unit.as_str()),
                (Some(unit), name)
            );
        }
        for (name, rule) in Extrapolation::OPTIONS {
            assert_eq!(option_named(name, &Extrapolation::OPTIONS), Some(rule));
            assert_eq!(rule.as_str(), name);
        }
        let custom = Extrapolation::Damped {
            time_constants: [1.0; 5],
        };
        assert_eq!(custom.as_str(), "damped");
        let methods = [
            Method::FilterSpline(FilterSplineConfig::default()),
            Method::Const,
            Method::ConstantVelocity { window: None },
        ];
        assert_eq!(methods.map(|m| m.as_str()), Method::NAMES);
        assert_eq!(option_named("zero-phase", &FilterMode::OPTIONS), None);
    }
}
