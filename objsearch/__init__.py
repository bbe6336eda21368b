"""objsearch: a benchmark suite for goal-driven object search.

Importing the package registers its Gymnasium environments (``ObjSearch/GridWorld-v0``);
the environments themselves are imported lazily through string entry points.
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

__all__ = ["__version__", "register_envs"]
