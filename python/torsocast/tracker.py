"""Multi-person tracking, in the core (``torso_core::tracker``): detections to tracks by their 3D
torso centres (the optimal assignment within ``TrackerConfig.gate``, widened by 1 m per second
the camera sent no frame beyond 0.2 s between two frames), tentative tracks confirmed
after ``min_hits`` matched frames and given the next id, a confirmed track dropped after
``max_missing`` s unmatched (a tentative one at its first miss), one person chain per track. A
detection whose torso centre lies within ``MIN_SEPARATION`` (0.25 m) of one a track took is the
same body seen twice and opens no track; before association, a detection's joints lying within
``MIN_SEPARATION`` of the torso centre of someone nearer the camera were lifted onto them, and
are dropped.

:meth:`Tracker.step` takes a frame's 2D keypoints and registered depth image in one call (depth
lookup, deprojection, association, every track's update and forecast); :meth:`Tracker.update`
takes joints already in 3D. Every setting and its default lives in the core's configuration
structs, exposed here as frozen classes: :class:`TrackerConfig`, :class:`PersonConfig`,
:class:`DepthLookup`.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ._core import DepthLookup, PersonConfig, Tracker, TrackerConfig, TrackOutcome, TrackState

F64 = npt.NDArray[np.float64]

__all__ = ["F64", "DepthLookup", "PersonConfig", "TrackOutcome", "TrackState", "Tracker", "TrackerConfig"]
