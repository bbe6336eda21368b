import pytest

from objsearch.sim.world import HouseRef, World

SMALL_HOUSE = HouseRef(seed=3)  # a small house: ~1700 poses


@pytest.fixture(scope="session")
def small_house() -> HouseRef:
    return SMALL_HOUSE


@pytest.fixture(scope="session")
def small_world():
    return World.load(SMALL_HOUSE)


@pytest.fixture(scope="session")
def cache_dir(tmp_path_factory):
    """One observation cache for the whole test session (building one takes seconds)."""
    return str(tmp_path_factory.mktemp("objsearch-cache"))
