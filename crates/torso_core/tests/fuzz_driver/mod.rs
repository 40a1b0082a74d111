//! The fuzz driver shared by `tests/fuzz.rs` (seeded byte strings, stable Rust) and the
//! cargo-fuzz target `fuzz/fuzz_targets/engine.rs` (coverage-guided, nightly): a byte string
//! drives a sequence of calls on the public entry points, asserting that every call returns, a
//! refused one changes nothing and an accepted one gives finite numbers.

use torso_core::camera::{Camera, Intrinsics, Rigid};
use torso_core::coco::{Joints, N_JOINTS};
use torso_core::depth::DepthImage;
use torso_core::tracker::Keypoints;
use torso_core::*;

struct Input<'a> {
    data: &'a [u8],
    at: usize,
}

impl Input<'_> {
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }

    fn done(&self) -> bool {
        self.at >= self.data.len()
    }

    /// A number as a hostile caller sends them: specials, extremes, raw bit patterns, or a
    /// plausible value in -10..10.
    fn number(&mut self) -> f64 {
        match self.byte() % 10 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 0.0,
            4 => 1e308,
            5 => -1e-300,
            6 => f64::from_bits(u64::from_le_bytes(std::array::from_fn(|_| self.byte()))),
            _ => (f64::from(u16::from_le_bytes([self.byte(), self.byte()])) / 65535.0 - 0.5) * 20.0,
        }
    }

    /// Mostly plausible numbers, sometimes hostile ones: enough plausible frames for tracks to
    /// form, so that their later refusals are tested against real state.
    fn mostly(&mut self, plausible: f64) -> f64 {
        if self.byte() < 230 {
            plausible + (f64::from(self.byte()) / 255.0 - 0.5) * 0.1
        } else {
            self.number()
        }
    }

    fn size(&mut self, max: usize) -> usize {
        usize::from(self.byte()) % (max + 1)
    }
}

/// What a refused call must not change: the tracker's time, its tracks and their histories.
fn fingerprint(tracker: &Tracker) -> String {
    let tracks: Vec<String> = tracker
        .tracks()
        .map(|(t, p)| {
            let f = p.forecaster();
            format!("{t:?} {} {:?}", f.len(), f.last_time())
        })
        .collect();
    format!("{:?} {} {tracks:?}", tracker.last_time(), tracker.live())
}

fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

