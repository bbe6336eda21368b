"""Your own houses -> ``objsearch suite make`` -> ``objsearch-eval --suite FILE``, end to end
on two small generated houses, and the one-line errors for bad houses."""

import json
import shutil
from pathlib import Path

import pytest
from own_houses import assert_clean_error, run


def test_the_suite_file_is_made_as_the_shipped_ones_and_is_deterministic(made, cache_dir):
    from objsearch.house.categories import CATEGORY_IDS
    from objsearch.sim.cache import HouseCache
    from objsearch.sim.env import START_STEPS
    from objsearch.sim.goals import GOAL_CAMERA, goal_poses
    from objsearch.sim.suite_build import TARGETS
    from objsearch.sim.suites import load_houses, load_suite_file

    path = made / "my-suite.json"
    raw = json.loads(path.read_text())
    shipped = load_suite_file("house-single")
    assert list(raw) == list(shipped)  # the same fields, in the same order
    for key in ("navgraph", "goal_rule", "goal_camera", "start_steps", "max_steps"):
        assert raw[key] == shipped[key], key
    assert raw["version"].startswith("custom:") and raw["training_houses"] == {}
    assert raw["houses"] == {
        hid: {"path": f"houses/{hid}", "spec_sha256": raw["houses"][hid]["spec_sha256"]}
        for hid in ("train_000003", "train_000004")
    }
    targets = raw["categories"]["targets"]
    assert targets and set(targets) <= set(TARGETS) and targets == sorted(targets)
    (split,) = raw["splits"]
    assert split == "my-suite" and len(raw["splits"][split]) == 20

    worlds = load_houses(load_suite_file(str(path)))  # house paths resolved against the file's folder
    for hid, world in worlds.items():
        assert world.spec_sha256 == raw["houses"][hid]["spec_sha256"]
        cache = HouseCache.open(world, GOAL_CAMERA, cache_dir, progress=False)
        for target, poses in raw["goals"][hid].items():  # the goal rule's poses, as for the shipped suites
            ids = goal_poses(cache.semantic, cache.depth, CATEGORY_IDS[target])
            assert [list(world.graph.pose_of(int(i))) for i in ids] == poses, (hid, target)
    for item in raw["splits"][split]:
        graph = worlds[item["house"]].graph
        dist = graph.shortest_steps([graph.pose_id(*g) for g in raw["goals"][item["house"]][item["target"]]])
        assert dist[graph.pose_id(*item["start"])] == item["min_steps"]
        assert START_STEPS[0] <= item["min_steps"] <= START_STEPS[1]

    before = path.read_bytes()
    args = ["--houses", "houses", "--episodes", "20", "--cache-dir", cache_dir]
    assert run("objsearch", "suite", "make", *args, "--seed", "1", "--out", "my-suite.json", cwd=made).returncode == 0
    assert path.read_bytes() == before  # the same houses, seed and paths: the same bytes
    other = run(
        "objsearch", "suite", "make", *args, "--seed", "2", "--targets", "bed,sofa", "--out", "other.json", cwd=made
    )
    assert other.returncode == 0, other.stderr
    other = json.loads((made / "other.json").read_text())
    assert other["categories"] == {"targets": ["bed", "sofa"]} and {t for g in other["goals"].values() for t in g} <= {
        "bed",
        "sofa",
    }
    assert other["version"] != raw["version"]


def test_oracle_is_perfect_on_the_made_suite_and_random_is_not(made, cache_dir, tmp_path):
    out = run(
        "objsearch-eval",
        "--agent",
        "oracle",
        "--suite",
        "my-suite.json",
        "--seeds",
        "1",
        "--cache-dir",
        cache_dir,
        "--out",
        str(tmp_path / "r.json"),
        "--quiet",
        cwd=made,
    )
    assert out.returncode == 0, out.stderr
    results = json.loads((tmp_path / "r.json").read_text())
    assert results["suite"] == "my-suite.json" and results["episode_set_version"].startswith("custom:")
    split = results["splits"]["my-suite"]
    assert split["sr"] == 1.0 and split["spl"] == 1.0 and split["episodes"] == 20

    # the file names its houses relative to itself: moved together with them, it still works
    moved = tmp_path / "elsewhere"
    shutil.copytree(made / "houses", moved / "houses")
    shutil.copy(made / "my-suite.json", moved / "my-suite.json")
    out = run(
        "objsearch-eval",
        "--agent",
        "random",
        "--suite",
        str(moved / "my-suite.json"),
        "--seeds",
        "1",
        "--cache-dir",
        cache_dir,
        "--quiet",
    )
    assert out.returncode == 0, out.stderr
    assert "My Suite" in out.stdout


