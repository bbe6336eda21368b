"""A3C (paper appendix B.2; houses only): an actor-critic on the target's mask and depth,
trained as synchronous A2C over the lockstep episodes (n-step rollouts, entropy bonus,
RMSProp; ``objsearch_agents.core.a2c``). No high level, no Q-network: every action is sampled
from the policy pointed at the episode's target."""

from __future__ import annotations

from objsearch_agents.methods.base import Method


class A3C(Method):
    name = "a3c"

    def trains_actor_critic(self, config) -> bool:
        return True

    def acting_category(self, policy):
        return policy.target


METHOD = A3C()
