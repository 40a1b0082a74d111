//! Butterworth low-pass design and filtering in second-order sections (thesis section 3.3.1).
//!
//! The design follows SciPy step by step (`buttap` → `lp2lp_zpk` → `bilinear_zpk` →
//! `zpk2sos(pairing='nearest')`), so [`design_lowpass`] equals
//! `scipy.signal.butter(order, cutoff_hz, fs=rate_hz, output='sos')` to rounding. Filtering uses
//! the transposed direct form II of `sosfilt`; [`SosFilter::steady_state`] is `sosfilt_zi`, and
//! [`ZeroPhase`] is `sosfiltfilt` with its default odd padding.

use crate::error::{check_positive, Error, Result};
use nalgebra::Complex;
use std::f64::consts::PI;

/// Highest supported filter order.
pub const MAX_ORDER: usize = 8;

/// One biquad `[b0, b1, b2, 1, a1, a2]`, as a row of SciPy's `sos` array.
pub type Section = [f64; 6];

/// A cascade of second-order sections and its unit-step steady state.
///
/// ```
/// use torso_core::design_lowpass;
/// // The thesis' filter: 2nd order, 5 Hz at 25 Hz, as second-order sections.
/// let filter = design_lowpass(2, 5.0, 25.0).unwrap();
/// let mut x = [1.0; 10];
/// filter.filter_from_steady_state(&mut x);
/// assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-12)); // unit gain at 0 Hz
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SosFilter {
    sections: Vec<Section>,
    /// `sosfilt_zi(sos)`: the section states for a constant input of 1.
    zi: Vec<[f64; 2]>,
}

/// Lowest cut-off frequency, as a fraction of the sample rate.
pub const MIN_CUTOFF_PER_RATE: f64 = 1e-5;

/// Designs an `order`-th order Butterworth low-pass with cut-off `cutoff_hz` for samples at
/// `rate_hz`.
pub fn design_lowpass(order: usize, cutoff_hz: f64, rate_hz: f64) -> Result<SosFilter> {
    check_positive("rate_hz", rate_hz, "a positive, finite sample rate in Hz")?;
    if !(1..=MAX_ORDER).contains(&order) {
        return Err(Error::InvalidArgument {
            name: "order",
            expected: "a filter order from 1 to 8",
            value: order as f64,
        });
    }
    // Below a hundred-thousandth of the rate (the longest history's resolution) the design's
    // poles sit on 1 to rounding and its steady state divides by zero.
    if !(cutoff_hz.is_finite()
        && cutoff_hz >= MIN_CUTOFF_PER_RATE * rate_hz
        && cutoff_hz < 0.5 * rate_hz)
    {
        return Err(Error::InvalidArgument {
            name: "cutoff_hz",
            expected: "a cut-off frequency from rate_hz / 100000 up to (not including) the \
                       Nyquist frequency rate_hz / 2",
            value: cutoff_hz,
        });
    }
    // Analogue prototype poles on the unit circle, pre-warped for the bilinear transform at
    // SciPy's internal fs = 2.
    let wn = cutoff_hz / (0.5 * rate_hz);
    let warped = 4.0 * (PI * wn / 2.0).tan();
    let n = order as i32;
    let mut poles: Vec<Complex<f64>> = Vec::with_capacity(order + 1);
    let mut gain = warped.powi(n);
    let mut denominator = Complex::new(1.0, 0.0);
    for m in (-(n - 1)..=(n - 1)).step_by(2) {
        let analog = -Complex::from_polar(1.0, PI * m as f64 / (2.0 * n as f64)) * warped;
        denominator *= Complex::new(4.0, 0.0) - analog;
        poles.push((Complex::new(4.0, 0.0) + analog) / (Complex::new(4.0, 0.0) - analog));
    }
    gain *= (Complex::new(1.0, 0.0) / denominator).re;
    let zeros = vec![Complex::new(-1.0, 0.0); order];
    let sections = zpk2sos_nearest(zeros, poles, gain);
    let zi = steady_state(&sections);
    Ok(SosFilter { sections, zi })
}

