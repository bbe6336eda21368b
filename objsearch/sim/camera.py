"""Cameras as pure data: ``RenderSettings``, the agent camera, and the one camera check.

Light on purpose: no MuJoCo, no OpenGL, no torch. Configs, checkpoints, suites and caches
name and compare cameras without starting a renderer (``objsearch.sim.renderer`` draws
what a ``RenderSettings`` describes).

Two cameras are named, and they are independent concepts that happen to be equal today:

* ``AGENT_CAMERA`` (here): what agents see. The house env's default, the observation
  caches agents read, the perception network's training frames and the camera recorded in
  house policies' checkpoints. Changing it means re-rendering caches and retraining.
* ``GOAL_CAMERA`` (``objsearch.sim.goals``): the camera the goal rule looks through to
  choose goal poses. Fixed benchmark data: the suite files store its poses, so it never
  follows the agent camera.

A network or policy trained on one camera cannot be used with another: every place that
pairs them calls ``check_camera``, which raises ``CameraMismatchError`` naming the
checkpoint, both cameras and the fix.
"""

from __future__ import annotations

import hashlib
import json
import math
import numbers
from dataclasses import dataclass, fields

from objsearch.configs import JsonConfig
from objsearch.errors import UserError

__all__ = [
    "RENDERER_VERSION",
    "MAX_SHEET",
    "RenderSettings",
    "AGENT_CAMERA",
    "AGENT_CAMERA_NAME",
    "PERCEPTION_FIX",
    "CameraMismatchError",
    "check_camera",
    "check_predictor_camera",
    "describe_camera",
]

#: Bump whenever the same settings and house could give different pixels (of
#: ``objsearch.sim.renderer.HouseRenderer``). Here, not in the renderer, because every cache
#: key hashes it (``RenderSettings.key``) and computing a key must not load MuJoCo.
RENDERER_VERSION = "house-renderer-1"

MAX_SHEET = 2048  # largest side of the renderer's tiled offscreen buffer, pixels (so the largest image side)


