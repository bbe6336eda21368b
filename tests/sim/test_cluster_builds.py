"""Observation caches and perception datasets built on a Ray cluster are the local build, byte for byte."""

from pathlib import Path

import pytest
import ray
import torch

from objsearch.cli import main
from objsearch.cluster import map_houses
from objsearch.errors import UserError
from objsearch.perception.cache_cli import build_caches
from objsearch.perception.dataset import build_dataset
from objsearch.perception.inference import save_checkpoint
from objsearch.perception.model import ModelConfig, SegDepthNet
from objsearch.perception.train import init_weights
from objsearch.sim.camera import RenderSettings

CAMERA = RenderSettings(width=32, height=32)  # low resolution: fast
TINY_MODEL = ModelConfig(stem=16, mid=32, deep=48, aspp=32, aspp_rates=(2, 4), skip=16, decoder=32)


@pytest.fixture(scope="module")
def local_ray():
    """A local Ray cluster of 2 CPUs, shared by the tests here (the builds use it as it is)."""
    ray.init(num_cpus=2, include_dashboard=False, logging_level="ERROR", log_to_driver=False)
    yield
    ray.shutdown()


def file_bytes(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def test_cache_build_on_ray_is_the_local_build(local_ray, small_house, small_world, tmp_path):
    model = SegDepthNet(TINY_MODEL)
    init_weights(model, torch.Generator().manual_seed(0))
    save_checkpoint(tmp_path / "model.pt", model, CAMERA)
    houses = {small_world.house_id: small_house.to_json()}
    builds = {
        executor: build_caches(
            houses, tmp_path / executor, CAMERA, tmp_path / "model.pt", executor=executor, progress=False
        )
        for executor in ("local", "ray")
    }
    assert [line.replace("/ray/", "/local/") for line in builds["ray"]] == builds["local"]
    local, distributed = file_bytes(tmp_path / "local"), file_bytes(tmp_path / "ray")
    assert len(local) == 2 + 2  # frames and meta of the observations; of the predictions
    assert list(distributed) == list(local)
    for name in local:
        assert distributed[name] == local[name], name


def test_perception_dataset_on_ray_is_the_local_build(local_ray, tmp_path):
    kwargs = dict(
        settings=CAMERA,
        seed=0,
        poses_per_house=3,
        eval_poses_per_house=2,
        houses={"train": 2, "val": 1, "test": 0},
        progress=False,
    )
    manifests = {
        executor: build_dataset(tmp_path / executor, executor=executor, **kwargs) for executor in ("local", "ray")
    }
    assert manifests["ray"] == manifests["local"]
    assert [len(s["houses"]) for s in manifests["local"]["splits"].values()] == [2, 1]
    local, distributed = file_bytes(tmp_path / "local"), file_bytes(tmp_path / "ray")
    assert len(local) == 1 + 3  # the manifest and a shard a house
    assert list(distributed) == list(local)
    for name in local:
        assert distributed[name] == local[name], name

    shard = next((tmp_path / "ray" / "train").glob("*.npz"))
    shard.write_bytes(b"not a zip file")
    with pytest.raises(UserError, match=f"cannot read dataset shard {shard}"):  # a task's UserError comes back as it is
        build_dataset(tmp_path / "ray", executor="ray", **kwargs)


def test_map_houses_keeps_the_order_of_its_houses():
    items = [-3, 1, -2, 5]
    assert map_houses(abs, items, progress=False) == map_houses(abs, items, workers=2, progress=False) == [3, 1, 2, 5]
    with pytest.raises(ValueError, match="needs executor='ray'"):
        map_houses(abs, items, address="auto", progress=False)


@pytest.mark.parametrize(
    "command", [["cache", "build", "--suite", "house-single"], ["perception", "dataset", "--out", "data"]]
)
def test_cluster_flags_without_a_cluster_are_refused(command, capsys):
    assert main([*command, "--address", "10.0.0.1:6379"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--address 10.0.0.1:6379 needs --executor ray" in err
    assert main([*command, "--executor", "ray", "--address", "auto", "--workers", "4"]) == 2
    assert "drop --workers" in capsys.readouterr().err


def test_cache_build_command_on_ray(local_ray, tmp_path, capsys):
    assert main(["cache", "build", "--suite", "house-single", "--cache-dir", str(tmp_path), "--executor", "ray"]) == 0
    (line,) = capsys.readouterr().out.splitlines()
    assert line.startswith("train_000007: ") and line.endswith(f" poses in {next(tmp_path.iterdir())}")
