//! Torso joints whose depth came off something else.
//!
//! A keypoint is right in the image, but its depth is read at one pixel: where another person
//! stands in front of a joint, or the keypoint lands just off the body onto the background, the
//! joint lifts to the wrong place, often metres off. Such a joint turns the torso plane by tens
//! of degrees and, in the mean a track is associated by, moves the person further than the
//! association gate. Both the track ([`crate::Person`]) and the association
//! ([`crate::tracker::detection_centre`]) take the torso joints through [`drop_stray`] first;
//! to the track, a dropped joint is one not seen, whose last position the gate carries along
//! with the body. Before that, the tracker drops the joints a detection shows on the torso of
//! someone nearer the camera ([`drop_read_off_nearer`]), which no rule within one torso can
//! tell: every torso joint of a person hidden behind others can lift onto them.

use crate::coco::{Joints, TORSO};
use crate::tracker::MIN_SEPARATION;
use crate::vec3::{distance, finite, horizontal_distance, horizontally_within};

/// The farthest (m) a torso joint may lie, horizontally, from the median of the other three: a
/// frontal torso with broad shoulders (0.5 m) and hips (0.35 m) puts a shoulder about 0.43 m
/// from it. Chosen on the scenes benchmark's development split (flips level from 0.4 to
/// 0.6 m; docs/benchmark_log.md).
pub const MAX_TORSO_SPREAD: f64 = 0.5;

/// No two joints of one torso lie further apart than this (m), horizontally: a torso bent flat
/// puts a shoulder about 0.65 m from the opposite hip. Joints further apart belong to different
/// surfaces, and the torso splits into groups (two people one behind the other, each holding
/// two of the keypoints' depths).
pub const MAX_TORSO_SPAN: f64 = 2.0 * MAX_TORSO_SPREAD;

/// Drops (NaN) the seen torso joints whose depth came off something else, and says which.
///
/// First, where the seen torso joints fall into groups more than [`MAX_TORSO_SPAN`] apart
/// (linked joint to joint), only the largest group is kept, and of groups as large the one
/// farthest from `camera`: something that hides a joint stands in front of it, so its depth
/// pulls the joint towards the camera. Then, where all four are left, the one lying farthest,
/// horizontally, from the median of the other three is dropped when that is more than
/// [`MAX_TORSO_SPREAD`].
///
/// ```
/// use torso_core::stray::drop_stray;
/// use torso_core::coco::{N_JOINTS, LEFT_SHOULDER, RIGHT_SHOULDER, LEFT_HIP, RIGHT_HIP};
/// // A torso 4 m ahead whose shoulders read the depth of someone 3 m nearer the camera.
/// let mut joints = [[f64::NAN; 3]; N_JOINTS];
/// joints[LEFT_SHOULDER] = [1.0, -0.2, 1.4];
/// joints[RIGHT_SHOULDER] = [1.0, 0.2, 1.4];
/// joints[LEFT_HIP] = [4.0, -0.12, 0.9];
/// joints[RIGHT_HIP] = [4.0, 0.12, 0.9];
/// let dropped = drop_stray(&mut joints, [0.0, 0.0, 1.0]);
/// assert_eq!(dropped, [true, true, false, false]);
/// assert!(joints[LEFT_SHOULDER][0].is_nan() && joints[LEFT_HIP][0] == 4.0);
/// ```
pub fn drop_stray(joints: &mut Joints, camera: [f64; 3]) -> [bool; 4] {
    let mut dropped = [false; 4];
    let seen = TORSO.map(|i| finite(&joints[i]));
    let horizontal = |a: usize, b: usize| horizontal_distance(joints[TORSO[a]], joints[TORSO[b]]);
    // Single linkage over at most four joints: a group is named by its smallest member.
    let mut group = [0, 1, 2, 3];
    for a in 0..4 {
        for b in a + 1..4 {
            if seen[a] && seen[b] && horizontal(a, b) <= MAX_TORSO_SPAN {
                let (from, to) = (group[a].max(group[b]), group[a].min(group[b]));
                group
                    .iter_mut()
                    .filter(|g| **g == from)
                    .for_each(|g| *g = to);
            }
        }
    }
    let size = |g: usize| (0..4).filter(|&k| seen[k] && group[k] == g).count();
    let depth = |g: usize| {
        let members = (0..4).filter(|&k| seen[k] && group[k] == g);
        members
            .map(|k| distance(joints[TORSO[k]], camera))
            .sum::<f64>()
            / size(g) as f64
    };
    let kept = (0..4)
        .filter(|&k| seen[k])
        .map(|k| group[k])
        .max_by(|&a, &b| {
            size(a)
                .cmp(&size(b))
                .then_with(|| depth(a).total_cmp(&depth(b)))
        });
    for k in 0..4 {
        if seen[k] && Some(group[k]) != kept {
            dropped[k] = true;
        }
    }
    if !dropped.iter().any(|&d| d) && seen.iter().all(|&s| s) {
        if let Some(k) = farthest_from_the_others(joints) {
            dropped[k] = true;
        }
    }
    for k in 0..4 {
        if dropped[k] {
            joints[TORSO[k]] = [f64::NAN; 3];
        }
    }
    dropped
}

