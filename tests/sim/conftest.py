import pytest

from objsearch.sim.world import HouseRef, World

SMALL_HOUSE = HouseRef(seed=3)  # a small house: ~1700 poses


@pytest.fixture(scope="session")
def small_house() -> HouseRef:
    return SMALL_HOUSE


@pytest.fixture(scope="session")
def small_world():
    return World.load(SMALL_HOUSE)
