"""The ObjectNav protocol beside the paper's: ``objsearch suite make --protocol objectnav``
writes it, the env needs STOP at a goal pose, the oracle stops there, the frontier agent
stops on sight of the target within 1 m, random may stop anywhere, learned agents (no STOP
action) are refused, and results record the protocol."""

import json
import shutil

import numpy as np
import pytest
from own_houses import assert_clean_error, run

from objsearch.cli import eval_main


@pytest.fixture(scope="module")
def objectnav(made, cache_dir, tmp_path_factory):
    """``on.json``: the houses of ``made`` as an ObjectNav suite (20 episodes, seed 1)."""
    work = tmp_path_factory.mktemp("objectnav")
    shutil.copytree(made / "houses", work / "houses")
    out = run(
        "objsearch", "suite", "make", "--houses", "houses", "--out", "on.json", "--episodes", "20", "--seed", "1",
        "--protocol", "objectnav", "--cache-dir", cache_dir, cwd=work,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "protocol objectnav" in out.stderr
    return work


def test_suite_make_writes_the_protocol_its_rule_and_step_limit(objectnav, made, cache_dir):
    from objsearch.house.categories import CATEGORY_IDS
    from objsearch.sim.cache import HouseCache
    from objsearch.sim.goals import GOAL_CAMERA, GoalRule, goal_poses
    from objsearch.sim.suites import load_houses, load_suite_file

    raw = json.loads((objectnav / "on.json").read_text())
    assert raw["protocol"] == "objectnav" and raw["max_steps"] == 500
    rule = {k: v for k, v in raw["goal_rule"].items() if k != "version"}
    assert rule == {"kind": "near_visible", "top_k": 5, "min_pixels": 20, "max_distance": 1.0}
    assert "protocol" not in json.loads((made / "my-suite.json").read_text())  # the paper's: files keep their bytes
    worlds = load_houses(load_suite_file(str(objectnav / "on.json")))
    for house, table in raw["goals"].items():
        cache = HouseCache.open(worlds[house], GOAL_CAMERA, cache_dir, progress=False)
        for target, poses in table.items():  # every pose seeing 20 target pixels within 1 m
            ids = goal_poses(cache.semantic, cache.depth, CATEGORY_IDS[target], GoalRule(**rule))
            assert [list(worlds[house].graph.pose_of(int(i))) for i in ids] == poses
    for item in raw["splits"]["on"]:  # the minimal actions to succeed: the moves, then STOP
        graph = worlds[item["house"]].graph
        dist = graph.shortest_steps([graph.pose_id(*g) for g in raw["goals"][item["house"]][item["target"]]])
        assert item["min_steps"] == dist[graph.pose_id(*item["start"])] + 1


def test_oracle_stops_at_the_goal_and_frontier_stops_on_sight_far_above_random(objectnav, cache_dir, capsys):
    results = {}
    for agent in ("oracle", "frontier", "random"):
        out = objectnav / f"{agent}.json"
        args = ["--agent", agent, "--suite", str(objectnav / "on.json"), "--seeds", "1", "--cache-dir", cache_dir]
        assert eval_main([*args, "--quiet", "--out", str(out)]) == 0
        results[agent] = json.loads(out.read_text())
        assert results[agent]["protocol"] == "objectnav"
    assert "protocol objectnav" in capsys.readouterr().out  # the table's footer says it
    oracle, frontier, random = (results[a]["splits"]["on"] for a in ("oracle", "frontier", "random"))
    assert oracle["sr"] == 1.0 and oracle["spl"] == 1.0
    assert frontier["sr"] >= 0.8 and random["sr"] <= 0.2, (frontier["sr"], random["sr"])
    # random samples STOP among its 7 actions: its episodes end early, and never by the step limit
    assert max(r["steps"] for r in results["random"]["episodes"]) < 100


def test_frontier_calls_stop_when_the_frame_passes_the_rule_and_only_where_stop_exists(objectnav, cache_dir):
    """At an ObjectNav goal pose the frame shows 20 target pixels within 1 m: the frontier
    agent calls STOP there, which succeeds; in an env without STOP (the paper's protocol) it
    never returns 6, which that env refuses."""
    from dataclasses import replace

    from objsearch.eval.episode import agent_task
    from objsearch.eval.suites.house import HouseSuite
    from objsearch.sim.env import HouseEnv
    from objsearch.sim.goals import GoalRule
    from objsearch_agents.baselines.frontier import FrontierAgent

    suite = HouseSuite(str(objectnav / "on.json"), cache_dir=cache_dir)
    episode = suite.episodes("on")[0]
    for stop in (True, False):
        # the episode started at one of its goal poses: min_steps is the STOP alone, or nothing
        task = replace(episode.task, start=episode.task.goals[0], min_steps=int(stop))
        env = HouseEnv(list(suite.worlds.values()), cache_dir=cache_dir, stop_action=stop,
                       goal_rule=GoalRule(kind="near_visible"))  # fmt: skip
        obs, info = env.reset(options={"task": task})
        assert ((obs["semantic"] == obs["target"]) & (obs["depth"] <= 1.0)).sum() >= 20
        at_goal = replace(episode, task=task, min_steps=task.min_steps)
        agent_view = agent_task(suite.name, "on", at_goal, 1, info, env.observation_space, env.action_space)
        assert agent_view.stop_action == (6 if stop else None) and agent_view.goal_rule["kind"] == "near_visible"
        agent = FrontierAgent()
        agent.reset(agent_view)
        action = agent.act(obs)
        if stop:
            assert action == 6
            _, reward, terminated, _, info = env.step(action)
            assert terminated and info["success"] and reward == 1.0
        else:
            assert action != 6 and env.action_space.contains(action)


def test_learned_agents_are_refused_on_an_objectnav_suite(objectnav, capsys):
    for agent, suite, hint in (
        ("a3c", str(objectnav / "on.json"), "--protocol paper"),
        ("hrl_grg", "house-gen-v2-objectnav", "house-gen-v2 has the same episodes"),
    ):
        assert eval_main(["--agent", agent, "--suite", suite, "--seeds", "1", "--quiet"]) == 2
        (line,) = capsys.readouterr().err.strip().splitlines()
        for needle in (f"agent {agent!r}", "no STOP action", "paper protocol", hint):
            assert needle in line, (needle, line)


def test_an_unknown_protocol_is_refused_naming_the_file_the_field_and_the_choices(objectnav, tmp_path):
    shutil.copytree(objectnav / "houses", tmp_path / "houses")
    raw = json.loads((objectnav / "on.json").read_text())
    (tmp_path / "bad.json").write_text(json.dumps({**raw, "protocol": "habitat"}))
    out = run("objsearch-eval", "--agent", "oracle", "--suite", "bad.json", "--seeds", "1", "--quiet", cwd=tmp_path)
    assert_clean_error(out, "suite file bad.json", "protocol", "'habitat'", "paper", "objectnav")


def test_results_record_the_paper_protocol_of_the_other_suites(made, cache_dir, tmp_path):
    out = tmp_path / "r.json"
    args = ["--agent", "oracle", "--suite", str(made / "my-suite.json"), "--seeds", "1", "--cache-dir", cache_dir]
    assert eval_main([*args, "--quiet", "--out", str(out)]) == 0
    assert json.loads(out.read_text())["protocol"] == "paper"


def test_the_shipped_objectnav_suite_is_house_gen_v2_under_the_objectnav_rules():
    """The same houses, targets, splits and starts as house-gen-v2; every episode whose start
    reaches a goal pose under the ObjectNav rule, in order, its min_steps counting the STOP."""
    from objsearch.sim.suites import load_houses, load_suite_file

    paper, on = load_suite_file("house-gen-v2"), load_suite_file("house-gen-v2-objectnav")
    assert (on["protocol"], on["max_steps"], on["goal_rule"]["kind"]) == ("objectnav", 500, "near_visible")
    for key in ("houses", "training_houses", "categories", "start_steps", "navgraph", "goal_camera"):
        assert on[key] == paper[key], key
    assert list(on["splits"]) == list(paper["splits"])
    worlds = load_houses(on)
    kept = 0
    for split, items in paper["splits"].items():
        ours = iter(on["splits"][split])
        mine = next(ours)
        for item in items:
            graph = worlds[item["house"]].graph
            goals = [graph.pose_id(*g) for g in on["goals"][item["house"]][item["target"]]]
            moves = graph.shortest_steps(goals)[graph.pose_id(*item["start"])]
            if moves < 0:  # no goal pose within 1 m of the target is reachable from this start
                continue
            assert mine == {**item, "min_steps": int(moves) + 1}
            kept += 1
            mine = next(ours, None)
        assert mine is None
    assert kept == sum(len(v) for v in on["splits"].values()) >= 0.99 * sum(len(v) for v in paper["splits"].values())
    assert np.mean([e["min_steps"] for v in on["splits"].values() for e in v]) > 10
