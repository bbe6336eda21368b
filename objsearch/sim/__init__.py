"""Simulation of generated houses: rendering (RGB, depth, segmentation), poses, envs, caches."""

from objsearch.mujoco_gl import import_mujoco

import_mujoco()  # before this package imports MuJoCo, whatever MUJOCO_GL holds (objsearch.mujoco_gl)
