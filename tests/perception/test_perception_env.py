"""The house env's predicted observation mode gives the network's output."""

import numpy as np
import pytest
import torch

from objsearch.perception.inference import Predictor, save_checkpoint
from objsearch.perception.model import ModelConfig, SegDepthNet
from objsearch.perception.train import init_weights
from objsearch.sim.cache import HouseCache, PredictedCache, quantize_depth
from objsearch.sim.camera import CameraMismatchError, RenderSettings
from objsearch.sim.env import HouseEnv, HouseTask
from objsearch.sim.world import HouseRef, World

TINY_MODEL = ModelConfig(stem=16, mid=32, deep=48, aspp=32, aspp_rates=(2, 4), skip=16, decoder=32)  # trains in seconds
HOUSE = HouseRef(seed=3)  # the small house of tests/sim
CAMERA = RenderSettings(width=32, height=32)  # the network's and the env's camera (low resolution: fast)


@pytest.fixture(scope="module")
def predictor(tmp_path_factory):
    model = SegDepthNet(TINY_MODEL)
    init_weights(model, torch.Generator().manual_seed(0))
    path = tmp_path_factory.mktemp("ckpt") / "model.pt"
    save_checkpoint(path, model, CAMERA)
    return Predictor.from_checkpoint(path, device="cpu")


@pytest.fixture(scope="module")
def cache_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("cache"))


def _task(world: World) -> HouseTask:
    """A task given explicitly (so the goal camera's cache is not needed)."""
    graph = world.graph
    goal = graph.num_poses // 2
    dist = graph.shortest_steps([goal])
    start = int(np.flatnonzero(dist == 5)[0])
    return HouseTask(
        house=world.house_id, start=graph.pose_of(start), target="sofa", goals=(graph.pose_of(goal),), min_steps=5
    )


def test_predicted_observations_are_the_networks_output(predictor, cache_dir):
    env = HouseEnv(
        [HOUSE], mode="cached", settings=CAMERA, cache_dir=cache_dir, observation="predicted", predictor=predictor
    )
    world = env.world(World.load(HOUSE).house_id)
    task = _task(world)
    obs, _ = env.reset(options={"task": task})
    for action in (0, 1, 0):
        obs, *_ = env.step(action)
    assert env.observation_space.contains(obs)
    assert obs["semantic"].shape == (32, 32) and obs["depth"].dtype == np.float32
    pose_id = world.graph.pose_id(*env.pose)
    gt = HouseCache.open(world, CAMERA, cache_dir)
    assert np.array_equal(obs["rgb"], gt.rgb[pose_id])
    semantic, depth = predictor.predict(gt.rgb)  # every pose, batched as the cache was filled: bit for bit
    assert np.array_equal(obs["semantic"], semantic[pose_id])
    assert np.array_equal(obs["depth"], quantize_depth(depth[pose_id]))
    semantic, depth = predictor.predict(gt.rgb[pose_id][None])  # the pose alone: up to float rounding
    assert np.mean(obs["semantic"] == semantic[0]) > 0.99
    assert np.abs(obs["depth"] - quantize_depth(depth[0])).max() <= 0.0011
    assert not np.array_equal(obs["semantic"], gt.semantic[pose_id])  # an untrained network is not the ground truth
    cache = PredictedCache.open(world, CAMERA, predictor, cache_dir)  # reopened, not rebuilt
    assert cache.directory.name.endswith(predictor.key) and np.array_equal(cache.semantic[pose_id], obs["semantic"])
    live = HouseEnv([HOUSE], mode="live", settings=CAMERA, observation="predicted", predictor=predictor)
    live_obs, _ = live.reset(options={"task": task})
    first, _ = env.reset(options={"task": task})
    # live mode predicts the same (up to float rounding of a differently laid-out input: 1 mm, rare label flips)
    assert np.array_equal(live_obs["rgb"], first["rgb"])
    assert np.mean(live_obs["semantic"] == first["semantic"]) > 0.99
    assert np.abs(live_obs["depth"] - first["depth"]).max() <= 0.0011
    live.close()
    env.close()


def test_gt_stays_the_default_and_bad_arguments_are_refused(predictor):
    assert HouseEnv([HOUSE]).observation == "gt"
    with pytest.raises(ValueError, match="needs a predictor"):
        HouseEnv([HOUSE], observation="predicted")
    with pytest.raises(ValueError, match="observation must be one of"):
        HouseEnv([HOUSE], observation="learned", predictor=predictor)
    # the default camera is 64x64, the network's 32x32: one error, naming the checkpoint, both cameras and the fix
    with pytest.raises(
        CameraMismatchError,
        match=r"model.pt was made for camera \[width=32 .*\[width=64 .*they differ in width, height",
    ):
        HouseEnv([HOUSE], observation="predicted", predictor=predictor)


def test_vector_env_reads_the_predicted_cache(predictor, cache_dir):
    from objsearch.sim.vector import HouseVectorEnv

    envs = HouseVectorEnv(
        3, houses=[HOUSE], settings=CAMERA, cache_dir=cache_dir, observation="predicted", predictor=predictor
    )
    world = envs.env.world(World.load(HOUSE).house_id)
    predicted = PredictedCache.open(world, CAMERA, predictor, cache_dir)
    gt = HouseCache.open(world, CAMERA, cache_dir)
    obs, _ = envs.reset(seed=0)
    for _ in range(3):
        assert np.array_equal(obs["semantic"], predicted.semantic[envs.pose])
        assert np.array_equal(obs["depth"], predicted.depth[envs.pose]) and np.array_equal(
            obs["rgb"], gt.rgb[envs.pose]
        )
        obs, *_ = envs.step(np.array([0, 1, 2]))
    envs.close()