/// `scipy.signal.zpk2sos(z, p, k, pairing='nearest')` for a digital filter whose zeros are real.
fn zpk2sos_nearest(mut z: Vec<Complex<f64>>, mut p: Vec<Complex<f64>>, k: f64) -> Vec<Section> {
    let n_sections = p.len().div_ceil(2);
    if p.len() % 2 == 1 {
        p.push(Complex::new(0.0, 0.0));
        z.push(Complex::new(0.0, 0.0));
    }
    // Like `_cplxreal`: keep one member (positive imaginary part) of each conjugate pair, then
    // the real ones with their imaginary parts set to exactly zero.
    let tol = 100.0 * f64::EPSILON;
    let is_real = |c: &Complex<f64>| c.im.abs() <= tol * c.norm();
    let mut p_cplx: Vec<Complex<f64>> = p
        .iter()
        .filter(|c| !is_real(c) && c.im > 0.0)
        .copied()
        .collect();
    p_cplx.sort_by(|a, b| a.re.total_cmp(&b.re));
    let p_real = p
        .iter()
        .filter(|c| is_real(c))
        .map(|c| Complex::new(c.re, 0.0));
    let mut p: Vec<Complex<f64>> = p_cplx.into_iter().chain(p_real).collect();
    let mut z: Vec<Complex<f64>> = z.iter().map(|c| Complex::new(c.re, 0.0)).collect();

    let worst = |v: &[Complex<f64>], among: &dyn Fn(&Complex<f64>) -> bool| -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (i, c) in v.iter().enumerate() {
            if !among(c) {
                continue;
            }
            let d = (1.0 - c.norm()).abs();
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((i, d));
            }
        }
        best.map(|(i, _)| i)
    };
    let nearest = |v: &[Complex<f64>], to: Complex<f64>, real_only: bool| -> usize {
        let mut best: Option<(usize, f64)> = None;
        for (i, c) in v.iter().enumerate() {
            if real_only && c.im != 0.0 {
                continue;
            }
            let d = (c - to).norm();
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((i, d));
            }
        }
        best.expect("zpk2sos pairs as many zeros as poles").0
    };

    let mut sections = vec![[0.0; 6]; n_sections];
    for si in (0..n_sections).rev() {
        let p1 = p.remove(worst(&p, &|_| true).expect("a pole per section"));
        let p2 = if p1.im == 0.0 {
            if !p.iter().any(|c| c.im == 0.0) {
                // Special case (1) of SciPy: the last remaining real pole.
                let z1 = z.remove(nearest(&z, p1, true));
                sections[si] = biquad([z1.re, 0.0], [p1.re, 0.0]);
                continue;
            }
            p.remove(worst(&p, &|c| c.im == 0.0).expect("a real pole"))
        } else {
            p1.conj()
        };
        // All zeros are real here, so the nearest zero is real and a second real zero follows.
        let z1 = z.remove(nearest(&z, p1, false));
        let z2 = z.remove(nearest(&z, p1, true));
        sections[si] = if p1.im == 0.0 {
            biquad([z1.re, z2.re], [p1.re, p2.re])
        } else {
            let b = [1.0, -(z1.re + z2.re), z1.re * z2.re];
            let a = [1.0, -2.0 * p1.re, (p1 * p2).re];
            [b[0], b[1], b[2], a[0], a[1], a[2]]
        };
    }
    for c in &mut sections[0][..3] {
        *c *= k;
    }
    sections
}

/// Section with two real zeros and two real poles.
fn biquad(z: [f64; 2], p: [f64; 2]) -> Section {
    [
        1.0,
        -(z[0] + z[1]),
        z[0] * z[1],
        1.0,
        -(p[0] + p[1]),
        p[0] * p[1],
    ]
}

/// `sosfilt_zi`: per-section states that make a constant unit input pass through unchanged.
fn steady_state(sections: &[Section]) -> Vec<[f64; 2]> {
    let mut scale = 1.0;
    sections
        .iter()
        .map(|s| {
            // lfilter_zi for a biquad, solved in closed form: (I - Aᵀ) zi = b[1:] - a[1:] b0.
            let (b0, b1, b2, a1, a2) = (s[0], s[1], s[2], s[4], s[5]);
            let (r0, r1) = (b1 - a1 * b0, b2 - a2 * b0);
            let z0 = (r0 + r1) / (1.0 + a1 + a2);
            let zi = [scale * z0, scale * (r1 - a2 * z0)];
            scale *= (b0 + b1 + b2) / (1.0 + a1 + a2);
            zi
        })
        .collect()
}