/// Drops (NaN) the joints of one detection, whose torso centre is `centre`, that lie,
/// horizontally, within [`MIN_SEPARATION`] of the torso centre of a person nearer the camera
/// (`nearer`: their centres); returns how many were dropped. A person partly hidden by someone
/// in front has keypoints on the front person's body in the image, and their depth lifts them
/// onto it, where no joint of another body lies (two people shoulder to shoulder have their
/// torso centres a shoulder width apart, each shoulder joint half of one from its own). Where
/// every torso joint lifts onto people in front, [`drop_stray`] keeps them all, and the
/// detection's centre lands among those people, a metre or more from the person's own. A
/// centre within [`MIN_SEPARATION`] of `centre` is passed over: that is one body seen twice,
/// which the tracker gives no second track.
///
/// ```
/// use torso_core::stray::drop_read_off_nearer;
/// use torso_core::coco::{N_JOINTS, LEFT_SHOULDER, RIGHT_SHOULDER};
/// // Seen 2.6 m ahead, its left shoulder on the torso of a person 2 m ahead.
/// let mut joints = [[f64::NAN; 3]; N_JOINTS];
/// joints[LEFT_SHOULDER] = [2.0, 0.1, 1.4];
/// joints[RIGHT_SHOULDER] = [2.6, 0.6, 1.4];
/// let front = [2.05, 0.0, 1.1];
/// assert_eq!(drop_read_off_nearer(&mut joints, [2.6, 0.4, 1.1], [front]), 1);
/// assert!(joints[LEFT_SHOULDER][0].is_nan() && joints[RIGHT_SHOULDER][0] == 2.6);
/// ```
pub fn drop_read_off_nearer(
    joints: &mut Joints,
    centre: [f64; 3],
    nearer: impl IntoIterator<Item = [f64; 3]>,
) -> usize {
    // The joints' extent over the ground, so that the people in front far from all of them
    // (most of a crowd) are passed over with four comparisons. Twice the separation keeps
    // rounding from passing over anyone a joint is within it of.
    let reach = 2.0 * MIN_SEPARATION;
    let (mut low, mut high) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in joints.iter().filter(|x| finite(x)) {
        for axis in 0..2 {
            low[axis] = low[axis].min(x[axis] - reach);
            high[axis] = high[axis].max(x[axis] + reach);
        }
    }
    let mut dropped = 0;
    for front in nearer {
        let apart = (0..2).any(|axis| !(front[axis] >= low[axis] && front[axis] <= high[axis]));
        if apart || !(distance(front, centre) >= MIN_SEPARATION) {
            continue;
        }
        for x in joints.iter_mut().filter(|x| finite(x)) {
            if horizontally_within(*x, front, MIN_SEPARATION) {
                *x = [f64::NAN; 3];
                dropped += 1;
            }
        }
    }
    dropped
}

