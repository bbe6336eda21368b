"""objsearch: a benchmark suite for goal-driven object search.

Importing the package registers its Gymnasium environments (``objsearch.envs``:
``ObjSearch/GridWorld-v0``, ``ObjSearch/House-v1``, ``ObjSearch/Suite-v1``, which plays a
suite's fixed episodes, and ``ObjSearch/<suite>-v1`` for every shipped suite); the environments themselves are imported lazily through string entry
points. It imports no MuJoCo and leaves ``MUJOCO_GL`` as it is (``objsearch.mujoco_gl``). The
Python API (``objsearch.api``): ``evaluate(agent, suite, seeds=..., split=...)``, ``make_suite``
and ``register_suite``, imported on first use.
"""

from objsearch.envs import register_envs
from objsearch.version import __version__

register_envs()

__all__ = ["__version__", "evaluate", "make_suite", "register_envs", "register_suite"]
_API = ("evaluate", "make_suite", "register_suite")


def __getattr__(name: str):
    if name in _API:  # the harness loads only when used
        from objsearch import api

        return getattr(api, name)
    if name == "dm_env":  # the adapter's name until 2026-12-05, which shadowed the package it wraps
        import warnings

        from objsearch import dm_adapter

        warnings.warn(
            "objsearch.dm_env is now objsearch.dm_adapter (from objsearch import dm_adapter)",
            DeprecationWarning,
            stacklevel=2,
        )
        return dm_adapter
    raise AttributeError(f"module 'objsearch' has no attribute {name!r}")