impl SosFilter {
    /// The sections as SciPy's `(n_sections, 6)` rows.
    pub fn sections(&self) -> &[Section] {
        &self.sections
    }

    /// `sosfilt_zi(sos)`: the state for a constant input of 1 (scale it by the first sample).
    pub fn steady_state(&self) -> &[[f64; 2]] {
        &self.zi
    }

    /// Number of sections.
    pub fn len(&self) -> usize {
        self.sections.len()
    }

    /// Never true: a designed filter has at least one section.
    pub fn is_empty(&self) -> bool {
        self.sections.is_empty()
    }

    /// Sets `state` to the steady state for a constant input `x0`.
    pub fn start_at(&self, x0: f64, state: &mut [[f64; 2]]) {
        for (s, zi) in state.iter_mut().zip(&self.zi) {
            *s = [zi[0] * x0, zi[1] * x0];
        }
    }

    /// One sample through the cascade (transposed direct form II, as `sosfilt`).
    #[inline]
    pub fn step(&self, x: f64, state: &mut [[f64; 2]]) -> f64 {
        let mut v = x;
        for (s, z) in self.sections.iter().zip(state.iter_mut()) {
            let y = s[0] * v + z[0];
            z[0] = s[1] * v - s[4] * y + z[1];
            z[1] = s[2] * v - s[5] * y;
            v = y;
        }
        v
    }

    /// [`filter_from_steady_state`](Self::filter_from_steady_state) for a window from a caller:
    /// a window with a non-finite sample is refused and left as it was.
    pub fn filter_window(&self, x: &mut [f64]) -> Result<()> {
        check_samples("x", x)?;
        self.filter_from_steady_state(x);
        Ok(())
    }

    /// Causal filtering of a window in place, starting in steady state at its first sample:
    /// `sosfilt(sos, x, zi=sosfilt_zi(sos) * x[0])`.
    pub fn filter_from_steady_state(&self, x: &mut [f64]) {
        self.cascade(x, false);
    }

    /// Runs a whole window through the cascade, one section after the other, each starting in
    /// its steady state for a constant input at the window's first sample (its last, running
    /// `backward`). Section by section, the state stays in registers; sample by sample (as
    /// [`SosFilter::step`]), a window took 2.5 times as long. Each sample meets the same
    /// operations in the same order either way, and in every lane of a [`Lanes`] sample.
    fn cascade<T: Lanes>(&self, x: &mut [T], backward: bool) {
        let Some(&(mut x0)) = (if backward { x.last() } else { x.first() }) else {
            return;
        };
        let x0 = x0.values();
        for (s, zi) in self.sections.iter().zip(&self.zi) {
            let (mut z0, mut z1) = (T::splat(0.0), T::splat(0.0));
            for ((a, b), v) in z0.values().iter_mut().zip(z1.values()).zip(&*x0) {
                (*a, *b) = (zi[0] * v, zi[1] * v);
            }
            let mut section = |t: &mut T| {
                let lanes = t.values().iter_mut().zip(z0.values()).zip(z1.values());
                for ((v, z0), z1) in lanes {
                    let y = s[0] * *v + *z0;
                    *z0 = s[1] * *v - s[4] * y + *z1;
                    *z1 = s[2] * *v - s[5] * y;
                    *v = y;
                }
            };
            if backward {
                x.iter_mut().rev().for_each(&mut section);
            } else {
                x.iter_mut().for_each(&mut section);
            }
        }
    }

    /// SciPy's default `sosfiltfilt` pad length for this filter.
    pub fn default_padlen(&self) -> usize {
        let trailing_b = self.sections.iter().filter(|s| s[2] == 0.0).count();
        let trailing_a = self.sections.iter().filter(|s| s[5] == 0.0).count();
        3 * (2 * self.sections.len() + 1 - trailing_b.min(trailing_a))
    }
}

/// A streaming causal low-pass: feed one sample at a time. The first sample sets the steady
/// state, so the output equals `sosfilt(sos, x, zi=sosfilt_zi(sos) * x[0])`.
///
/// ```
/// use torso_core::{design_lowpass, LowPass};
/// let mut low_pass = LowPass::new(design_lowpass(2, 1.0, 25.0).unwrap());
/// let first = low_pass.step(1.0).unwrap(); // starts in steady state at the first sample
/// assert!((first - 1.0).abs() < 1e-12);
/// assert!(low_pass.step(f64::NAN).is_err()); // refused, state unchanged
/// ```
#[derive(Clone, Debug)]
pub struct LowPass {
    filter: SosFilter,
    state: Vec<[f64; 2]>,
    started: bool,
}

