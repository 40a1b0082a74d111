//! Latency of the per-frame work of torso_core: `cargo bench` (figures in benches/README.md).

use divan::{black_box, Bencher};
use torso_core::*;

fn main() {
    // Sub-microsecond calls need many iterations per sample, or the 20 ns timer precision and
    // the first-call outliers decide the median; command-line options still override these.
    divan::Divan::default()
        .sample_count(1000)
        .sample_size(100)
        .config_with_args()
        .main();
}

const KINDS: &[&str] = &[
    "const",
    "cvel_2s",
    "cvel_0.4s",
    "default_fast",
    "default_general",
    "causal_n1_fast",
    "zero_phase_n2",
    "zero_phase_n3",
    "zero_phase_n3_general",
];

fn config(kind: &str) -> ForecasterConfig {
    let spline = |filter, degree, fast_path| ForecasterConfig {
        method: Method::FilterSpline(FilterSplineConfig {
            filter,
            degree,
            lam: 1.0,
            ..FilterSplineConfig::default()
        }),
        fast_path,
        ..ForecasterConfig::default()
    };
    match kind {
        "const" => ForecasterConfig::constant(),
        "cvel_2s" => ForecasterConfig::constant_velocity(None),
        "cvel_0.4s" => ForecasterConfig::constant_velocity(Some(0.4)),
        "default_fast" => ForecasterConfig::default(),
        "default_general" => spline(FilterMode::ZeroPhase, 1, false),
        "causal_n1_fast" => spline(FilterMode::Causal, 1, true),
        "zero_phase_n2" => spline(FilterMode::ZeroPhase, 2, true),
        "zero_phase_n3" => spline(FilterMode::ZeroPhase, 3, true),
        "zero_phase_n3_general" => spline(FilterMode::ZeroPhase, 3, false),
        other => panic!("unknown kind {other}"),
    }
}

fn pose(k: usize) -> Pose {
    let t = k as f64 * 0.04;
    [
        0.9 * t,
        0.3 * t.sin(),
        1.1,
        2.6 + 1.2 * t + 0.15 * (11.3 * t).sin(),
        1.57,
    ]
}

fn full(kind: &str) -> Forecaster {
    let mut f = Forecaster::new(config(kind)).unwrap();
    for k in 0..50 {
        f.update(pose(k), k as f64 * 0.04, 1.0).unwrap();
    }
    f
}

/// One forecast of all five components at a horizon of STEPS grid steps (40 ms each), after the
/// update that makes the history new (a ring-buffer write): a forecaster keeps its fit until its
/// history changes, so a forecast alone on an unchanged history would time only the
/// continuation.
#[divan::bench(args = KINDS, consts = [10, 25, 50])]
fn forecast<const STEPS: usize>(bencher: Bencher, kind: &str) {
    let mut f = full(kind);
    let horizon = [STEPS as f64 * 0.04];
    let mut out = [[0.0; 5]];
    let mut k = 50;
    bencher.bench_local(|| {
        f.update(pose(k), k as f64 * 0.04, 1.0).unwrap();
        k += 1;
        f.forecast(black_box(&horizon), &mut out).unwrap();
    });
}

/// A frame's work for one track: add the new pose, forecast at 0.4, 1 and 2 s.
#[divan::bench(args = KINDS)]
fn update_and_forecast(bencher: Bencher, kind: &str) {
    let mut f = full(kind);
    let mut k = 50;
    let mut out = [[0.0; 5]; 3];
    bencher.bench_local(|| {
        f.update(pose(k), k as f64 * 0.04, 1.0).unwrap();
        k += 1;
        f.forecast(black_box(&[0.4, 1.0, 2.0]), &mut out).unwrap();
    });
}

/// A frame with 100 tracked people, default forecaster.
#[divan::bench]
fn hundred_tracks_per_frame(bencher: Bencher) {
    let mut tracks: Vec<Forecaster> = (0..100).map(|_| full("default_fast")).collect();
    let mut k = 50;
    let mut out = [[0.0; 5]; 2];
    bencher.bench_local(|| {
        for f in tracks.iter_mut() {
            f.update(pose(k), k as f64 * 0.04, 1.0).unwrap();
            f.forecast(black_box(&[0.4, 1.0]), &mut out).unwrap();
        }
        k += 1;
    });
}

