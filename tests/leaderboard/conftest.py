import pytest

from objsearch.eval.runner import EvalConfig, evaluate


@pytest.fixture(scope="session")
def oracle_results():
    """A partial gridworld result (one split, two seeds): seconds to make."""
    return evaluate(EvalConfig(agent="oracle", splits=("unseen-goals",), seeds=(1, 5)), progress=False)


@pytest.fixture(scope="session")
def random_results():
    return evaluate(EvalConfig(agent="random", splits=("unseen-goals",), seeds=(1, 5)), progress=False)


@pytest.fixture(scope="session")
def full_oracle():
    """A full gridworld result: every split with the standard seeds (1500 episodes)."""
    return evaluate(EvalConfig(agent="oracle"), progress=False, batch=64)


@pytest.fixture(scope="session")
def full_random():
    return evaluate(EvalConfig(agent="random"), progress=False, batch=64)