def _spoil(folder: Path, how: str) -> None:
    house = folder / "houses" / "train_000004"
    if how == "missing folder":
        shutil.rmtree(house)
    elif how == "changed spec.json":  # a whole other house in its place: only the recorded hash tells
        shutil.rmtree(house)
        shutil.copytree(folder / "houses" / "train_000003", house)
    elif how == "edited house.xml":  # still loads, but is no longer what spec.json describes
        xml = (house / "house.xml").read_text()
        assert "<worldbody>" in xml
        (house / "house.xml").write_text(xml.replace("<worldbody>", "<worldbody><geom size='0.1'/>", 1))
    elif how == "broken house.xml":
        (house / "house.xml").write_text("<mujoco><worldbody>")
    elif how == "spec.json missing a field":
        spec = json.loads((house / "spec.json").read_text())
        del spec["rooms"]
        (house / "spec.json").write_text(json.dumps(spec))


@pytest.mark.parametrize(
    "how, message",
    [
        ("missing folder", "is missing"),
        ("changed spec.json", "changed after the suite was made"),
        ("edited house.xml", "no longer matches its house.xml"),
        ("broken house.xml", "cannot load house"),
        ("spec.json missing a field", "is not a house spec"),
    ],
)
def test_a_bad_house_stops_the_evaluation_naming_it(made, tmp_path, how, message):
    shutil.copytree(made / "houses", tmp_path / "houses")
    shutil.copy(made / "my-suite.json", tmp_path / "my-suite.json")
    _spoil(tmp_path, how)
    out = run(
        "objsearch-eval", "--agent", "oracle", "--suite", "my-suite.json", "--seeds", "1", "--quiet", cwd=tmp_path
    )
    assert_clean_error(out, "house train_000004", message)


def test_bad_houses_and_arguments_stop_suite_make_naming_them(made, tmp_path):
    shutil.copytree(made / "houses", tmp_path / "houses")
    _spoil(tmp_path, "broken house.xml")
    make = ("objsearch", "suite", "make", "--out", "s.json")
    assert_clean_error(run(*make, "--houses", "houses", cwd=tmp_path), "house train_000004", "cannot load house")
    assert not (tmp_path / "s.json").exists()
    assert_clean_error(run(*make, "--houses", "nowhere", cwd=tmp_path), "houses folder nowhere does not exist")
    (tmp_path / "empty").mkdir()
    assert_clean_error(run(*make, "--houses", "empty", cwd=tmp_path), "no houses under empty")
    assert_clean_error(
        run(*make, "--houses", str(made / "houses"), "--targets", "bedd", cwd=tmp_path),
        "unknown target category 'bedd'",
        "did you mean 'bed'",
    )
    assert_clean_error(
        run("objsearch", "suite", "make", "--houses", "houses", "--out", "s.txt", cwd=tmp_path), "ends in .json"
    )
    assert_clean_error(
        run("objsearch-eval", "--suite", "none.json", cwd=tmp_path), "suite file none.json does not exist"
    )


