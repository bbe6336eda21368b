"""``gymnasium.make("ObjSearch/Suite-v1", suite=..., split=...)`` plays the episodes that
``objsearch-eval`` plays, in its order: an agent stepping it ends with the harness's records."""

import warnings

import gymnasium
import pytest
from gymnasium.utils.env_checker import check_env

import objsearch  # noqa: F401  (registers the ids)
from objsearch.errors import UserError
from objsearch.eval.config import EvalConfig
from objsearch.eval.metrics import episode_spl
from objsearch.eval.runner import evaluate
from objsearch_agents.baselines.frontier import FrontierAgent
from objsearch_agents.baselines.oracle import OracleAgent
from objsearch_agents.baselines.random_agent import RandomAgent

KEYS = ("split", "seed", "episode_id", "success", "steps", "min_steps", "spl")


def play(env, agent) -> list[dict]:
    """One lap of the env's episodes, each as the harness records it."""
    records = []
    for _ in range(env.unwrapped.num_episodes):
        obs, start = env.reset()
        agent.reset(env.unwrapped.agent_task)
        steps, done = 0, False
        while not done:
            obs, _, terminated, truncated, info = env.step(agent.act(obs))
            steps, done = steps + 1, terminated or truncated
        success = bool(info["success"])
        records.append(
            {
                **{key: start[key] for key in ("split", "seed", "episode_id", "min_steps")},
                "success": success,
                "steps": steps,
                "spl": episode_spl(success, start["min_steps"], steps),
            }
        )
    return records


def harness(agent: str, suite: str, splits, seeds, episodes: int, **suite_config) -> list[dict]:
    config = EvalConfig(
        agent=agent, suite=suite, splits=tuple(splits), seeds=seeds, episodes=episodes, suite_config=suite_config
    )
    records = evaluate(config, progress=False)["episodes"]
    return [{**r, "spl": episode_spl(r["success"], r["min_steps"], r["steps"])} for r in records]


@pytest.mark.parametrize(
    "agent, name, episodes, max_steps",
    # random: its steps depend on task.rng (seed 1 and 5 differ), 3 of its 16 episodes succeed;
    # frontier: successes of every length; oracle: the privileged path
    [(RandomAgent, "random", 4, None), (FrontierAgent, "frontier", 2, 150), (OracleAgent, "oracle", 2, 150)],
)
def test_a_shipped_house_suite_plays_the_records_of_objsearch_eval(cache_dir, agent, name, episodes, max_steps):
    options = {"mode": "cached", "cache_dir": cache_dir, **({"max_steps": max_steps} if max_steps else {})}
    env = gymnasium.make("ObjSearch/Suite-v1", suite="house-single", seeds=[1, 5], episodes=episodes, **options)
    assert env.unwrapped.num_episodes == 2 * 2 * episodes  # splits x seeds x episodes
    ours = play(env, agent())
    theirs = harness(name, "house-single", ("seen-goals", "unseen-goals"), (1, 5), episodes, **options)
    assert [{k: r[k] for k in KEYS} for r in theirs] == ours
    assert any(r["success"] for r in ours)
    if name == "oracle":
        assert all(r["success"] and r["spl"] == 1.0 for r in ours)
    env.close()


def test_the_grid_world_too_and_every_standard_episode_in_order():
    env = gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", split=["unseen-goals"], seeds=[13], episodes=5)
    assert play(env, RandomAgent()) == [
        {k: r[k] for k in KEYS} for r in harness("random", "gridworld", ["unseen-goals"], (13,), 5)
    ]
    # no split, no seeds: the suite's every split, standard seeds and episode, as objsearch-eval plays them
    full = gymnasium.make("ObjSearch/Suite-v1", suite="house-single").unwrapped
    assert full.seeds == (1, 5, 13, 45, 99) and full.num_episodes == 2 * 5 * 100
    assert full.units[:2] == [("seen-goals", 1, 0), ("seen-goals", 1, 1)] and full.units[-1] == ("unseen-goals", 99, 99)


def test_every_shipped_suite_has_its_own_id_that_is_suite_v1_with_its_name():
    from objsearch.eval.suites import SUITES
    from objsearch.sim.suites import SUITE_NAMES

    assert {"gridworld", *SUITE_NAMES} <= set(SUITES)
    for name in ("gridworld", *SUITE_NAMES):
        assert gymnasium.spec(f"ObjSearch/{name}-v1").kwargs == {"suite": name}
    own = gymnasium.make("ObjSearch/gridworld-v1", split="seen-goals", seeds=[5], episodes=3)
    same = gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", split="seen-goals", seeds=[5], episodes=3)
    assert play(own, RandomAgent()) == play(same, RandomAgent())


def test_reset_with_a_seed_starts_over_and_the_env_passes_check_env():
    env = gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", split="seen-goals", seeds=[1, 5], episodes=2)
    order = [env.reset()[1] for _ in range(5)]
    assert [(i["seed"], i["episode_id"], i["index"]) for i in order] == [(1, 0, 0), (1, 1, 1), (5, 0, 2), (5, 1, 3)] + [
        (1, 0, 0)  # after the last, the first again
    ]
    env.reset()
    assert env.reset(seed=7)[1]["index"] == 0  # a seed chooses no episode: it starts the sequence over
    assert order[0]["suite"] == "gridworld" and order[0]["goal"] == f"g{env.unwrapped.agent_task.goal}"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)


def test_bad_arguments_are_refused_with_the_fix():
    with pytest.raises(UserError, match="needs the suite"):
        gymnasium.make("ObjSearch/Suite-v1")
    with pytest.raises(UserError, match="unknown split 'seen'"):
        gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", split="seen")
    with pytest.raises(UserError, match="unknown suite"):
        gymnasium.make("ObjSearch/Suite-v1", suite="house-singel")
    with pytest.raises(UserError, match="takes no option 'mode'"):
        gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", mode="live")
    with pytest.raises(UserError, match="seeds"):
        gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", seeds=[1.5])
    with pytest.raises(UserError, match="episodes=0"):
        gymnasium.make("ObjSearch/Suite-v1", suite="gridworld", episodes=0)


def test_the_readmes_gymnasium_snippet_runs_as_written_in_a_fresh_interpreter():
    import re
    import subprocess
    import sys
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    (snippet,) = [b for b in re.findall(r"```python\n(.*?)```", readme, re.S) if "ObjSearch/Suite-v1" in b]
    assert "import objsearch" not in snippet  # as a user pastes it: no import that registers the ids by hand
    proc = subprocess.run([sys.executable, "-c", snippet], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
