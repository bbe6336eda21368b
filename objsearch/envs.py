"""Registration of objsearch's Gymnasium environments (string entry points: nothing heavy
is imported until an environment is made)."""

import gymnasium

ENVS = {
    "ObjSearch/GridWorld-v0": "objsearch.gridworld.env:GridWorldEnv",
    "ObjSearch/House-v0": "objsearch.sim.env:HouseEnv",
}


def register_envs() -> None:
    """Register every objsearch environment id with Gymnasium; safe to call twice."""
    for env_id, entry_point in ENVS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point)
