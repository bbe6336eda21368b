"""Appearance variety for the perception network's training frames ("variety over volume").

Test houses hold object shapes the network never saw in training (each category's held-out
mesh variant), and the categories it fails on are the ones whose unseen shape looks like
another category's seen one (dresser -> sideboard, stove -> counter). ``vary_model`` gives
every training house new proportions and colours at render time, so the network sees many
shapes and colours per category instead of 3 shapes and a palette:

* every object's mesh is stretched along the world's x, y and z axes by factors drawn
  log-uniformly from ``SCALE``, about the centre of its footprint and its lowest point: it
  stands where it stood (a small object on a receptacle whose height changed floats above
  it or sinks into it by the difference; its normals are not recomputed);
* every object's colour is shifted in hue, saturation and value, and with probability
  ``RECOLOUR`` replaced by a random one;
* wall and floor materials get smaller shifts; the light's brightness changes.

Only the compiled model that frames are rendered from changes: the house's spec, its files
and every suite stay as they are, and so do the validation and test frames. ``strength``
(0..1) scales every range; 0 leaves the model untouched. Same model, rng state and strength,
same result.

Measured (``docs/perception.md``, "Appearance variety"): at strength 1 it lowered every test
measure of a 6,000-step training run by 0.02-0.03 and did not help the look-alike categories;
the shipped network is trained without it.
"""

from __future__ import annotations

import colorsys
import copy

import mujoco
import numpy as np

SCALE = (0.7, 1.4)  # range of each axis's stretch factor at strength 1
HUE = 0.08  # +- hue shift of objects (fraction of the colour wheel)
SATURATION = (0.6, 1.5)  # saturation factor
VALUE = (0.7, 1.3)  # value (brightness) factor
RECOLOUR = 0.25  # chance that an object gets a random colour
STRUCTURE = 0.5  # the structure's (wall, floor) shifts relative to the objects'
LIGHT = (0.75, 1.25)  # diffuse light factor


def _factor(rng: np.random.Generator, bounds: tuple[float, float], strength: float, size=None):
    """A factor drawn log-uniformly from ``bounds`` narrowed toward 1 by ``strength``."""
    lo, hi = np.log(bounds[0]) * strength, np.log(bounds[1]) * strength
    return np.exp(rng.uniform(lo, hi, size))


def _shift_colour(rgba: np.ndarray, rng: np.random.Generator, strength: float, recolour: float) -> np.ndarray:
    """``rgba`` with its hue, saturation and value shifted, or (``recolour`` chance) random."""
    if rng.random() < recolour * strength:
        rgb = rng.uniform(0.05, 0.95, 3)
    else:
        h, s, v = colorsys.rgb_to_hsv(*(float(c) for c in rgba[:3]))
        h = (h + rng.uniform(-HUE, HUE) * strength) % 1.0
        s = min(s * _factor(rng, SATURATION, strength), 1.0)
        v = min(v * _factor(rng, VALUE, strength), 1.0)
        rgb = np.array(colorsys.hsv_to_rgb(h, s, v))
    return np.array([*rgb, rgba[3]], dtype=rgba.dtype)


def vary_model(model: mujoco.MjModel, rng: np.random.Generator, strength: float = 1.0) -> mujoco.MjModel:
    """A copy of the house ``model`` with its objects stretched and recoloured and its walls,
    floors and light shifted, drawn from ``rng`` (see the module docstring)."""
    if not 0.0 <= strength <= 1.0:
        raise ValueError(f"strength must be in [0, 1], not {strength}")
    model = copy.deepcopy(model)
    if strength == 0.0:
        return model
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    objects = np.flatnonzero(model.geom_type == mujoco.mjtGeom.mjGEOM_MESH)
    for g in objects:
        mesh = model.geom_dataid[g]
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        rot = data.geom_xmat[g].reshape(3, 3)
        world = model.mesh_vert[start : start + count].astype(np.float64) @ rot.T  # offsets in world axes
        stretch = _factor(rng, SCALE, strength, 3)
        low, high = world.min(axis=0), world.max(axis=0)
        anchor = np.array([(low[0] + high[0]) / 2, (low[1] + high[1]) / 2, low[2]])  # footprint centre, bottom
        local = (anchor + (world - anchor) * stretch) @ rot
        model.mesh_vert[start : start + count] = local
        model.geom_rbound[g] = np.linalg.norm(local, axis=1).max()
        lo, hi = local.min(axis=0), local.max(axis=0)
        model.geom_aabb[g] = np.concatenate([(lo + hi) / 2, (hi - lo) / 2])
        model.geom_rgba[g] = _shift_colour(model.geom_rgba[g], rng, strength, RECOLOUR)
    for m in range(model.nmat):
        model.mat_rgba[m] = _shift_colour(model.mat_rgba[m], rng, strength * STRUCTURE, 0.0)
    for light in range(model.nlight):
        model.light_diffuse[light] = np.clip(model.light_diffuse[light] * _factor(rng, LIGHT, strength), 0.0, 1.0)
    return model
