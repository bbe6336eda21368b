"""Registration of objsearch's Gymnasium environments (string entry points: nothing heavy
is imported until an environment is made)."""

import gymnasium

ENVS = {
    "ObjSearch/GridWorld-v0": {"entry_point": "objsearch.gridworld.env:GridWorldEnv"},
    "ObjSearch/House-v0": {
        "entry_point": "objsearch.sim.env:HouseEnv",
        # gymnasium.make_vec(..., vectorization_mode="vector_entry_point"): the batched cached env
        "vector_entry_point": "objsearch.sim.vector:HouseVectorEnv",
    },
}


def register_envs() -> None:
    """Register every objsearch environment id with Gymnasium; safe to call twice."""
    for env_id, entry_points in ENVS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, **entry_points)
