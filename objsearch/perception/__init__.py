"""Perception: a DeepLabv3+-style network that predicts semantic segmentation and depth from
RGB, its datasets of rendered frames, training, metrics, and the predictor behind the house
env's ``observation="predicted"`` (``docs/perception.md``)."""

from objsearch.mujoco_gl import import_mujoco

import_mujoco()  # before this package imports MuJoCo, whatever MUJOCO_GL holds (objsearch.mujoco_gl)
