"""The rendered scenes benchmark (``torsocast eval scenes``): people from mocap seen by a virtual
RGB-D camera, every frame through the real pipeline and keypoint model, scored against the
truth per view, distance, number of people, motion category and frame rate (and by the torso's
tilt from upright).

:mod:`.plan` draws the scenes, :mod:`.run` runs them, :mod:`.score` turns frames into records,
:mod:`.tables` groups the records, :mod:`.report` and :mod:`.figures` write them."""
