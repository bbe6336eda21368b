"""An example out-of-tree suite: the grid world's episodes with half the paper's step limit.

A suite is any class with the protocol of ``objsearch.eval.suites`` (``world``, ``protocol``,
``options``, ``splits``, ``episodes(split)``, ``make_env()``, ``config()``); this one reuses
the grid world's and changes one default. The entry point in ``pyproject.toml`` names it.
"""

from objsearch.eval.suites.gridworld import GridWorldSuite


class ShortGridWorldSuite(GridWorldSuite):
    """The grid world in 50 steps instead of 100: a search must be direct to count."""

    def __init__(self, name: str = "gridworld-short", maps=None, tasks=None, max_steps: int = 50):
        super().__init__(name, maps, tasks, max_steps)