fn torso_joints() -> ([[f64; 3]; 6], [Side; 6]) {
    (
        [
            [2.0, 0.18, 1.40],
            [2.01, -0.18, 1.41],
            [2.0, 0.12, 0.92],
            [2.02, -0.12, 0.91],
            [2.03, 0.0, 1.35],
            [2.01, 0.0, 1.10],
        ],
        [
            Side::Left,
            Side::Right,
            Side::Left,
            Side::Right,
            Side::Centre,
            Side::Centre,
        ],
    )
}

/// Least-squares torso plane through six joints (shoulders, hips, thorax, spine).
#[divan::bench]
fn plane_fit(bencher: Bencher) {
    let (joints, sides) = torso_joints();
    bencher.bench_local(|| fit_torso_plane(black_box(&joints), &sides, None).unwrap());
}

/// Gating the 17 COCO keypoints of one person.
#[divan::bench]
fn gating_17_joints(bencher: Bencher) {
    let mut gate = JointGate::new(17, GateConfig::default()).unwrap();
    let base: Vec<[f64; 3]> = (0..17)
        .map(|j| [2.0, 0.02 * j as f64, 0.1 * j as f64])
        .collect();
    let mut joints = base.clone();
    let mut status = [JointStatus::Lost; 17];
    let mut k = 0u32;
    bencher.bench_local(|| {
        joints.copy_from_slice(&base);
        joints[(k % 17) as usize][0] += 0.3; // one jumping joint per frame
        k += 1;
        gate.update(black_box(&mut joints), &mut status).unwrap();
    });
}

/// One sample through a 2nd-order Butterworth (one biquad).
#[divan::bench]
fn filter_step(bencher: Bencher) {
    let mut lp = LowPass::new(design_lowpass(2, 5.0, 25.0).unwrap());
    let mut x = 0.0;
    bencher.bench_local(|| {
        x += 0.01;
        lp.step(black_box(x)).unwrap()
    });
}

/// The 17 keypoints of a person at `x` m facing the camera, slowly turning, as a detector with
/// full confidence would give them.
fn coco_person(x: f64, y: f64, k: usize) -> (coco::Joints, [f64; coco::N_JOINTS]) {
    let yaw = std::f64::consts::PI + 0.3 * (0.02 * k as f64).sin();
    let (s, c) = yaw.sin_cos();
    let joints = std::array::from_fn(|j| {
        // COCO numbers left joints odd and right joints even; the nose is on the centre line.
        let side = match j {
            0 => 0.0,
            _ if j % 2 == 1 => 0.18,
            _ => -0.18,
        };
        [x - side * s, y + side * c, 1.7 - 0.1 * j as f64]
    });
    (joints, [0.9; coco::N_JOINTS])
}

/// Ten people's per-frame chain (swap test, relative gate, plane, forecaster update) and a
/// forecast at two horizons each: the tracking and forecasting of one frame outside Python.
#[divan::bench]
fn ten_people_per_frame(bencher: Bencher) {
    let mut people: Vec<Person> = (0..10)
        .map(|_| Person::new(PersonConfig::default()).unwrap())
        .collect();
    let mut k = 0;
    let mut out = [[0.0; 5]; 2];
    bencher.bench_local(|| {
        for (i, p) in people.iter_mut().enumerate() {
            let (joints, scores) = coco_person(2.0 + 0.01 * k as f64, i as f64 - 5.0, k);
            p.update(k as f64 * 0.04, &joints, &scores, [0.0; 3])
                .unwrap();
            p.forecast(black_box(&[0.4, 1.0]), &mut out).unwrap();
        }
        k += 1;
    });
}

/// A 640x480 depth image (a wall at 6 m) with ten people as 2 m-deep boxes at 2 to 4 m, their
/// keypoints' pixels, and the camera they were seen by.
fn crowd_frame(k: usize) -> Frame {
    let (w, h) = (640usize, 480usize);
    let intrinsics = camera::Intrinsics::new(525.0, 525.0, 320.0, 240.0, [0.0; 5]).unwrap();
    let cam = camera::Camera::new(intrinsics, camera::Camera::level(1.0, 0.0));
    let mut depth = vec![6.0f32; w * h];
    let mut keypoints = Vec::new();
    for i in 0..10 {
        let u0 = 20 + 60 * i + (k % 4);
        let z = 2.0 + 0.2 * i as f32;
        for v in 100..400 {
            for u in u0..u0 + 40 {
                depth[v * w + u] = z;
            }
        }
        keypoints.push(std::array::from_fn(|j| {
            let side = if j % 2 == 1 { 12.0 } else { 28.0 };
            [u0 as f64 + side, 110.0 + 16.0 * j as f64, 0.9]
        }));
    }
    (depth, keypoints, cam)
}

