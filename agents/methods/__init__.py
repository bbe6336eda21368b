"""The learning methods, one module each: ``a3c``, ``dqn``, ``hdqn`` and ``hrl_grg`` (its
ablations are switches of the config: ``relation``, ``termination``, ``high_level``).

A method is a small strategy object (``base.Method``): which networks it has, how its high
level chooses a sub-goal, when it ends an option besides the shared rules, and its
Q-learning loss. Both worlds' policies and training loops run any method through it, each
through its world adapter (``gridworld.world.GridWorldAdapter``, ``house.world.HouseWorld``),
and never ask which method it is (``a3c`` runs in the houses only).
"""

from __future__ import annotations

import importlib

METHODS = ("a3c", "dqn", "hdqn", "hrl_grg")


def method_of(name: str):
    """The strategy of method ``name`` (one of ``METHODS``)."""
    if name not in METHODS:
        raise KeyError(name)
    return importlib.import_module(f"objsearch_agents.methods.{name}").METHOD
