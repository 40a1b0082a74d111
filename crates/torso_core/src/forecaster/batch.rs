//! Many history windows forecast in one call, for evaluations.

use super::{Forecaster, ForecasterConfig};
use crate::error::{check_len, check_positive, Error, Result};

/// Forecasts many history windows in one call, for evaluations. `histories` is a flat,
/// C-ordered `(n, window_len, 5)` array of poses on the config's grid (azimuth may be wrapped: it
/// is unwrapped per window); `out` receives the flat `(n, horizons.len(), 5)` forecasts. The
/// config's `history` is replaced by the window length. One forecaster serves every window.
pub fn forecast_batch(
    config: &ForecasterConfig,
    histories: &[f64],
    window_len: usize,
    horizons: &[f64],
    out: &mut [f64],
) -> Result<()> {
    let stride = window_len * 5;
    if window_len == 0 || histories.len() % stride != 0 {
        return Err(Error::LengthMismatch {
            name: "histories",
            expected: stride.max(5) * (histories.len() / stride.max(5)).max(1),
            got: histories.len(),
        });
    }
    let count = histories.len() / stride;
    check_len("out", out.len(), count * horizons.len() * 5)?;
    check_positive(
        "rate_hz",
        config.rate_hz,
        "a positive, finite grid rate in Hz",
    )?;
    let cfg = ForecasterConfig {
        history: window_len as f64 / config.rate_hz,
        ..*config
    };
    let mut f = Forecaster::new(cfg)?;
    let mut poses = [[0.0; 5]; 16];
    for (w, window) in histories.chunks_exact(stride).enumerate() {
        f.reset();
        for (i, p) in window.chunks_exact(5).enumerate() {
            let pose = [p[0], p[1], p[2], p[3], p[4]];
            f.update(pose, i as f64 / cfg.rate_hz, 1.0)
                .map_err(|e| match e {
                    Error::NonFinite { name: "pose", .. } => Error::NonFinite {
                        name: "histories",
                        index: w,
                    },
                    other => other,
                })?;
        }
        let dest = &mut out[w * horizons.len() * 5..(w + 1) * horizons.len() * 5];
        // Horizons in chunks of 16 so the forecast buffer stays on the stack.
        for (hs, d) in horizons.chunks(16).zip(dest.chunks_mut(16 * 5)) {
            f.forecast(hs, &mut poses[..hs.len()])?;
            for (o, p) in d.chunks_exact_mut(5).zip(&poses) {
                o.copy_from_slice(p);
            }
        }
    }
    Ok(())
}