/// The depth lookup of one person's 17 keypoints (7x7 windows at body edges and inside).
#[divan::bench]
fn depth_lookup_17_keypoints(bencher: Bencher) {
    let (depth, keypoints, _) = crowd_frame(0);
    let image = depth::DepthImage::new(&depth, 640, 480).unwrap();
    let lookup = depth::DepthLookup::default();
    bencher.bench_local(|| {
        let mut sum = 0.0;
        for [u, v, _] in black_box(&keypoints[0]) {
            sum += lookup.depth_at(&image, [*u, *v]);
        }
        sum
    });
}

/// One frame of ten people through `Tracker::step` (depth lookup and deprojection of 170
/// keypoints, association, ten person chains) and a forecast with intervals at two horizons
/// for each confirmed track: everything outside the model in one frame, without Python.
#[divan::bench]
fn tracker_step_ten_people(bencher: Bencher) {
    bench_tracker_step(bencher, (0..4).map(crowd_frame).collect(), |_, _| false);
}

/// Depth images of `tracker_step_ten_people_cold`: more than the caches hold.
const COLD_FRAMES: usize = 64;

/// As `tracker_step_ten_people`, each frame with a depth image of its own (64 of them, 79 MB,
/// so that it is read from memory, as a frame fresh from a sensor is), the keypoints moved by a
/// pixel's noise and their scores by a few hundredths, so that the forecasters' weights differ
/// within their windows (their general path, as on a detector's output).
#[divan::bench]
fn tracker_step_ten_people_cold(bencher: Bencher) {
    let mut next = {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    };
    let frames = (0..COLD_FRAMES)
        .map(|k| {
            let (depth, mut keypoints, camera) = crowd_frame(k);
            for [u, v, score] in keypoints.iter_mut().flatten() {
                *u += next() - 0.5;
                *v += next() - 0.5;
                *score = 0.85 + 0.1 * next();
            }
            (depth, keypoints, camera)
        })
        .collect();
    bench_tracker_step(bencher, frames, |_, _| false);
}

/// As `tracker_step_ten_people`, with two of the ten people undetected in turn, each for
/// `HIDDEN_FRAMES` frames: the tracker keeps their tracks unmatched (under `max_missing`),
/// looks for them where their forecasts put them and takes them up again when seen.
#[divan::bench]
fn tracker_step_ten_people_two_unseen(bencher: Bencher) {
    bench_tracker_step(bencher, (0..4).map(crowd_frame).collect(), |person, k| {
        person % 5 == (k / HIDDEN_FRAMES) % 5
    });
}

/// Frames (at 25 Hz) for which a person of `tracker_step_ten_people_two_unseen` goes unseen:
/// 1.6 s, less than a track is kept unmatched by default.
const HIDDEN_FRAMES: usize = 40;

/// A depth image, the keypoints seen in it, and the camera that saw them.
type Frame = (Vec<f32>, Vec<tracker::Keypoints>, camera::Camera);

/// Frame `k` (of `frames`, in turn) of ten people through `Tracker::step` and a forecast with
/// intervals at two horizons for each confirmed track, without the detections of the people
/// `hidden(person, k)` names.
fn bench_tracker_step(bencher: Bencher, frames: Vec<Frame>, hidden: impl Fn(usize, usize) -> bool) {
    let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
    let mut out = [[0.0; 5]; 2];
    let mut seen = Vec::with_capacity(10);
    let mut k = 0;
    let mut step = |tracker: &mut Tracker, k: usize| {
        let (depth, keypoints, cam) = &frames[k % frames.len()];
        let image = depth::DepthImage::new(depth, 640, 480).unwrap();
        seen.clear();
        seen.extend(
            (0..keypoints.len())
                .filter(|&i| !hidden(i, k))
                .map(|i| keypoints[i]),
        );
        let slots: [Option<usize>; 10] = {
            let outcomes = tracker.step(k as f64 * 0.04, &seen, &image, cam).unwrap();
            std::array::from_fn(|d| outcomes.get(d).and_then(|o| o.track).map(|t| t.slot))
        };
        for slot in slots.into_iter().flatten() {
            if tracker.forecast(slot, &[0.4, 1.0], &mut out).unwrap() {
                tracker.intervals(slot, &[0.4, 1.0], &mut out).unwrap();
            }
        }
    };
    // Long enough for every person to have been unseen once and taken up again.
    for _ in 0..5 * HIDDEN_FRAMES + 100 {
        step(&mut tracker, k);
        k += 1;
    }
    bencher.bench_local(|| {
        step(&mut tracker, k);
        k += 1;
    });
}
