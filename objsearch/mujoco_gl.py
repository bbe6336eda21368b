"""``MUJOCO_GL``, looked at before MuJoCo is imported.

``import mujoco`` reads ``MUJOCO_GL`` once and fails at once on a value it does not know (a
bare RuntimeError) or on an explicit ``egl`` / ``osmesa`` whose library is missing (an
AttributeError deep in PyOpenGL), even in commands that render nothing (``--help``, the grid
world). Importing ``objsearch`` therefore sets such a value aside: it moves to
``OBJSEARCH_MUJOCO_GL`` (which worker processes inherit), ``MUJOCO_GL`` becomes ``disable``
for the import, and the first render reports the value in one line
(``objsearch.sim.glbackend``).
"""

from __future__ import annotations

import ctypes.util
import os

SET_ASIDE = "OBJSEARCH_MUJOCO_GL"
KNOWN = ("", "1", "on", "true", "enable", "enabled", "0", "off", "false", "disable", "disabled")
KNOWN += ("egl", "osmesa", "glfw", "glx")
LIBRARIES = {"egl": "EGL", "osmesa": "OSMesa"}


def requested() -> str:
    """The ``MUJOCO_GL`` the user set (also one set aside), '' if none."""
    return os.environ.get(SET_ASIDE, os.environ.get("MUJOCO_GL", ""))


def missing_library(value: str) -> str | None:
    """The library (``EGL``, ``OSMesa``) that ``MUJOCO_GL=value`` names and that is not installed."""
    library = LIBRARIES.get(value.strip().lower())
    return library if library and ctypes.util.find_library(library) is None else None


def set_aside_unusable() -> None:
    """Move a ``MUJOCO_GL`` that would make ``import mujoco`` fail to ``OBJSEARCH_MUJOCO_GL``."""
    raw = os.environ.get("MUJOCO_GL")
    if raw is None or SET_ASIDE in os.environ:
        return
    if raw.strip().lower() not in KNOWN or missing_library(raw):
        os.environ[SET_ASIDE] = raw
        os.environ["MUJOCO_GL"] = "disable"
