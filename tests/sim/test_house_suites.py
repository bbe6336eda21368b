"""The house suites through the harness: fixed files, oracle perfect, random far below."""

from dataclasses import replace

import numpy as np
import pytest

from objsearch.eval.runner import EvalConfig, evaluate
from objsearch.eval.suites import make_suite
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.cache import HouseCache
from objsearch.sim.camera import AGENT_CAMERA, CameraMismatchError
from objsearch.sim.env import START_STEPS
from objsearch.sim.goals import GOAL_CAMERA, goal_poses
from objsearch.sim.suites import load_suite_file


@pytest.mark.parametrize("name", ["house-single", "house-multi", "house-single-v2", "house-multi-v2"])
def test_suite_files_are_consistent(name):
    data = load_suite_file(name)
    suite = make_suite(name, mode="live")
    assert len(suite.worlds) == len(data["houses"])  # regenerated, spec hashes checked
    for split in suite.splits:
        episodes = suite.episodes(split)
        assert len(episodes) == 100
        for ep in episodes[:20]:
            graph = suite.worlds[ep.task.house].graph
            dist = graph.shortest_steps([graph.pose_id(*g) for g in ep.task.goals])
            assert dist[graph.pose_id(*ep.task.start)] == ep.min_steps
            assert START_STEPS[0] <= ep.min_steps <= START_STEPS[1]
    generator = "house-gen-2" if name.endswith("-v2") else "house-gen-1"
    assert all(w.spec.generator_version == generator for w in suite.worlds.values())
    if name.startswith("house-single"):
        assert len(data["houses"]) == 1
        assert len(data["categories"]["seen"]) == len(data["categories"]["unseen"]) == 6
        assert not set(data["categories"]["seen"]) & set(data["categories"]["unseen"])
    else:
        assert len(data["houses"]) == 8 and len(data["categories"]["targets"]) == 6
        seen = {e.task.house for e in suite.episodes("seen-envs")}
        unseen = {e.task.house for e in suite.episodes("unseen-envs")}
        assert len(seen) == len(unseen) == 4 and not seen & unseen


@pytest.mark.parametrize("name", ["house-single", "house-multi", "house-gen-v2", "house-single-v2", "house-multi-v2"])
def test_oracle_is_perfect_on_every_split(name):
    results = evaluate(
        EvalConfig(agent="oracle", suite=name, seeds=(1,), suite_config={"mode": "live"}), progress=False
    )
    for split, s in results["splits"].items():
        assert s["sr"] == 1.0 and s["spl"] == 1.0 and s["as"] == s["ms"], split


def test_random_is_far_below(cache_dir):
    config = EvalConfig(
        agent="random", suite="house-single", seeds=(1,), suite_config={"mode": "cached", "cache_dir": cache_dir}
    )
    results = evaluate(config, progress=False)
    for split, s in results["splits"].items():
        assert s["sr"] < 0.6 and s["spl"] < 0.15, (split, s["sr"], s["spl"])


def test_goal_rule_golden_values(cache_dir):
    """The stored goal poses of house-single are what the goal rule gives today."""
    suite = make_suite("house-single", mode="cached", cache_dir=cache_dir)
    (world,) = suite.worlds.values()
    cache = HouseCache.open(world, GOAL_CAMERA, cache_dir, progress=False)
    stored = suite.data["goals"][world.house_id]
    for target in sorted(stored)[:8]:
        ids = goal_poses(cache.semantic, cache.depth, CATEGORY_IDS[target])
        assert [list(world.graph.pose_of(int(i))) for i in ids] == stored[target], target


