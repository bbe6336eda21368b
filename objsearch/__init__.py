"""objsearch: a benchmark suite for goal-driven object search.

Importing the package registers its Gymnasium environments (``ObjSearch/GridWorld-v0``);
the environments themselves are imported lazily through string entry points. The Python
API (``objsearch.api``): ``evaluate(agent, suite, seeds=..., split=...)``, ``make_suite``
and ``register_suite``, imported on first use.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("objsearch")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

from objsearch.mujoco_gl import set_aside_unusable

set_aside_unusable()  # before anything imports mujoco

from objsearch.envs import register_envs  # noqa: E402

register_envs()

__all__ = ["__version__", "evaluate", "make_suite", "register_envs", "register_suite"]
_API = ("evaluate", "make_suite", "register_suite")


def __getattr__(name: str):
    if name in _API:  # the harness loads only when used
        from objsearch import api

        return getattr(api, name)
    raise AttributeError(f"module 'objsearch' has no attribute {name!r}")
