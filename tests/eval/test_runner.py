import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.eval.config import EvalConfig
from objsearch.eval.episode import episode_rng
from objsearch.eval.runner import evaluate
from objsearch.gridworld import dataset
from objsearch.gridworld.maps import save_map
from objsearch.gridworld.tasks import save_tasks


def test_oracle_is_perfect_on_every_split():
    results = evaluate(EvalConfig(agent="oracle", seeds=(1, 5)), progress=False)
    assert list(results["splits"]) == ["seen-goals", "unseen-goals", "all-goals"]
    for split, s in results["splits"].items():
        assert s["sr"] == 1.0 and s["spl"] == 1.0, split
        assert s["as"] == s["ms"], split
        assert s["episodes"] == 200
    assert all(r["steps"] == r["min_steps"] for r in results["episodes"])


def test_random_is_the_papers_lower_bound():
    results = evaluate(EvalConfig(agent="random", seeds=(1, 5, 13)), progress=False)
    for split, s in results["splits"].items():
        # the paper: SR 0.15-0.18, SPL 0.03-0.05; 100 tasks leave about +-0.05 of noise
        assert 0.10 <= s["sr"] <= 0.30, (split, s["sr"])
        assert s["spl"] < 0.1, (split, s["spl"])


def test_workers_give_identical_results():
    config = EvalConfig(agent="random", splits=("unseen-goals",), seeds=(1, 5))
    one = evaluate(config, workers=1, progress=False)
    two = evaluate(config, workers=2, progress=False)
    assert one == two
    seeds_differ = {r["seed"]: r["steps"] for r in one["episodes"] if r["episode_id"] == 0}
    assert len(one["episodes"]) == 200 and len(seeds_differ) == 2


def test_results_carry_provenance():
    results = evaluate(EvalConfig(agent="oracle", splits=("all-goals",), seeds=(1,)), progress=False)
    for key in (
        "schema_version",
        "agent",
        "suite",
        "episode_set_version",
        "objsearch_version",
        "git_commit",
        "seeds",
        "config",
    ):
        assert key in results
    assert results["episode_set_version"] == dataset.DATA_VERSION
    assert results["config"]["splits"] == ["all-goals"]
    record = results["episodes"][0]
    assert {"split", "seed", "episode_id", "goal", "success", "steps", "min_steps", "spl", "task"} <= set(record)
    assert record["task"] == dataset.split_tasks("all-goals")[0].to_json()


def test_episode_rngs_are_independent_streams():
    a = episode_rng(1, "seen-goals", 0).integers(1 << 30, size=4)
    assert np.array_equal(a, episode_rng(1, "seen-goals", 0).integers(1 << 30, size=4))
    for other in (episode_rng(1, "seen-goals", 1), episode_rng(5, "seen-goals", 0), episode_rng(1, "all-goals", 0)):
        assert not np.array_equal(a, other.integers(1 << 30, size=4))


def test_custom_maps_and_tasks(tmp_path):
    maps = dataset.test_maps()
    save_map(maps["map_0100"], tmp_path / "maps")
    tasks = [t for t in dataset.split_tasks("all-goals") if t.map == "map_0100"][:3]
    save_tasks(tasks, tmp_path / "my-tasks.jsonl")
    config = EvalConfig(
        agent="oracle",
        seeds=(1,),
        suite_config={"maps": str(tmp_path / "maps"), "tasks": str(tmp_path / "my-tasks.jsonl")},
    )
    results = evaluate(config, progress=False)
    assert list(results["splits"]) == ["my-tasks"]
    assert results["splits"]["my-tasks"]["episodes"] == 3
    assert [r["min_steps"] for r in results["episodes"]] == [t.min_steps for t in tasks]


def test_unknown_split_is_a_user_error():
    with pytest.raises(UserError, match="unknown split 'unseen' .* did you mean 'unseen-goals'"):
        evaluate(EvalConfig(agent="oracle", splits=("unseen",)), progress=False)
