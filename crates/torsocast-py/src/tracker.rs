//! The multi-person tracker: one call per frame, with the GIL released while the core works.

use crate::arrays::{c_order, depth_size, joints_array, matrix, sequence};
use crate::config::TrackerConfig;
use crate::errors::{shape_error, to_py};
use crate::person::Observation;
use numpy::{AllowTypeChange, PyArray2, PyArray3, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use torso_core::camera::{Camera, Intrinsics, Rigid};
use torso_core::coco::{Joints, N_JOINTS};
use torso_core::depth::DepthImage;
use torso_core::tracker::{Keypoints, Outcome};
use torso_core::Pose;

/// Tracker(config=None): every person in a stream (`torso_core::tracker::Tracker`):
/// association by torso centre, track birth, confirmation and drop, one person chain per track,
/// and with `step` the depth lookup and deprojection of the 2D keypoints.
#[pyclass(module = "torsocast._core")]
pub struct Tracker {
    inner: torso_core::Tracker,
    // Conversion buffers, reused from frame to frame.
    rows: Vec<[[f64; 3]; N_JOINTS]>,
    scores: Vec<[f64; N_JOINTS]>,
    outcomes: Vec<Outcome>,
    poses: Vec<Pose>,
}

/// One detection's outcome in a frame.
#[pyclass(module = "torsocast._core", frozen, get_all)]
pub struct TrackOutcome {
    /// Index of the detection in the frame.
    detection: usize,
    /// The confirmed track's id; None for a tentative track or a detection with no track.
    track_id: Option<u64>,
    /// Unique per track over the tracker's life, tentative tracks included; None without one.
    key: Option<u64>,
    observation: Option<Py<Observation>>,
    /// Grid time of the track's newest sample: its forecasts count from here.
    last_time: Option<f64>,
    /// `(len(horizons), 5)` forecast of a confirmed track, once its history is long enough.
    forecast: Option<Py<PyArray2<f64>>>,
    /// `(len(horizons), 5)` half-widths of the 80 % intervals around `forecast`, once the track's
    /// history is long enough for a line.
    intervals: Option<Py<PyArray2<f64>>>,
}

#[pymethods]
impl TrackOutcome {
    fn __repr__(&self) -> String {
        format!(
            "TrackOutcome(detection={}, track_id={}, key={})",
            self.detection,
            self.track_id.map_or("None".into(), |i| i.to_string()),
            self.key.map_or("None".into(), |i| i.to_string()),
        )
    }
}

/// A confirmed track as the tracker holds it now.
#[pyclass(module = "torsocast._core", frozen, get_all)]
pub struct TrackState {
    id: u64,
    key: u64,
    /// Grid time of the newest sample.
    last_time: Option<f64>,
    /// Samples in the forecaster's history.
    samples: usize,
}

fn rows<const C: usize>(
    name: &str,
    flat: &[f64],
    shape: &[usize],
    out: &mut Vec<[[f64; C]; N_JOINTS]>,
) -> PyResult<()> {
    if shape.len() != 3 || shape[1] != N_JOINTS || shape[2] != C {
        return Err(shape_error(name, &format!("(people, 17, {C})"), shape));
    }
    out.clear();
    out.extend(
        flat.chunks_exact(N_JOINTS * C)
            .map(|person| std::array::from_fn(|j| std::array::from_fn(|c| person[j * C + c]))),
    );
    Ok(())
}

impl Tracker {
    /// The outcomes of the frame just tracked as Python objects, with forecasts and intervals
    /// at `horizons` for confirmed tracks.
    fn outcomes<'py>(&mut self, py: Python<'py>, horizons: &[f64]) -> PyResult<Vec<TrackOutcome>> {
        self.poses.resize(horizons.len(), [0.0; 5]);
        let mut out = Vec::with_capacity(self.outcomes.len());
        for o in &self.outcomes {
            let track = o.track;
            let mut forecast = None;
            let mut intervals = None;
            if let Some(t) = track.filter(|t| t.id.is_some() && !horizons.is_empty()) {
                if self
                    .inner
                    .forecast(t.slot, horizons, &mut self.poses)
                    .map_err(to_py)?
                {
                    forecast = Some(matrix(py, &self.poses).unbind());
                    if self
                        .inner
                        .intervals(t.slot, horizons, &mut self.poses)
                        .map_err(to_py)?
                    {
                        intervals = Some(matrix(py, &self.poses).unbind());
                    }
                }
            }
            let observation = match o.observation {
                Some(inner) => Some(Py::new(py, Observation { inner })?),
                None => None,
            };
            out.push(TrackOutcome {
                detection: o.detection,
                track_id: track.and_then(|t| t.id),
                key: track.map(|t| t.serial),
                observation,
                last_time: track
                    .and_then(|t| self.inner.person(t.slot))
                    .and_then(|p| p.forecaster().last_time()),
                forecast,
                intervals,
            });
        }
        Ok(out)
    }
}

