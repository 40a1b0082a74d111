//! Proves the "no heap allocation per frame" guarantee: a counting global allocator around
//! `update` + `forecast` of every forecaster kind, and around the other per-frame objects.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use torso_core::*;

struct Counting;

thread_local! {
    // Per thread, so the test harness's own threads do not count. `const` init: no lazy
    // allocation inside the allocator.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

fn every_forecaster_kind() -> Vec<(String, ForecasterConfig)> {
    let mut kinds = vec![
        ("const".to_string(), ForecasterConfig::constant()),
        (
            "cvel 2 s".to_string(),
            ForecasterConfig::constant_velocity(None),
        ),
        (
            "cvel 0.4 s".to_string(),
            ForecasterConfig::constant_velocity(Some(0.4)),
        ),
    ];
    for filter in [FilterMode::Off, FilterMode::Causal, FilterMode::ZeroPhase] {
        for degree in 0..=bspline::MAX_DEGREE {
            for fast_path in [true, false] {
                for extrapolation in [
                    Extrapolation::Polynomial,
                    Extrapolation::Linear,
                    Extrapolation::DAMPED_H36M_S1,
                ] {
                    let spline = FilterSplineConfig {
                        filter,
                        degree,
                        extrapolation,
                        lambda_unit: if degree % 2 == 0 {
                            LambdaUnit::Seconds
                        } else {
                            LambdaUnit::Samples
                        },
                        ..FilterSplineConfig::default()
                    };
                    kinds.push((
                        format!("{filter:?} N={degree} fast={fast_path} {extrapolation:?}"),
                        ForecasterConfig {
                            method: Method::FilterSpline(spline),
                            fast_path,
                            ..ForecasterConfig::default()
                        },
                    ));
                }
            }
        }
    }
    kinds
}

#[test]
fn update_and_forecast_never_allocate() {
    let horizons = [0.04, 0.4, 1.0, 2.0];
    let mut out = [[0.0; 5]; 4];
    for (name, config) in every_forecaster_kind() {
        let mut f = Forecaster::new(config).unwrap();
        let count = allocations_during(|| {
            // Warm-up (growing history), a full history with uniform weights (fast path), varying
            // weights (general path), a filled gap, a restart, rejected input and a reset.
            for k in 0..140 {
                let t = k as f64 * 0.04
                    + if k > 90 { 0.08 } else { 0.0 }
                    + if k > 120 { 1.0 } else { 0.0 };
                let weight = if (60..80).contains(&k) {
                    0.5 + 0.01 * k as f64
                } else {
                    1.0
                };
                let pose = [
                    0.01 * k as f64,
                    0.2,
                    1.0,
                    (0.05 * k as f64).sin() * 3.5,
                    1.5,
                ];
                f.update(pose, t, weight).unwrap();
                if f.len() >= f.min_samples() {
                    f.forecast(&horizons, &mut out).unwrap();
                    assert!(out.iter().flatten().all(|v| v.is_finite()));
                } else {
                    assert!(matches!(
                        f.forecast(&horizons, &mut out),
                        Err(Error::NotEnoughHistory { .. })
                    ));
                }
            }
            assert!(f.update([f64::NAN; 5], 100.0, 1.0).is_err());
            assert!(f.forecast(&[-1.0], &mut out[..1]).is_err());
            f.reset();
            assert!(f.forecast(&horizons, &mut out).is_err());
        });
        assert_eq!(count, 0, "{name}: {count} allocations per run");
    }
}

#[test]
fn per_frame_helpers_never_allocate() {
    let mut gate = JointGate::new(6, GateConfig::default()).unwrap();
    let mut status = [JointStatus::Lost; 6];
    let mut low_pass = LowPass::new(design_lowpass(4, 5.0, 25.0).unwrap());
    let mut zero_phase = ZeroPhase::new(design_lowpass(2, 5.0, 25.0).unwrap(), 50);
    let mut spline = SmoothingSpline::new(3, 50).unwrap();
    let x: Vec<f64> = (0..50).map(|i| i as f64 * 0.04).collect();
    let y: Vec<f64> = x.iter().map(|t| t.sin()).collect();
    let w = vec![1.0; 50];
    let mut filtered = vec![0.0; 50];
    let mut coeffs = vec![0.0; 52];
    let sides = [
        Side::Left,
        Side::Right,
        Side::Left,
        Side::Right,
        Side::Centre,
        Side::Centre,
    ];
    let count = allocations_during(|| {
        for k in 0..50 {
            let s = k as f64 * 0.01;
            let mut joints = [
                [s, 0.18, 1.4],
                [s, -0.18, 1.4],
                [s, 0.12, 0.9],
                [s, -0.12, 0.9],
                [s + 0.02, 0.0, 1.35],
                if k % 7 == 0 {
                    [f64::NAN; 3]
                } else {
                    [s, 0.0, 1.0]
                },
            ];
            gate.update(&mut joints, &mut status).unwrap();
            let plane = fit_torso_plane(&joints, &sides, None).unwrap();
            shoulder_heading(joints[0], joints[1]).unwrap();
            low_pass.step(plane.azimuth).unwrap();
        }
        zero_phase.apply(&y, &mut filtered).unwrap();
        spline.set_abscissae(&x).unwrap();
        spline.fit(&w, 0.1, &filtered, &mut coeffs).unwrap();
    });
    assert_eq!(count, 0);
}

#[test]
fn a_tracked_person_never_allocates_per_frame() {
    use torso_core::coco::{Joints, N_JOINTS};
    let mut person = Person::new(PersonConfig::default()).unwrap();
    let mut out = [[0.0; 5]; 2];
    // Build the first frames outside the count: the forecaster's history fills up, then every
    // branch (plane, shoulders only, a swapped frame, a jumping joint, bent knees, a gap) runs
    // counted.
    let frame = |k: usize| -> (Joints, [f64; N_JOINTS]) {
        let x = 2.0 + 0.02 * k as f64;
        let joints = std::array::from_fn(|j| {
            let side = match j {
                0 => 0.0,
                _ if j % 2 == 1 => 0.18,
                _ => -0.18,
            };
            [x, side, 1.7 - 0.1 * j as f64]
        });
        (joints, [0.9; N_JOINTS])
    };
    for k in 0..60 {
        let (joints, scores) = frame(k);
        person
            .update(k as f64 * 0.04, &joints, &scores, [0.0; 3])
            .unwrap();
    }
    let count = allocations_during(|| {
        for k in 60..120 {
            let (mut joints, mut scores) = frame(k);
            match k % 4 {
                0 => scores[11..13].fill(0.0), // no hips: shoulders only
                1 => joints[11][0] += 0.5,     // a jumping joint
                2 => coco::swap_sides(&mut joints),
                _ => {
                    // Bent knees: the heading's knee cue votes.
                    joints[13][0] -= 0.1;
                    joints[14][0] -= 0.1;
                }
            }
            let t = k as f64 * 0.04 + if k >= 100 { 0.2 } else { 0.0 };
            person.update(t, &joints, &scores, [0.0; 3]).unwrap();
            person.forecast(&[0.4, 1.0], &mut out).unwrap();
        }
    });
    assert_eq!(count, 0);
}

#[test]
fn a_tracker_step_never_allocates_once_it_has_seen_its_busiest_frame() {
    use torso_core::camera::{Camera, Intrinsics};
    use torso_core::coco::N_JOINTS;
    use torso_core::depth::DepthImage;
    use torso_core::tracker::Keypoints;
    let (w, h) = (320usize, 240usize);
    // Ten people in a row, each a vertical strip of pixels at their own depth, far enough apart
    // to be ten bodies (`MIN_SEPARATION`); the wall behind.
    let people = 10;
    let mut data = vec![6.0f32; w * h];
    for (i, px) in data.iter_mut().enumerate() {
        let person = (i % w) / (w / people);
        if (i % w) % (w / people) < 20 {
            *px = 1.5 + 0.3 * person as f32;
        }
    }
    let image = DepthImage::new(&data, w, h).unwrap();
    let camera = Camera::new(
        Intrinsics::new(300.0, 300.0, 160.0, 120.0, [0.05, -0.01, 0.0, 0.0, 0.0]).unwrap(),
        Camera::level(1.0, 0.1),
    );
    let frame = |k: usize, n: usize| -> Vec<Keypoints> {
        (0..n)
            .map(|p| {
                let u = (p * (w / people) + 10) as f64 + 0.02 * k as f64;
                std::array::from_fn(|j| {
                    let side = if j % 2 == 1 { -4.0 } else { 4.0 };
                    [
                        u + side,
                        40.0 + 9.0 * j as f64,
                        if j == 3 { 0.1 } else { 0.9 },
                    ]
                })
            })
            .collect()
    };
    let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
    // Some people missed for a frame; the last one gone for longer than `max_missing` (its track
    // dropped) and back as a new track, born in the dropped one's reused slot.
    let present = |k: usize| match k {
        _ if k % 9 == 0 => 6,
        90..160 => people - 1,
        _ => people,
    };
    let frames: Vec<Vec<Keypoints>> = (0..200).map(|k| frame(k, present(k))).collect();
    let mut out = [[0.0; 5]; 3];
    let mut run = |tracker: &mut Tracker, range: std::ops::Range<usize>| {
        for k in range {
            let outcomes = tracker
                .step(k as f64 / 30.0, &frames[k], &image, &camera)
                .unwrap();
            assert_eq!(outcomes.len(), frames[k].len());
            let tracked: [Option<usize>; 16] =
                std::array::from_fn(|d| outcomes.get(d).and_then(|o| o.track).map(|t| t.slot));
            for slot in tracked.into_iter().flatten() {
                tracker.forecast(slot, &[0.4, 1.0, 2.0], &mut out).unwrap();
                tracker.intervals(slot, &[0.4, 1.0, 2.0], &mut out).unwrap();
            }
        }
        assert!(tracker.joints().iter().all(|j| j.len() == N_JOINTS));
    };
    // Warm-up: the busiest frame, every track born.
    run(&mut tracker, 0..80);
    assert_eq!(tracker.tracks().count(), people);
    let count = allocations_during(|| run(&mut tracker, 80..200));
    assert_eq!(count, 0);
    let ids: Vec<u64> = tracker.tracks().filter_map(|(t, _)| t.id).collect();
    assert_eq!(ids.len(), people);
    assert_eq!(ids.iter().max(), Some(&(people as u64 + 1)));
}