pub fn run(data: &[u8]) {
    let mut input = Input { data, at: 0 };
    let mut tracker = Tracker::new(TrackerConfig {
        min_hits: 1,
        capacity: 4,
        max_detections: 6,
        ..TrackerConfig::default()
    })
    .unwrap();
    let mut forecaster = Forecaster::new(ForecasterConfig::live()).unwrap();
    let mut low_pass = LowPass::new(design_lowpass(2, 2.0, 25.0).unwrap());
    let mut solver = Assignment::default();
    let mut clock = 0.0;
    let mut out = [[0.0; 5]; 3];
    while !input.done() {
        clock += 0.04;
        match input.byte() % 7 {
            0 => {
                // World joints of up to 7 people (one more than max_detections).
                let people = input.size(7);
                let joints: Vec<Joints> = (0..people)
                    .map(|p| {
                        std::array::from_fn(|j| {
                            let side = if j % 2 == 1 { 0.18 } else { -0.18 };
                            [
                                input.mostly(2.0 + p as f64),
                                input.mostly(side),
                                input.mostly(1.7 - 0.08 * j as f64),
                            ]
                        })
                    })
                    .collect();
                let scores: Vec<[f64; N_JOINTS]> = (0..people)
                    .map(|_| std::array::from_fn(|_| input.mostly(0.9)))
                    .collect();
                let t = input.mostly(clock);
                let camera = [input.mostly(0.0), input.mostly(0.0), input.mostly(1.0)];
                let before = fingerprint(&tracker);
                match tracker.update(t, &joints, &scores, camera) {
                    Err(_) => assert_eq!(fingerprint(&tracker), before),
                    Ok(outcomes) => {
                        assert_eq!(outcomes.len(), people);
                        for o in outcomes {
                            if let Some(pose) = o.observation.and_then(|obs| obs.pose) {
                                assert!(finite(&pose), "{pose:?}");
                            }
                        }
                    }
                }
            }
            1 => {
                // Keypoints on a small depth image through an arbitrary camera.
                let (w, h) = (1 + input.size(15), 1 + input.size(11));
                let depth: Vec<f32> = (0..w * h).map(|_| input.mostly(2.5) as f32).collect();
                let image = DepthImage::new(&depth, w, h).unwrap();
                let people = input.size(3);
                let keypoints: Vec<Keypoints> = (0..people)
                    .map(|_| {
                        std::array::from_fn(|_| {
                            [
                                input.mostly(w as f64 / 2.0),
                                input.mostly(h as f64 / 2.0),
                                input.mostly(0.9),
                            ]
                        })
                    })
                    .collect();
                let k = [
                    input.mostly(20.0),
                    input.mostly(20.0),
                    input.number(),
                    input.number(),
                ];
                let distortion = std::array::from_fn(|_| input.mostly(0.0) * 0.1);
                let Ok(intrinsics) = Intrinsics::new(k[0], k[1], k[2], k[3], distortion) else {
                    continue;
                };
                let rows = std::array::from_fn(|i| {
                    std::array::from_fn(|j| input.mostly(if i == j { 1.0 } else { 0.0 }))
                });
                let to_world = Rigid::from_rows(rows).unwrap_or(Camera::level(1.0, 0.0));
                let camera = Camera::new(intrinsics, to_world);
                let t = input.mostly(clock);
                let before = fingerprint(&tracker);
                match tracker.step(t, &keypoints, &image, &camera) {
                    Err(_) => assert_eq!(fingerprint(&tracker), before),
                    Ok(_) => {
                        for joint in tracker.joints().iter().flatten() {
                            // Lifted or missing, never half-finite.
                            assert!(
                                finite(joint) || joint.iter().all(|v| v.is_nan()),
                                "{joint:?}"
                            );
                        }
                    }
                }
            }
            2 => {
                let slot = input.size(5);
                let horizons = [input.mostly(0.4), input.mostly(1.0), input.mostly(2.0)];
                let before = fingerprint(&tracker);
                match tracker.forecast(slot, &horizons, &mut out) {
                    Ok(true) => assert!(finite(out.as_flattened()), "{out:?}"),
                    Ok(false) | Err(_) => assert_eq!(fingerprint(&tracker), before),
                }
                let _ = tracker.intervals(slot, &horizons, &mut out);
            }
            3 => {
                let pose = std::array::from_fn(|_| input.mostly(1.0));
                let (t, weight) = (input.mostly(clock), input.mostly(1.0));
                let before = (forecaster.len(), forecaster.last_time());
                if forecaster.update(pose, t, weight).is_err() {
                    assert_eq!((forecaster.len(), forecaster.last_time()), before);
                } else if forecaster.len() >= forecaster.min_samples() {
                    forecaster.forecast(&[0.4, 1.0, 2.0], &mut out).unwrap();
                    assert!(finite(out.as_flattened()), "{out:?}");
                }
            }
            4 => {
                let n = input.size(6);
                let mut window: Vec<f64> = (0..n).map(|_| input.mostly(1.0)).collect();
                let copy = window.clone();
                let mut twin = low_pass.clone();
                match low_pass.filter_window(&mut window) {
                    Err(_) => {
                        // Unchanged state: the next sample comes out as from an untouched twin.
                        let bits = |w: &[f64]| w.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(&window), bits(&copy));
                        assert_eq!(low_pass.step(1.0).ok(), twin.step(1.0).ok());
                    }
                    Ok(()) => assert!(finite(&window)),
                }
            }
            5 => {
                let n = input.size(6);
                let joints: Vec<[f64; 3]> = (0..n)
                    .map(|_| [input.mostly(2.0), input.mostly(0.0), input.mostly(1.2)])
                    .collect();
                let sides: Vec<Side> = (0..n)
                    .map(|i| [Side::Left, Side::Right, Side::Centre][(i + input.size(2)) % 3])
                    .collect();
                if let Ok(plane) = fit_torso_plane(&joints, &sides, None) {
                    assert!(finite(&[
                        plane.azimuth,
                        plane.elevation,
                        plane.rms_residual
                    ]));
                }
            }
            _ => {
                let (rows, cols) = (input.size(5), input.size(5));
                let cost: Vec<f64> = (0..rows * cols).map(|_| input.mostly(1.0)).collect();
                if let Ok(pairs) = solver.solve(&cost, rows, cols) {
                    assert_eq!(pairs.len(), rows.min(cols));
                }
            }
        }
    }
}