impl LowPass {
    pub fn new(filter: SosFilter) -> Self {
        let state = vec![[0.0; 2]; filter.len()];
        Self {
            filter,
            state,
            started: false,
        }
    }

    /// Filters the samples of `x` in place, continuing from the current state. A window with a
    /// non-finite sample is refused before any sample changes the state.
    pub fn filter_window(&mut self, x: &mut [f64]) -> Result<()> {
        check_samples("x", x)?;
        for v in x.iter_mut() {
            *v = self.step(*v)?;
        }
        Ok(())
    }

    /// Filters one sample. A non-finite sample is rejected and leaves the state untouched.
    pub fn step(&mut self, x: f64) -> Result<f64> {
        check_samples("x", &[x])?;
        if !self.started {
            self.filter.start_at(x, &mut self.state);
            self.started = true;
        }
        Ok(self.filter.step(x, &mut self.state))
    }

    /// Forgets the past: the next sample starts a new steady state.
    pub fn reset(&mut self) {
        self.started = false;
    }

    pub fn filter(&self) -> &SosFilter {
        &self.filter
    }
}

/// Zero-phase forward-backward filtering of windows of up to `capacity` samples, equal to
/// `sosfiltfilt(sos, x)` (odd extension of SciPy's default length at each end). A window no
/// longer than that padding is padded by `len - 1` instead (SciPy would refuse it).
///
/// ```
/// use torso_core::{design_lowpass, ZeroPhase};
/// let mut filter = ZeroPhase::new(design_lowpass(2, 5.0, 25.0).unwrap(), 50);
/// let ramp: Vec<f64> = (0..50).map(|k| k as f64 * 0.04).collect();
/// let mut out = vec![0.0; 50];
/// filter.apply(&ramp, &mut out).unwrap();
/// // No lag: a ramp comes through forward-backward filtering unchanged inside the window and
/// // within a small end transient at its last sample.
/// assert!((out[25] - ramp[25]).abs() < 1e-9 && (out[49] - ramp[49]).abs() < 1e-4);
/// ```
#[derive(Clone, Debug)]
pub struct ZeroPhase(ForwardBackward<f64>);

impl ZeroPhase {
    pub fn new(filter: SosFilter, capacity: usize) -> Self {
        Self(ForwardBackward::new(filter, capacity))
    }

    /// Filters `x` into `out` (same length, at most `capacity`).
    pub fn apply(&mut self, x: &[f64], out: &mut [f64]) -> Result<()> {
        crate::error::check_len("out", out.len(), x.len())?;
        self.0.check_len(x.len())?;
        check_samples("x", x)?;
        out.copy_from_slice(self.0.filter(x.len(), |i| x[i]));
        Ok(())
    }

    pub fn padlen(&self) -> usize {
        self.0.padlen
    }
}

/// A sample of the filters: one series' value (`f64`), or the values of several series
/// filtered side by side (`[f64; L]`), whose recursions are independent, so that their
/// latencies overlap instead of adding up.
pub(crate) trait Lanes: Copy {
    fn splat(value: f64) -> Self;
    fn values(&mut self) -> &mut [f64];
}

impl Lanes for f64 {
    fn splat(value: f64) -> Self {
        value
    }

    fn values(&mut self) -> &mut [f64] {
        std::slice::from_mut(self)
    }
}

impl<const L: usize> Lanes for [f64; L] {
    fn splat(value: f64) -> Self {
        [value; L]
    }

    fn values(&mut self) -> &mut [f64] {
        self
    }
}

/// [`ZeroPhase`] of [`Lanes`] samples: each lane filtered as [`ZeroPhase::apply`] filters one
/// series.
#[derive(Clone, Debug)]
pub(crate) struct ForwardBackward<T> {
    filter: SosFilter,
    padlen: usize,
    capacity: usize,
    extended: Vec<T>,
}

