import os

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")
# The test networks are tiny: one thread each is faster than two that fight over the
# machine's cores (and keeps timings steady when something else runs beside the tests).
os.environ.setdefault("OMP_NUM_THREADS", "1")


@pytest.fixture(scope="session")
def cache_dir(tmp_path_factory):
    """One observation cache for the whole test session (building one takes seconds)."""
    return str(tmp_path_factory.mktemp("objsearch-cache"))