/// The horizons, checked before the frame changes anything.
fn horizons_checked(horizons: Option<Vec<f64>>) -> PyResult<Vec<f64>> {
    let horizons = horizons.unwrap_or_default();
    torso_core::person::check_horizons(&horizons).map_err(to_py)?;
    Ok(horizons)
}

#[pymethods]
impl Tracker {
    #[new]
    #[pyo3(signature = (config=None))]
    fn new(config: Option<PyRef<'_, TrackerConfig>>) -> PyResult<Self> {
        let config = config.map_or_else(torso_core::TrackerConfig::default, |c| c.inner);
        Ok(Self {
            inner: torso_core::Tracker::new(config).map_err(to_py)?,
            rows: Vec::new(),
            scores: Vec::new(),
            outcomes: Vec::new(),
            poses: Vec::new(),
        })
    }

    #[getter]
    fn config(&self) -> TrackerConfig {
        TrackerConfig {
            inner: *self.inner.config(),
        }
    }

    /// Time of the last accepted frame.
    #[getter]
    fn last_time(&self) -> Option<f64> {
        self.inner.last_time()
    }

    /// check_time(t): raises as `update` and `step` would for a frame at `t` (not finite, or not
    /// after the last frame), without changing anything.
    fn check_time(&self, t: f64) -> PyResult<()> {
        self.inner.check_time(t).map_err(to_py)
    }

    /// update(t, joints (people, 17, 3), scores (people, 17), camera_position (3,),
    /// horizons=None) -> list[TrackOutcome]: one frame of world joints (NaN where missing).
    /// A refused frame raises and leaves the tracker as it was.
    #[pyo3(signature = (t, joints, scores, camera_position, horizons=None))]
    fn update(
        &mut self,
        py: Python<'_>,
        t: f64,
        joints: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
        scores: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
        camera_position: PyArrayLikeDyn<'_, f64, AllowTypeChange>,
        horizons: Option<Vec<f64>>,
    ) -> PyResult<Vec<TrackOutcome>> {
        let horizons = horizons_checked(horizons)?;
        let view = joints.as_array();
        rows("joints", &c_order(&view), joints.shape(), &mut self.rows)?;
        if scores.shape() != [self.rows.len(), N_JOINTS] {
            return Err(shape_error(
                "scores",
                "(people, 17) as joints",
                scores.shape(),
            ));
        }
        let view = scores.as_array();
        let flat = c_order(&view);
        self.scores.clear();
        self.scores.extend(
            flat.chunks_exact(N_JOINTS)
                .map(|s| std::array::from_fn(|j| s[j])),
        );
        let view = camera_position.as_array();
        let position: [f64; 3] = c_order(&view)
            .as_ref()
            .try_into()
            .map_err(|_| shape_error("camera_position", "(3,)", camera_position.shape()))?;
        let (inner, rows, scores, outcomes) = (
            &mut self.inner,
            &self.rows,
            &self.scores,
            &mut self.outcomes,
        );
        py.detach(|| -> torso_core::Result<()> {
            let joints: &[Joints] = rows;
            let done = inner.update(t, joints, scores, position)?;
            outcomes.clear();
            outcomes.extend_from_slice(done);
            Ok(())
        })
        .map_err(to_py)?;
        self.outcomes(py, &horizons)
    }

