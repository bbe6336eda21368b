"""``gymnasium.make("ObjSearch/House-v1", max_steps=...)`` refuses a step limit that is not an
integer >= 1 with a ValueError naming ``max_steps``, not an error from inside the observation
space's ``Box``; so do ``HouseEnv`` itself and the batched env."""

import gymnasium
import pytest

import objsearch  # noqa: F401 - registers the envs
from objsearch.sim.env import HouseEnv


@pytest.mark.parametrize("value", [-5, 0, 2.5, True, "100", None])
def test_a_step_limit_that_is_not_an_integer_of_at_least_1_is_refused_naming_max_steps(value):
    with pytest.raises(ValueError, match=r"^max_steps=.*: the step limit of an episode is an integer >= 1"):
        gymnasium.make("ObjSearch/House-v1", max_steps=value)
    with pytest.raises(ValueError, match=r"^max_steps=.*: the step limit of an episode is an integer >= 1"):
        gymnasium.make_vec("ObjSearch/House-v1", num_envs=2, vectorization_mode="vector_entry_point", max_steps=value)
    with pytest.raises(ValueError, match=r"^max_steps=.*: the step limit of an episode is an integer >= 1"):
        HouseEnv(max_steps=value)  # the env itself, not only its registered id


def test_a_valid_step_limit_makes_the_house_env():
    env = gymnasium.make("ObjSearch/House-v1", max_steps=50.0)
    assert type(env.unwrapped) is HouseEnv and env.unwrapped.max_steps == 50
    assert gymnasium.make("ObjSearch/House-v1").unwrapped.max_steps == 1000
