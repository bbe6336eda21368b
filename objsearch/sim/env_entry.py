"""The entry point of ``ObjSearch/House-v0`` (``objsearch.envs``): ``HouseEnv`` with its
``max_steps`` checked first, so that ``gymnasium.make("ObjSearch/House-v0", max_steps=-5)``
says which argument is wrong instead of failing inside the observation space's ``Box``."""

from __future__ import annotations

import numbers

from objsearch.sim.env import HouseEnv


def check_max_steps(value) -> int:
    """``max_steps`` as an int if it is an integer >= 1 (a Python or numpy integer, or a float
    with no fraction); else ``ValueError`` naming it: ``-5``, ``0``, ``2.5``, ``True`` or ``"100"``
    are not step limits."""
    whole = isinstance(value, numbers.Integral) or (isinstance(value, float) and value.is_integer())
    if isinstance(value, bool) or not whole or value < 1:
        raise ValueError(
            f"max_steps={value!r}: the step limit of an episode is an integer >= 1 (e.g. max_steps=1000, the default)"
        )
    return int(value)


def make_house_env(**kwargs) -> HouseEnv:
    """``HouseEnv(**kwargs)``, its ``max_steps`` checked (``check_max_steps``) first."""
    if "max_steps" in kwargs:
        kwargs["max_steps"] = check_max_steps(kwargs["max_steps"])
    return HouseEnv(**kwargs)


make_house_env.metadata = HouseEnv.metadata  # what gymnasium.make reads of an entry point (render modes)
