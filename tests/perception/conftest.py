import pytest
import torch

from objsearch.sim.camera import RenderSettings

LOW_RES = RenderSettings(width=32, height=32)


@pytest.fixture(autouse=True, scope="session")
def one_thread():
    before = torch.get_num_threads()
    torch.set_num_threads(1)  # the machine is shared; also makes timings comparable
    yield
    torch.set_num_threads(before)


@pytest.fixture(scope="session")
def tiny_dataset(tmp_path_factory):
    """48 frames at 32x32 of one small training house (train split only)."""
    from objsearch.perception.dataset import build_dataset

    out = tmp_path_factory.mktemp("perception-data")
    build_dataset(
        out, settings=LOW_RES, seed=0, poses_per_house=48, houses={"train": 1, "val": 0, "test": 0}, progress=False
    )
    return out