@dataclass(frozen=True)
class RenderSettings(JsonConfig):
    """A camera: image size, field of view, height, clipping, ceiling. Part of every cache key (``key()``).

    Stored as JSON through ``objsearch.configs.JsonConfig``: ``to_json()`` is a dict of plain
    ints, floats and bools (what checkpoints, manifests and cache headers record),
    ``from_json(data, source=...)`` reads one back (unknown keys are an error; a missing key
    takes today's default, so whoever needs a complete record checks it, as
    ``objsearch.perception.inference.checkpoint_settings`` does).

    The defaults are today's agent camera; code that means a particular camera names it
    (``AGENT_CAMERA``, ``objsearch.sim.goals.GOAL_CAMERA``) rather than relying on them.
    """

    width: int = 64
    """Image width in pixels."""
    height: int = 64
    """Image height in pixels."""
    fovy: float = 90.0
    """Vertical field of view in degrees; the horizontal one follows from width / height."""
    camera_height: float = 1.0
    """Height of the optical centre above the floor, metres."""
    znear: float = 0.05
    """Near clipping distance, metres (the agent's radius is 0.2 m)."""
    zfar: float = 30.0
    """Far clipping distance, metres; also the depth of pixels that see nothing."""
    ceiling: bool = True
    """Close the rooms with a ceiling (category ``ceiling``) at the top of the walls."""

    DESCRIPTION = "camera settings"
    JSON_SORT_KEYS = True

    def __post_init__(self):
        if not all(isinstance(v, numbers.Integral) and 1 <= v <= MAX_SHEET for v in (self.width, self.height)):
            raise UserError(f"render size {self.width}x{self.height} must be integers in 1..{MAX_SHEET}")
        for name, kind in (
            ("width", int),
            ("height", int),
            ("fovy", float),
            ("camera_height", float),
            ("znear", float),
            ("zfar", float),
            ("ceiling", bool),
        ):
            object.__setattr__(self, name, kind(getattr(self, name)))  # plain Python types: JSON, stable keys
        if not 1.0 <= self.fovy <= 170.0:
            raise UserError(f"fovy={self.fovy} must be in [1, 170] degrees")
        if not 0.0 < self.znear < self.zfar:
            raise UserError(f"need 0 < znear < zfar, got znear={self.znear}, zfar={self.zfar}")

    def intrinsics(self) -> dict:
        """What an agent needs to turn a depth image into points: image size, vertical and
        horizontal field of view (degrees), pinhole focal lengths and principal point (pixels;
        row 0 is the top, column 0 the left), the camera's height above the floor and the
        clipping range (metres). Depth is planar: a pixel (u, v) at depth z is the point
        ``((u + 0.5 - cx) * z / fx, (cy - v - 0.5) * z / fy, z)`` (right, up, forward)."""
        # rounded: tan(45 degrees) is 0.9999999999999999 in floating point
        fy = round(self.height / 2 / math.tan(math.radians(self.fovy) / 2), 9)
        fovx = round(math.degrees(2 * math.atan(self.width / 2 / fy)), 9)
        return {
            "width": self.width,
            "height": self.height,
            "vfov": self.fovy,
            "hfov": fovx,
            "fx": fy,  # square pixels
            "fy": fy,
            "cx": self.width / 2,
            "cy": self.height / 2,
            "camera_height": self.camera_height,
            "znear": self.znear,
            "zfar": self.zfar,
            "depth": "planar",
        }

    def key(self) -> str:
        """A short stable hash of the settings and ``RENDERER_VERSION`` (cache keys use it)."""
        # The bytes hashed are those of every existing cache key: keep them (tests/sim/test_cameras.py pins one).
        text = json.dumps([RENDERER_VERSION, self.to_json()], sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


AGENT_CAMERA = RenderSettings(width=64, height=64, fovy=90.0, camera_height=1.0, znear=0.05, zfar=30.0, ceiling=True)
"""What agents see: 64 x 64 pixels, 90 degrees vertical field of view, 1 m above the floor
(the paper's egocentric camera). The house env's default camera, the camera of the
observation caches that suites and training read, of the perception network's training
frames (``objsearch perception dataset`` without ``--size``), and the one house policies
record. Every field is given, so a change to ``RenderSettings``' defaults leaves it (and
every cache key) alone."""

AGENT_CAMERA_NAME = "the agent camera (objsearch.sim.camera.AGENT_CAMERA)"
"""How error messages name ``AGENT_CAMERA``."""

PERCEPTION_FIX = (
    "use a perception network trained on frames of that camera (objsearch perception dataset, then "
    "objsearch perception train), or pass --perception with such a checkpoint"
)


class CameraMismatchError(UserError):
    """A checkpoint (a perception network, a house policy) was made for another camera than
    the one it is used with. The one error type of ``check_camera``."""


def describe_camera(camera) -> str:
    """``width=64 height=64 fovy=90.0 ...`` for a ``RenderSettings``; ``repr`` for anything else."""
    if isinstance(camera, RenderSettings):
        return " ".join(f"{k}={v}" for k, v in camera.to_json().items())
    return "none recorded" if camera is None else repr(camera)


def _as_settings(camera) -> RenderSettings | None:
    """``camera`` as ``RenderSettings``: itself, or a complete ``to_json()`` record; None if it is neither."""
    if isinstance(camera, RenderSettings):
        return camera
    if isinstance(camera, dict) and set(camera) == {f.name for f in fields(RenderSettings)}:
        try:
            return RenderSettings.from_json(camera)
        except (UserError, TypeError, ValueError):
            return None
    return None


def check_camera(camera, expected: RenderSettings, *, source: str, expected_name: str, fix: str) -> RenderSettings:
    """The one camera compatibility check: ``camera`` (what ``source`` was made for) must be ``expected``.

    Args:
        camera: the checkpoint's camera: ``RenderSettings``, or the ``to_json()`` record a
            file holds (an incomplete or unreadable record, or None, never matches).
        expected: the camera it is about to be used with.
        source: names the checkpoint, e.g. ``"perception checkpoint runs/p/model.pt"``.
        expected_name: names ``expected``, e.g. ``AGENT_CAMERA_NAME``.
        fix: what the user can do about it.

    Returns:
        ``camera`` as ``RenderSettings`` (equal to ``expected``).

    Raises:
        CameraMismatchError: (a ``UserError``: the CLI exits 2) naming the checkpoint, its
            camera, the camera expected and the fix.
    """
    settings = _as_settings(camera)
    if settings == expected:
        return settings
    if settings is None:
        differ = "its camera record is missing, incomplete or unreadable"
    else:
        mine, theirs = settings.to_json(), expected.to_json()
        differ = "they differ in " + ", ".join(k for k in theirs if mine[k] != theirs[k])
    raise CameraMismatchError(
        f"{source} was made for camera [{describe_camera(settings or camera)}], but "
        f"{expected_name} is [{describe_camera(expected)}] ({differ}); {fix}"
    )


def check_predictor_camera(
    predictor, expected: RenderSettings = AGENT_CAMERA, expected_name: str = AGENT_CAMERA_NAME
) -> None:
    """``check_camera`` for a perception ``Predictor`` (its ``settings``: the camera of its
    training frames; its ``checkpoint``: where it came from) about to see frames of ``expected``.

    A predictor without ``settings`` (any object with ``key`` and ``predict``, see
    ``objsearch.sim.cache.Predictor``) declares no camera and is not checked.
    """
    if getattr(predictor, "settings", None) is None:
        return
    where = getattr(predictor, "checkpoint", None)
    source = f"perception checkpoint {where}" if where else f"perception network {getattr(predictor, 'key', '?')}"
    check_camera(predictor.settings, expected, source=source, expected_name=expected_name, fix=PERCEPTION_FIX)