/// Of four seen torso joints, the one lying farthest, horizontally, from the median of the other
/// three, where that is more than [`MAX_TORSO_SPREAD`].
fn farthest_from_the_others(joints: &Joints) -> Option<usize> {
    let torso = TORSO.map(|i| joints[i]);
    let spread = |i: usize| {
        let others: [[f64; 3]; 3] = std::array::from_fn(|k| torso[if k < i { k } else { k + 1 }]);
        let centre = [0, 1].map(|axis| median3(others.map(|p| p[axis])));
        horizontal_distance(torso[i], [centre[0], centre[1], 0.0])
    };
    let (worst, far) = (0..4)
        .map(|i| (i, spread(i)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("four torso joints");
    (far > MAX_TORSO_SPREAD).then_some(worst)
}

fn median3([a, b, c]: [f64; 3]) -> f64 {
    a.min(b).max(a.max(b).min(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coco::{LEFT_HIP, LEFT_SHOULDER, N_JOINTS, RIGHT_HIP, RIGHT_SHOULDER};

    const CAMERA: [f64; 3] = [0.0, 0.0, 1.0];

    /// A torso facing the camera, `x` metres ahead, its shoulders `lean` metres ahead of its hips.
    fn torso(x: f64, lean: f64) -> Joints {
        let mut j = [[f64::NAN; 3]; N_JOINTS];
        j[LEFT_SHOULDER] = [x - lean, -0.25, 1.4];
        j[RIGHT_SHOULDER] = [x - lean, 0.25, 1.4];
        j[LEFT_HIP] = [x, -0.175, 0.9];
        j[RIGHT_HIP] = [x, 0.175, 0.9];
        j
    }

    /// [`torso`] moved `y` metres to the side.
    fn beside(x: f64, y: f64) -> Joints {
        let mut j = torso(x, 0.0);
        for i in TORSO {
            j[i][1] += y;
        }
        j
    }

    /// The mean of the seen torso joints.
    fn centre(j: &Joints) -> [f64; 3] {
        let seen: Vec<[f64; 3]> = TORSO.map(|i| j[i]).into_iter().filter(finite).collect();
        std::array::from_fn(|k| seen.iter().map(|p| p[k]).sum::<f64>() / seen.len() as f64)
    }

    #[test]
    fn joints_lifted_onto_someone_in_front_are_dropped_and_a_neighbours_are_kept() {
        // Behind a person 2.85 m from the camera, a person 4.4 m away shows a shoulder and a hip
        // on the front one's torso, read at its depth.
        let front = beside(2.85, -0.2);
        let mut joints = beside(4.4, -0.55);
        joints[LEFT_SHOULDER] = [2.85, -0.3, 1.4];
        joints[LEFT_HIP] = [2.85, -0.25, 0.9];
        let seen = centre(&joints);
        assert_eq!(drop_read_off_nearer(&mut joints, seen, [centre(&front)]), 2);
        assert_eq!(
            TORSO.map(|i| finite(&joints[i])),
            [false, true, false, true]
        );
        // A detection with no centre, or a front person without one, takes or loses nothing.
        let mut unplaced = beside(4.4, -0.55);
        let nan = [f64::NAN; 3];
        assert_eq!(
            drop_read_off_nearer(&mut unplaced, nan, [centre(&front)]),
            0
        );
        assert_eq!(
            drop_read_off_nearer(&mut unplaced, centre(&front), [nan]),
            0
        );
        // Side by side, broad shoulders 5 cm apart, and a body seen twice 5 cm off: nothing.
        for other in [beside(2.85, 0.35), beside(2.9, -0.2)] {
            let mut joints = other;
            assert_eq!(
                drop_read_off_nearer(&mut joints, centre(&other), [centre(&front)]),
                0
            );
        }
    }

    #[test]
    fn the_people_in_front_passed_over_are_those_no_joint_is_within_reach_of() {
        // The rule written out plainly: every joint against every person in front.
        let plain = |joints: &mut Joints, centre: [f64; 3], nearer: &[[f64; 3]]| {
            let mut dropped = 0;
            for &front in nearer {
                if distance(front, centre) >= MIN_SEPARATION {
                    for x in joints.iter_mut().filter(|x| finite(x)) {
                        if horizontally_within(*x, front, MIN_SEPARATION) {
                            *x = [f64::NAN; 3];
                            dropped += 1;
                        }
                    }
                }
            }
            dropped
        };
        let mut next = crate::testing::uniform(11);
        for _ in 0..2000 {
            let mut joints = [[f64::NAN; 3]; N_JOINTS];
            for x in joints.iter_mut() {
                if next() < 0.8 {
                    *x = [2.0 + 3.0 * next(), 2.0 * next() - 1.0, 2.0 * next()];
                }
            }
            let centre = joints[(next() * N_JOINTS as f64) as usize];
            // People in front anywhere, and on the edge of a joint's reach.
            let nearer: Vec<[f64; 3]> = (0..8)
                .map(|_| {
                    let x = joints[(next() * N_JOINTS as f64) as usize];
                    let angle = std::f64::consts::TAU * next();
                    let r = MIN_SEPARATION * (1.0 + (next() - 0.5) * 1e-12);
                    match (next() * 3.0) as usize {
                        0 => [x[0] + r * angle.cos(), x[1] + r * angle.sin(), x[2]],
                        1 => [1.0 + 5.0 * next(), 3.0 * next() - 1.5, 1.0],
                        _ => [f64::NAN; 3],
                    }
                })
                .collect();
            let (mut fast, mut slow) = (joints, joints);
            assert_eq!(
                drop_read_off_nearer(&mut fast, centre, nearer.iter().copied()),
                plain(&mut slow, centre, &nearer)
            );
            assert!(fast
                .iter()
                .zip(&slow)
                .all(|(a, b)| a == b || (a[0].is_nan() && b[0].is_nan())));
        }
    }

    #[test]
    fn a_torso_bent_flat_stays_one_group() {
        // Leaning forwards or back by up to the torso's length, the torso does not split: at
        // most the one joint farthest from the others' median goes (a broad torso bent far).
        for lean in [0.0, 0.3, 0.5, 0.6, -0.5] {
            let mut joints = torso(3.0, lean);
            let dropped = drop_stray(&mut joints, CAMERA);
            assert!(dropped.iter().filter(|&&d| d).count() <= 1, "lean {lean}");
        }
        let mut upright = torso(3.0, 0.0);
        assert_eq!(drop_stray(&mut upright, CAMERA), [false; 4]);
    }

    #[test]
    fn a_pair_hidden_by_someone_nearer_is_dropped_whichever_pair_it_is() {
        // The depth of a person 1.5 m in front of the torso, read at two of its keypoints.
        for hidden in [[0, 1], [2, 3], [0, 2], [1, 3]] {
            let mut joints = torso(4.0, 0.0);
            for k in hidden {
                joints[TORSO[k]][0] -= 1.5;
            }
            let dropped = drop_stray(&mut joints, CAMERA);
            let expected: [bool; 4] = std::array::from_fn(|k| hidden.contains(&k));
            assert_eq!(dropped, expected, "hidden {hidden:?}");
            assert!((0..4).all(|k| joints[TORSO[k]][0].is_nan() == expected[k]));
        }
    }

    #[test]
    fn a_lone_joint_off_the_torso_is_dropped_near_or_far() {
        // Three seen joints: the odd one out goes, whether it came nearer or farther; within the
        // span, three joints cannot tell which is off and all stay.
        for offset in [-2.0, 2.0, -1.2] {
            let mut joints = torso(4.0, 0.0);
            joints[RIGHT_HIP] = [f64::NAN; 3];
            joints[LEFT_HIP][0] += offset;
            assert_eq!(
                drop_stray(&mut joints, CAMERA),
                [false, false, true, false],
                "offset {offset}"
            );
        }
        let mut joints = torso(4.0, 0.0);
        joints[RIGHT_HIP] = [f64::NAN; 3];
        joints[LEFT_HIP][0] -= 0.8;
        assert_eq!(drop_stray(&mut joints, CAMERA), [false; 4]);
        // Two seen joints far apart: the one farther from the camera is the person's.
        let mut joints = torso(4.0, 0.0);
        joints[LEFT_HIP] = [f64::NAN; 3];
        joints[RIGHT_HIP] = [f64::NAN; 3];
        joints[LEFT_SHOULDER][0] -= 2.0;
        assert_eq!(drop_stray(&mut joints, CAMERA), [true, false, false, false]);
    }

    #[test]
    fn nothing_seen_or_one_joint_seen_drops_nothing() {
        let mut joints = [[f64::NAN; 3]; N_JOINTS];
        assert_eq!(drop_stray(&mut joints, CAMERA), [false; 4]);
        joints[RIGHT_HIP] = [3.0, 0.0, 0.9];
        assert_eq!(drop_stray(&mut joints, CAMERA), [false; 4]);
    }
}