impl<T: Lanes> ForwardBackward<T> {
    pub(crate) fn new(filter: SosFilter, capacity: usize) -> Self {
        let padlen = filter.default_padlen();
        Self {
            filter,
            padlen,
            capacity,
            extended: vec![T::splat(0.0); capacity + 2 * padlen],
        }
    }

    /// Refuses a window longer than the capacity.
    pub(crate) fn check_len(&self, n: usize) -> Result<()> {
        if n > self.capacity {
            return Err(Error::LengthMismatch {
                name: "x",
                expected: self.capacity,
                got: n,
            });
        }
        Ok(())
    }

    /// The window `x(0), ..., x(n - 1)` (`n` at most the capacity) filtered forward and
    /// backward; a window under two samples as it is.
    pub(crate) fn filter(&mut self, n: usize, x: impl Fn(usize) -> T) -> &[T] {
        let edge = if n > self.padlen {
            self.padlen
        } else {
            n.max(1) - 1
        };
        let ext = &mut self.extended[..n + 2 * edge];
        // Odd extension: 2 x[0] - x[edge..0], x, 2 x[-1] - x[-2..-edge-2].
        let odd = |mut end: T, mut inner: T| {
            for (e, v) in end.values().iter_mut().zip(inner.values()) {
                *e = 2.0 * *e - *v;
            }
            end
        };
        if edge > 0 {
            let (first, last) = (x(0), x(n - 1));
            for i in 0..edge {
                ext[i] = odd(first, x(edge - i));
                ext[edge + n + i] = odd(last, x(n - 2 - i));
            }
        }
        for (i, e) in ext[edge..edge + n].iter_mut().enumerate() {
            *e = x(i);
        }
        if n >= 2 {
            self.filter.cascade(ext, false);
            // The backward pass runs over the same buffer from its end: no reversal copies.
            self.filter.cascade(ext, true);
        }
        &ext[edge..edge + n]
    }
}

/// Largest sample magnitude the filters take: the cascade's gains and the zero-phase filter's
/// odd extension amplify a sample by a small factor, and this leaves a factor of 1e8 before a
/// sample could overflow to infinity.
pub const MAX_SAMPLE: f64 = 1e300;

