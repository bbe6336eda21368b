"""Choosing and creating the headless OpenGL context a ``HouseRenderer`` draws into.

``MUJOCO_GL`` (as ``objsearch.mujoco_gl.requested`` reads it) picks the backend when set
(``egl``, ``osmesa`` or ``glfw``; ``glx`` means
``glfw`` as in MuJoCo). When it is unset (or ``1``/``on``/...), EGL is tried first (Mesa
llvmpipe on a CPU machine, the NVIDIA driver on a GPU) and OSMesa second. When nothing
works, ``RenderBackendError`` names every backend tried, why it failed, and the fix.

One caveat of the Python stack: PyOpenGL binds to one platform (``PYOPENGL_PLATFORM``) for
the life of the process. The first backend that works is therefore remembered and reused
by every later context; and if EGL is tried and fails after PyOpenGL was loaded for it,
OSMesa cannot be loaded in the same process (the error then says to set
``MUJOCO_GL=osmesa``). We never use MuJoCo's own ``gl_context`` (chosen once at
``import mujoco``), so the choice is made when a renderer is created.
"""

from __future__ import annotations

import ctypes.util
import os

from objsearch import mujoco_gl
from objsearch.errors import UserError

BACKENDS = ("egl", "osmesa", "glfw")
AUTO_ORDER = ("egl", "osmesa")
_ALIASES = {"glx": "glfw"}
_AUTO_VALUES = ("", "1", "on", "true", "enable", "enabled")
_DISABLED_VALUES = ("0", "off", "false", "disable", "disabled")
_FIX = (
    "install an OpenGL backend (Debian/Ubuntu: apt-get install libegl1 libgl1 for EGL, "
    "or libosmesa6 for OSMesa) or set MUJOCO_GL to one that works here (egl, osmesa, glfw); "
    "on a GPU machine EGL needs the NVIDIA driver's libEGL_nvidia"
)

_working_backend: str | None = None


class RenderBackendError(UserError):
    """No OpenGL backend could be created for offscreen rendering."""


def requested_backends(value: str | None = None) -> tuple[str, ...]:
    """Backends to try, in order, for a ``MUJOCO_GL`` value (default: the environment's).

    Raises:
        RenderBackendError: ``MUJOCO_GL`` names no backend or disables rendering.
    """
    raw = mujoco_gl.requested() if value is None else value
    name = raw.strip().lower()
    if name in _AUTO_VALUES:
        return AUTO_ORDER
    name = _ALIASES.get(name, name)
    if name in BACKENDS:
        return (name,)
    if name in _DISABLED_VALUES:
        raise RenderBackendError(
            f"MUJOCO_GL={raw!r} disables rendering; unset it (tries {' then '.join(AUTO_ORDER)}) "
            f"or set it to one of {', '.join(BACKENDS)}"
        )
    raise RenderBackendError(
        f"MUJOCO_GL={raw!r} is not a rendering backend; set it to one of {', '.join(BACKENDS)} "
        f"or unset it to try {' then '.join(AUTO_ORDER)}"
    )


def check_mujoco_gl() -> None:
    """Raise ``RenderBackendError`` if ``MUJOCO_GL`` names no backend, or one not installed.

    Called when a renderer is first created (``create_gl_context``), not at import: a value
    that ``import mujoco`` would fail on was set aside by ``objsearch.mujoco_gl``, so that
    commands that render nothing run whatever it is.
    """
    raw = mujoco_gl.requested()
    if raw.strip().lower() not in _DISABLED_VALUES:
        requested_backends()
    library = mujoco_gl.missing_library(raw)
    if library:
        raise RenderBackendError(f"MUJOCO_GL={raw!r} but lib{library} is not installed; fix: {_FIX}")


def _context_class(name: str):
    """Import the backend's GLContext class (imports can fail: missing library or PyOpenGL)."""
    if name == "egl":
        if ctypes.util.find_library("EGL") is None:
            raise ImportError("libEGL not found")
        from mujoco.egl import GLContext
    elif name == "osmesa":
        if ctypes.util.find_library("OSMesa") is None:
            raise ImportError("libOSMesa not found")
        from mujoco.osmesa import GLContext
    else:
        from mujoco.glfw import GLContext
    return GLContext


def create_gl_context(width: int, height: int):
    """Create and make current a headless GL context; returns ``(context, backend name)``.

    Args:
        width: Largest framebuffer width the context will render (OSMesa allocates it).
        height: Largest framebuffer height.

    Raises:
        RenderBackendError: No backend worked; the message lists each one tried and why.
    """
    global _working_backend
    check_mujoco_gl()
    candidates = requested_backends()
    if _working_backend is not None and _working_backend in candidates:
        candidates = (_working_backend,)
    failures = []
    for name in candidates:
        platform = os.environ.get("PYOPENGL_PLATFORM")
        if platform and platform.lower() != name and name != "glfw":
            failures.append(
                f"{name}: PyOpenGL is already bound to platform {platform!r} in this process "
                f"(set MUJOCO_GL={name} before the first render)"
            )
            continue
        context = None
        try:
            context = _context_class(name)(width, height)
            if name == "glfw" and not getattr(context, "_context", None):
                raise RuntimeError("could not create a hidden GLFW window (no display?)")
            context.make_current()
        except Exception as err:  # noqa: BLE001 - any failure means: try the next backend
            failures.append(f"{name}: {type(err).__name__}: {err}")
            if context is not None:
                try:
                    context.free()
                except Exception:  # noqa: BLE001
                    pass
            continue
        _working_backend = name
        return context, name
    raise RenderBackendError(
        f"no OpenGL backend works for offscreen rendering (tried {'; '.join(failures)}); fix: {_FIX}"
    )