def test_video_writes_map_and_mp4(tmp_path):
    config = EvalConfig(
        agent="oracle", suite="house-single", splits=("seen-goals",), seeds=(1,), suite_config={"mode": "live"}
    )
    from objsearch.eval.plan import resolve
    from objsearch.eval.worker import Worker

    worker = Worker(resolve(config, video_dir=str(tmp_path)))
    record = worker.run("seen-goals", 1, 0)
    png = tmp_path / "seen-goals_seed1_ep0000.png"
    mp4 = tmp_path / "seen-goals_seed1_ep0000.mp4"
    assert record["success"] and png.stat().st_size > 1000 and mp4.stat().st_size > 1000
    import cv2

    video = cv2.VideoCapture(str(mp4))
    frames = int(video.get(cv2.CAP_PROP_FRAME_COUNT))
    assert frames == record["steps"] + 1
    image = cv2.imread(str(png))
    assert image is not None and image.shape[2] == 3


def test_house_single_file_is_reproduced_by_its_builder(cache_dir):
    """The shipped file is the benchmark; if this fails the builder, generator or goal rule
    changed: bump the suite version and rebuild it deliberately."""
    from objsearch.sim.suite_build import build_suite

    assert build_suite("house-single", cache_dir) == load_suite_file("house-single")


def test_predicted_observations_through_the_harness(cache_dir, tmp_path):
    """--observation predicted: the agent sees the network's output, success stays ground truth,
    and the results record which network it was."""
    import torch

    from objsearch.errors import UserError
    from objsearch.perception.inference import Predictor, save_checkpoint
    from objsearch.perception.model import ModelConfig, SegDepthNet
    from objsearch.perception.train import init_weights
    from objsearch.sim.cache import PredictedCache

    model = SegDepthNet(ModelConfig(stem=8, mid=8, deep=8, aspp=8, aspp_rates=(2,), skip=8, decoder=8))
    init_weights(model, torch.Generator().manual_seed(0))
    path = tmp_path / "model.pt"
    save_checkpoint(path, model, AGENT_CAMERA)
    key = Predictor.from_checkpoint(path).key
    suite_config = {"mode": "cached", "cache_dir": cache_dir, "observation": "predicted", "perception": str(path)}
    config = EvalConfig(
        agent="random", suite="house-single", splits=("seen-goals",), seeds=(1,), suite_config=suite_config
    )
    results = evaluate(config, progress=False)
    assert results["config"]["suite_config"]["perception_key"] == key
    gt = evaluate(
        EvalConfig(
            agent="random",
            suite="house-single",
            splits=("seen-goals",),
            seeds=(1,),
            suite_config={"mode": "cached", "cache_dir": cache_dir},
        ),
        progress=False,
    )
    # the random agent ignores what it sees, so the same episodes succeed: success is judged on the ground truth
    assert [e["success"] for e in results["episodes"]] == [e["success"] for e in gt["episodes"]]

    suite = make_suite(
        "house-single", **results["config"]["suite_config"]
    )  # what a resumed run or a validator rebuilds
    env = suite.make_env()
    episode = suite.episodes("seen-goals")[0]
    obs, info = env.reset(options={"task": episode.task})
    world = suite.worlds[episode.task.house]
    predicted = PredictedCache.open(world, AGENT_CAMERA, suite.predictor, cache_dir, progress=False)
    pose = world.graph.pose_id(*info["pose"])
    assert np.array_equal(obs["semantic"], predicted.semantic[pose]) and np.array_equal(
        obs["depth"], predicted.depth[pose]
    )
    with pytest.raises(UserError, match="has key"):
        make_suite("house-single", **{**results["config"]["suite_config"], "perception_key": "0" * 16})
    with pytest.raises(UserError, match="predicted observations only"):
        make_suite("house-single", perception=str(path))
    small = tmp_path / "small.pt"
    save_checkpoint(small, model, replace(AGENT_CAMERA, width=32, height=32))
    with pytest.raises(
        CameraMismatchError, match=r"small.pt was made for camera \[width=32 .* the agent camera .* is \[width=64 "
    ):
        make_suite("house-single", observation="predicted", perception=str(small))

    from objsearch.cli import main

    assert (
        main(
            [
                "cache",
                "build",
                "--suite",
                "house-single",
                "--cache-dir",
                cache_dir,
                "--observation",
                "predicted",
                "--perception",
                str(path),
            ]
        )
        == 0
    )
    assert main(["cache", "build", "--suite", "house-single", "--perception", str(path)]) == 2