/// Refuses samples `name` with a NaN, infinite or overflowing value (beyond ±[`MAX_SAMPLE`]),
/// naming the first: the filters and the spline fit take the same data.
pub(crate) fn check_samples(name: &'static str, x: &[f64]) -> Result<()> {
    match x.iter().position(|v| !(v.abs() <= MAX_SAMPLE)) {
        Some(index) if x[index].is_finite() => Err(Error::InvalidArgument {
            name,
            expected: "samples within ±MAX_SAMPLE (1e300)",
            value: x[index],
        }),
        Some(index) => Err(Error::NonFinite { name, index }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn second_order_matches_the_bilinear_closed_form() {
        // Textbook biquad from the bilinear transform with pre-warping, K = tan(π fc / fs).
        let (fc, fs) = (5.0, 25.0);
        let k = (PI * fc / fs).tan();
        let norm = 1.0 / (1.0 + 2f64.sqrt() * k + k * k);
        let b0 = k * k * norm;
        let expected = [
            b0,
            2.0 * b0,
            b0,
            1.0,
            2.0 * (k * k - 1.0) * norm,
            (1.0 - 2f64.sqrt() * k + k * k) * norm,
        ];
        let f = design_lowpass(2, fc, fs).unwrap();
        assert_eq!(f.sections().len(), 1);
        for (a, b) in f.sections()[0].iter().zip(&expected) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
    }

    #[test]
    fn first_order_matches_the_bilinear_closed_form() {
        let (fc, fs) = (3.0, 30.0);
        let k = (PI * fc / fs).tan();
        let f = design_lowpass(1, fc, fs).unwrap();
        let s = f.sections()[0];
        assert!((s[0] - k / (1.0 + k)).abs() < 1e-14);
        assert!((s[1] - k / (1.0 + k)).abs() < 1e-14);
        assert!((s[4] - (k - 1.0) / (k + 1.0)).abs() < 1e-14);
        assert_eq!((s[2], s[5]), (0.0, 0.0));
    }

    #[test]
    fn unit_dc_gain_and_half_power_at_cutoff_for_every_order() {
        for order in 1..=MAX_ORDER {
            let (fc, fs) = (5.0, 25.0);
            let f = design_lowpass(order, fc, fs).unwrap();
            // |H(e^{jω})| from the sections.
            let gain_at = |hz: f64| -> f64 {
                let z = Complex::from_polar(1.0, 2.0 * PI * hz / fs);
                f.sections()
                    .iter()
                    .map(|s| {
                        let num = Complex::new(s[0], 0.0) + z.inv() * s[1] + z.inv().powi(2) * s[2];
                        let den = Complex::new(1.0, 0.0) + z.inv() * s[4] + z.inv().powi(2) * s[5];
                        (num / den).norm()
                    })
                    .product()
            };
            assert!((gain_at(0.0) - 1.0).abs() < 1e-12, "order {order}");
            assert!((gain_at(fc) - 0.5f64.sqrt()).abs() < 1e-12, "order {order}");
        }
    }

    #[test]
    fn steady_state_passes_a_constant_unchanged() {
        for order in 1..=MAX_ORDER {
            let f = design_lowpass(order, 2.0, 25.0).unwrap();
            let mut x = [3.25; 40];
            f.filter_from_steady_state(&mut x);
            assert!(x.iter().all(|v| (v - 3.25).abs() < 1e-12), "order {order}");
            let mut zp = ZeroPhase::new(f, 40);
            let mut out = [0.0; 40];
            zp.apply(&[3.25; 40], &mut out).unwrap();
            assert!(out.iter().all(|v| (v - 3.25).abs() < 1e-12));
        }
    }

    #[test]
    fn zero_phase_has_no_lag_on_a_ramp() {
        // A zero-phase filter with unit DC gain passes a ramp without delay. Only the start-up
        // transient of each pass remains (steady state is exact for a constant, not a ramp); it
        // decays with the pole radius (about 0.5 per sample at 5 Hz / 25 Hz), so the middle of
        // the window is the ramp to rounding and the ends are close.
        let f = design_lowpass(2, 5.0, 25.0).unwrap();
        let x: Vec<f64> = (0..80).map(|i| 0.1 * i as f64 - 2.0).collect();
        let mut out = vec![0.0; 80];
        ZeroPhase::new(f, 80).apply(&x, &mut out).unwrap();
        for (i, (a, b)) in x.iter().zip(&out).enumerate() {
            let tol = if (30..50).contains(&i) { 1e-12 } else { 1e-4 };
            assert!((a - b).abs() < tol, "{i}: {a} vs {b}");
        }
    }

    #[test]
    fn series_filtered_side_by_side_come_out_as_each_alone_to_the_bit() {
        let mut next = crate::testing::uniform(5);
        for order in [1, 2, 4] {
            let f = design_lowpass(order, 1.0, 25.0).unwrap();
            let padlen = f.default_padlen();
            let mut lanes = ForwardBackward::<[f64; 3]>::new(f.clone(), 60);
            let mut alone = ZeroPhase::new(f, 60);
            // Windows longer than the padding, as long as it and shorter, a sample, none.
            for n in [60, 37, padlen + 1, padlen, 3, 2, 1, 0] {
                let x: Vec<[f64; 3]> = (0..n)
                    .map(|_| [next() * 4.0 - 2.0, 1e3 * next(), -next()])
                    .collect();
                let together = lanes.filter(n, |i| x[i]).to_vec();
                for lane in 0..3 {
                    let series: Vec<f64> = x.iter().map(|v| v[lane]).collect();
                    let mut out = vec![0.0; n];
                    alone.apply(&series, &mut out).unwrap();
                    let side_by_side: Vec<f64> = together.iter().map(|v| v[lane]).collect();
                    assert_eq!(side_by_side, out, "order {order}, {n} samples, lane {lane}");
                }
            }
        }
    }

    #[test]
    fn rejects_bad_designs() {
        assert!(design_lowpass(0, 5.0, 25.0).is_err());
        assert!(design_lowpass(9, 5.0, 25.0).is_err());
        assert!(matches!(
            design_lowpass(2, 12.5, 25.0),
            Err(Error::InvalidArgument {
                name: "cutoff_hz",
                ..
            })
        ));
        assert!(matches!(
            design_lowpass(2, 5.0, f64::NAN),
            Err(Error::InvalidArgument {
                name: "rate_hz",
                ..
            })
        ));
    }
}
