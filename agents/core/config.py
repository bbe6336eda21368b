"""What the learned agents' configs of both worlds share besides their fields
(``gridworld.config.GridAgentConfig``, ``house.config.HouseAgentConfig``): the method check,
the checks of the counts that must be at least 1, and what the method makes of the config
(``hierarchical``, the agent ``name``).

The fields stay in each world's dataclass, in each one's order: a config is stored as a
JSON object, in field order, in every ``policy.pt`` and ``config.json`` (the shipped
checkpoints' digests cover those bytes), and a dataclass base would put its fields first,
so a run trained after the move would write other bytes than one trained before it. The
shared fields' defaults differ by world too (the paper's grid-world and house protocols:
``option_steps`` 10 or 50, ``rmsprop_alpha`` 0.9 or 0.99, ...).
"""

from __future__ import annotations

from objsearch.configs import JsonConfig, require_at_least
from objsearch.errors import UserError


class AgentConfig(JsonConfig):
    """Base of the learned agents' dataclass configs; ``__post_init__`` checks the method
    (one of ``METHODS``), then the world's own rules (``check``), then ``AT_LEAST_ONE``."""

    METHODS: tuple[str, ...] = ()
    """The methods the world trains (``objsearch_agents.methods.METHODS`` or a subset)."""
    AT_LEAST_ONE: tuple[str, ...] = ()
    """The fields (counts, intervals) that must be at least 1, checked in this order."""

    def __post_init__(self):
        if self.method not in self.METHODS:
            raise UserError(f"method must be one of {self.METHODS}, not {self.method!r}")
        self.check()
        require_at_least(self, self.AT_LEAST_ONE, 1)

    def check(self) -> None:
        """The world's own rules (``UserError`` for a bad value)."""

    @property
    def hierarchical(self) -> bool:
        """Whether the method chooses sub-goals for a low level (h-DQN, HRL-GRG)."""
        from objsearch_agents.methods import method_of

        return method_of(self.method).hierarchical

    @property
    def name(self) -> str:
        """The agent name this config trains (``hrl_grg_no_relation`` for an ablation)."""
        from objsearch_agents.methods import method_of

        return method_of(self.method).agent_name(self)
