"""``MUJOCO_GL``, read when a renderer is made, never rewritten.

``import objsearch`` leaves ``MUJOCO_GL`` as the user set it (or unset) and imports no
MuJoCo. The value chooses the OpenGL backend when the first ``HouseRenderer`` is made
(``objsearch.sim.glbackend``, which reports a value that cannot render in one line).

One thing has to happen earlier: ``import mujoco`` reads ``MUJOCO_GL`` once and fails at once
on a value it does not know (a bare RuntimeError) or on an explicit ``egl`` / ``osmesa`` whose
library is missing (an AttributeError deep in PyOpenGL), even in commands that render nothing
(``--help``, a house's pose graph). The packages that import MuJoCo (``objsearch.house``,
``objsearch.sim``, ``objsearch.perception``) therefore call ``import_mujoco`` first: under such
a value MuJoCo is imported with ``MUJOCO_GL=disable`` (its own ``GLContext``, which objsearch
never uses, is then off) and the value is put back as soon as the import returns.
"""

from __future__ import annotations

import ctypes.util
import os
import sys

KNOWN = ("", "1", "on", "true", "enable", "enabled", "0", "off", "false", "disable", "disabled")
KNOWN += ("egl", "osmesa", "glfw", "glx")
LIBRARIES = {"egl": "EGL", "osmesa": "OSMesa"}


def requested() -> str:
    """The ``MUJOCO_GL`` the user set, '' if none."""
    return os.environ.get("MUJOCO_GL", "")


def missing_library(value: str) -> str | None:
    """The library (``EGL``, ``OSMesa``) that ``MUJOCO_GL=value`` names and that is not installed."""
    library = LIBRARIES.get(value.strip().lower())
    return library if library and ctypes.util.find_library(library) is None else None


def import_fails(value: str | None) -> bool:
    """Whether ``import mujoco`` would fail under ``MUJOCO_GL=value`` (None: unset, it would not)."""
    return value is not None and (value.strip().lower() not in KNOWN or missing_library(value) is not None)


def import_mujoco() -> None:
    """Import MuJoCo now if ``MUJOCO_GL`` holds a value its import would fail on, with
    ``MUJOCO_GL=disable`` for the import alone; ``os.environ`` is as it was when this returns.
    Under any other value (or with MuJoCo imported already) nothing is done: MuJoCo is
    imported where it is needed, as it is."""
    raw = os.environ.get("MUJOCO_GL")
    if "mujoco" in sys.modules or not import_fails(raw):
        return
    os.environ["MUJOCO_GL"] = "disable"
    try:
        import mujoco  # noqa: F401
    finally:
        os.environ["MUJOCO_GL"] = raw