    /// step(t, keypoints (people, 17, 3), depth (h, w), intrinsics (fx, fy, cx, cy),
    /// distortion (5,), camera_to_world (4, 4), horizons=None) -> (joints (people, 17, 3),
    /// list[TrackOutcome]): one frame of 2D keypoints `(u, v, score)` with the depth image (m)
    /// registered to them; the lifted world joints as the tracks took them (NaN where unseen,
    /// without depth, or lifted onto someone nearer the camera) and each detection's outcome.
    /// A refused frame raises and leaves the tracker as it was.
    #[pyo3(signature = (t, keypoints, depth, intrinsics, distortion, camera_to_world, horizons=None))]
    #[allow(clippy::too_many_arguments)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        keypoints: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        depth: PyArrayLikeDyn<'py, f32, AllowTypeChange>,
        intrinsics: Vec<f64>,
        distortion: Vec<f64>,
        camera_to_world: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        horizons: Option<Vec<f64>>,
    ) -> PyResult<(Bound<'py, PyArray3<f64>>, Vec<TrackOutcome>)> {
        let horizons = horizons_checked(horizons)?;
        let intrinsics: [f64; 4] = sequence("intrinsics", &intrinsics)?;
        let distortion: [f64; 5] = sequence("distortion", &distortion)?;
        let view = keypoints.as_array();
        rows(
            "keypoints",
            &c_order(&view),
            keypoints.shape(),
            &mut self.rows,
        )?;
        if camera_to_world.shape() != [4, 4] {
            return Err(shape_error(
                "camera_to_world",
                "(4, 4)",
                camera_to_world.shape(),
            ));
        }
        let view = camera_to_world.as_array();
        let m = c_order(&view);
        let to_world = Rigid::from_rows(std::array::from_fn(|i| {
            std::array::from_fn(|j| m[4 * i + j])
        }))
        .map_err(to_py)?;
        let [fx, fy, cx, cy] = intrinsics;
        let camera = Camera::new(
            Intrinsics::new(fx, fy, cx, cy, distortion).map_err(to_py)?,
            to_world,
        );
        let (height, width) = depth_size(depth.shape())?;
        let view = depth.as_array();
        let pixels = c_order(&view);
        let image = DepthImage::new(&pixels, width, height).map_err(to_py)?;
        let (inner, rows, outcomes) = (&mut self.inner, &self.rows, &mut self.outcomes);
        py.detach(|| -> torso_core::Result<()> {
            let keypoints: &[Keypoints] = rows;
            let done = inner.step(t, keypoints, &image, &camera)?;
            outcomes.clear();
            outcomes.extend_from_slice(done);
            Ok(())
        })
        .map_err(to_py)?;
        let array = joints_array(py, self.inner.joints());
        Ok((array, self.outcomes(py, &horizons)?))
    }

    /// The last frame's joints (people, 17, 3) as given to `update` or lifted by `step`, before
    /// the tracker dropped any read off someone nearer the camera: `update` with them tracks
    /// the frame again as it was tracked (what a recording of a stream keeps).
    #[getter]
    fn lifted<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        joints_array(py, self.inner.lifted())
    }

    /// The confirmed tracks, in order of birth.
    #[getter]
    fn tracks(&self) -> Vec<TrackState> {
        self.inner
            .tracks()
            .map(|(t, p)| TrackState {
                id: t.id.expect("confirmed"),
                key: t.serial,
                last_time: p.forecaster().last_time(),
                samples: p.forecaster().len(),
            })
            .collect()
    }

    /// forecast(track_id, horizons) -> (len(horizons), 5) or None: the confirmed track's
    /// forecast (None for an unknown id or a history too short).
    fn forecast<'py>(
        &mut self,
        py: Python<'py>,
        track_id: u64,
        horizons: Vec<f64>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.poses_of(py, track_id, &horizons, |t, slot, h, out| {
            t.forecast(slot, h, out)
        })
    }

    /// intervals(track_id, horizons) -> (len(horizons), 5) or None: the half-widths of the 80 %
    /// intervals around the confirmed track's forecast (None for an unknown id or a history
    /// too short for a line).
    fn intervals<'py>(
        &mut self,
        py: Python<'py>,
        track_id: u64,
        horizons: Vec<f64>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.poses_of(py, track_id, &horizons, |t, slot, h, out| {
            t.intervals(slot, h, out)
        })
    }

    /// A copy with every track's state (`copy.copy` and `copy.deepcopy` give it).
    fn __copy__(&self) -> Self {
        Self {
            inner: self.inner.clone(),
            rows: Vec::new(),
            scores: Vec::new(),
            outcomes: Vec::new(),
            poses: Vec::new(),
        }
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.__copy__()
    }

    /// restart(): drops every track and forgets the last frame's time, as for a new stream; ids
    /// go on counting.
    fn restart(&mut self) {
        self.inner.restart();
    }

    /// Live tracks, tentative ones included.
    fn __len__(&self) -> usize {
        self.inner.live()
    }
}

impl Tracker {
    /// The `(len(horizons), 5)` poses `fill` writes for the confirmed track `track_id` (None for
    /// an unknown id, or where `fill` has none to give).
    fn poses_of<'py>(
        &mut self,
        py: Python<'py>,
        track_id: u64,
        horizons: &[f64],
        fill: impl FnOnce(
            &mut torso_core::Tracker,
            usize,
            &[f64],
            &mut [Pose],
        ) -> torso_core::Result<bool>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let Some(slot) = self.slot_of(track_id) else {
            return Ok(None);
        };
        self.poses.resize(horizons.len(), [0.0; 5]);
        if fill(&mut self.inner, slot, horizons, &mut self.poses).map_err(to_py)? {
            Ok(Some(matrix(py, &self.poses)))
        } else {
            Ok(None)
        }
    }

    fn slot_of(&self, track_id: u64) -> Option<usize> {
        self.inner
            .tracks()
            .find(|(t, _)| t.id == Some(track_id))
            .map(|(t, _)| t.slot)
    }
}