def test_suite_make_draws_starts_near_the_entrance(made, cache_dir, tmp_path):
    """``--starts entrance``: house-gen-2 houses get starts near their entrance (recorded in
    the file, evaluated as any suite file); house-gen-1 houses (no entrance) are a clean error."""
    from objsearch.sim.env import entrance_poses
    from objsearch.sim.suites import load_houses, load_suite_file

    assert_clean_error(
        run(
            "objsearch", "suite", "make", "--houses", str(made / "houses"), "--out", "s.json",
            "--starts", "entrance", cwd=tmp_path,
        ),
        "house train_000003",
        "no entrance",
        "house-gen-2",
    )  # fmt: skip
    assert not (tmp_path / "s.json").exists()
    gen = ["objsearch", "generate", "--generator", "house-gen-2", "--seed", "3", "--num", "2", "--rooms", "small"]
    assert run(*gen, "--no-preview", "--quiet", "--out", "houses", cwd=tmp_path).returncode == 0
    args = ["--houses", "houses", "--episodes", "12", "--seed", "1", "--cache-dir", cache_dir]
    out = run("objsearch", "suite", "make", *args, "--starts", "entrance", "--out", "near.json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    raw = json.loads((tmp_path / "near.json").read_text())
    assert raw["starts"] == "entrance"
    worlds = load_houses(load_suite_file(str(tmp_path / "near.json")))
    for item in raw["splits"]["near"]:
        world = worlds[item["house"]]
        assert entrance_poses(world)[world.graph.pose_id(*item["start"])]
    out = run(
        "objsearch-eval", "--agent", "oracle", "--suite", "near.json", "--seeds", "1", "--quiet",
        "--cache-dir", cache_dir, "--out", "r.json", cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr


def test_shipped_agents_run_on_your_suite_with_the_checkpoint_of_its_generator(made, cache_dir, tmp_path):
    """No --checkpoint: the checkpoint trained for unseen houses of the suite's generator is
    picked and named; one made for another generator is refused in one line."""
    out = run(
        "objsearch-eval", "--agent", "a3c", "--suite", "my-suite.json", "--seeds", "1", "--cache-dir", cache_dir,
        "--out", str(tmp_path / "a3c.json"), "--quiet", cwd=made,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "houses of generator house-gen-1; using the checkpoint trained on house-gen's training houses" in out.stderr
    results = json.loads((tmp_path / "a3c.json").read_text())
    assert results["splits"]["my-suite"]["episodes"] == 20 and not any("error" in r for r in results["episodes"])
    v2 = Path(__file__).resolve().parents[2] / "agents" / "checkpoints" / "house-gen-v2" / "a3c"
    out = run(
        "objsearch-eval", "--agent", "a3c", "--suite", "my-suite.json", "--seeds", "1", "--cache-dir", cache_dir,
        "--checkpoint", str(v2), "--quiet", cwd=made,
    )  # fmt: skip
    assert_clean_error(out, "trained on suite house-gen-v2 (for unseen houses of generator house-gen-2)", "house-gen-1")
    out = run("objsearch-eval", "--agent", "hdqn", "--suite", "my-suite.json", "--seeds", "1", "--quiet", cwd=made)
    assert_clean_error(
        out,
        "no hdqn checkpoint",
        "`objsearch train --agent hdqn --suite my-suite.json` (it writes runs/my-suite/hdqn-seed0)",
    )


def test_suite_make_takes_the_large_tiers_rules(made, cache_dir, tmp_path):
    """``--goal-pixels/--goal-distance`` (ObjectNav), far starts (``--min-distance``,
    ``--min-room-hops``), ``--max-steps`` and ``--seeds``: the file records them, its goal poses
    follow the rule, every start meets the far-start rule, and a full evaluation plays its seeds."""
    from objsearch.errors import UserError
    from objsearch.house.categories import CATEGORY_IDS
    from objsearch.sim.cache import HouseCache
    from objsearch.sim.goals import GOAL_CAMERA, GoalRule, goal_poses
    from objsearch.sim.start_rules import MadeRules, room_hops
    from objsearch.sim.suite_build import suite_from_houses
    from objsearch.sim.suites import load_houses, load_suite_file

    shutil.copytree(made / "houses", tmp_path / "houses")
    rules = ["--protocol", "objectnav", "--goal-pixels", "5", "--goal-distance", "1.5", "--max-steps", "300"]
    far = ["--min-distance", "3", "--min-room-hops", "1", "--seeds", "1,2"]
    make = ["objsearch", "suite", "make", "--houses", "houses", "--episodes", "12", "--cache-dir", cache_dir]
    out = run(*make, *rules, *far, "--out", "far.json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    raw = json.loads((tmp_path / "far.json").read_text())
    rule = {k: v for k, v in raw["goal_rule"].items() if k != "version"}
    assert rule == {"kind": "near_visible", "top_k": 5, "min_pixels": 5, "max_distance": 1.5}
    assert raw["max_steps"] == 300 and raw["seeds"] == [1, 2]
    worlds = load_houses(load_suite_file(str(tmp_path / "far.json")))
    for house, table in raw["goals"].items():
        cache = HouseCache.open(worlds[house], GOAL_CAMERA, cache_dir, progress=False)
        for target, poses in table.items():
            ids = goal_poses(cache.semantic, cache.depth, CATEGORY_IDS[target], GoalRule(**rule))
            assert [list(worlds[house].graph.pose_of(int(i))) for i in ids] == poses
    moves = []
    for item in raw["splits"]["far"]:
        world = worlds[item["house"]]
        graph, start = world.graph, world.graph.pose_id(*item["start"])
        goals = [graph.pose_id(*g) for g in raw["goals"][item["house"]][item["target"]]]
        assert graph.geodesic_metres(goals)[start] >= 3 and item["geodesic"] >= 3
        assert item["min_steps"] == graph.shortest_steps(goals)[start] + 1
        holders = {o.room for o in world.spec.objects if o.category == item["target"]}
        room = int(world.cell_rooms[start // 4])
        assert all(room_hops(world.spec)[room, h] >= 1 for h in holders)  # not in a room that holds it
        moves.append(item["min_steps"] - 1)
    assert raw["start_steps"] == [min(moves), max(moves)]
    out = run("objsearch-eval", "--agent", "oracle", "--suite", "far.json", "--quiet", "--out", "r.json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    results = json.loads((tmp_path / "r.json").read_text())
    assert results["seeds"] == [1, 2] and all(r["success"] for r in results["episodes"])

    assert_clean_error(run(*make, "--goal-pixels", "5", "--out", "p.json", cwd=tmp_path), "--protocol objectnav")
    assert not (tmp_path / "p.json").exists()
    houses, out = tmp_path / "houses", tmp_path / "n.json"
    with pytest.raises(UserError, match="exclude each other"):
        suite_from_houses(houses, out, starts="entrance", rules=MadeRules(min_distance=3))
    with pytest.raises(UserError, match="target 'bed' has no goal pose with a start 1000 m walking"):
        suite_from_houses(houses, out, ["bed"], cache_dir=cache_dir, rules=MadeRules(min_distance=1000))
