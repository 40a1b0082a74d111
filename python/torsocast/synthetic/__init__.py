"""Synthetic RGB-D frames from mocap, with exact ground truth: the demo's walk and the scenes
benchmark's crowds. Not part of the runtime library (the pipeline never imports it)."""
