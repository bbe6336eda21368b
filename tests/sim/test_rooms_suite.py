"""The ``rooms`` suite (``objsearch.sim.rooms_suite``): single functional rooms under the paper's
AI2-THOR protocol, with a step limit per room type."""

import json
import os
import subprocess
import sys
from collections import Counter

import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_IDS
from objsearch.house.rooms import ROOM_TYPES
from objsearch.sim.cache import HouseCache
from objsearch.sim.env import HouseEnv, HouseTask
from objsearch.sim.goals import GOAL_CAMERA
from objsearch.sim.rooms_suite import EPISODES_PER_ROOM_TYPE, ROOM_MAX_STEPS, SPLITS, mapped_goals
from objsearch.sim.suites import episode_task, load_suite_file, training_houses
from objsearch.sim.vector import HouseVectorEnv
from objsearch.sim.world import HouseRef, World

ENV = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}


@pytest.fixture(scope="module")
def suite():
    return load_suite_file("rooms")


def room_of(suite, house):
    return suite["houses"][house]["room"]


def test_rooms_splits_and_goals(suite):
    assert tuple(suite["splits"]) == SPLITS and suite["room_max_steps"] == ROOM_MAX_STEPS
    assert suite["max_steps"] == 200 and suite["starts"] == "not_visible"
    rooms = Counter((room_of(suite, h), info["split"]) for h, info in suite["houses"].items())
    assert rooms == {(room, split): n for room in ROOM_TYPES for split, n in (("train", 20), ("test", 10))}
    assert {ref.seed for ref in training_houses(suite)} == set(range(1000, 1020))
    assert (
        all(ref.split == "train" and ref.room for ref in training_houses(suite)) and len(training_houses(suite)) == 80
    )
    categories = suite["categories"]
    for room in ROOM_TYPES:
        seen, unseen = categories[f"{room}-seen"], categories[f"{room}-unseen"]
        assert seen and unseen and not set(seen) & set(unseen)
        assert set(seen) <= set(mapped_goals(room, "seen")) and set(unseen) <= set(mapped_goals(room, "unseen"))
    for split, episodes in suite["splits"].items():
        env, kind = split.split("-env-")[0], split.split("-env-")[1].removesuffix("-goals")
        assert Counter(room_of(suite, e["house"]) for e in episodes) == dict.fromkeys(
            ROOM_TYPES, EPISODES_PER_ROOM_TYPE
        )
        for e in episodes:
            assert suite["houses"][e["house"]]["split"] == ("train" if env == "seen" else "test")
            assert e["target"] in categories[f"{room_of(suite, e['house'])}-{kind}"]
            assert 1 <= e["min_steps"] <= ROOM_MAX_STEPS[room_of(suite, e["house"])]


def test_rooms_regenerate_to_their_spec_hashes(suite):
    """The suite is locked by the spec hashes: a sample of one room per type and set regenerates to them."""
    sample = {}
    for house, info in suite["houses"].items():
        sample.setdefault((info["room"], info["seed"] // 1000), (house, info))
    assert len(sample) == 12
    for house, info in sample.values():
        world = World.load(HouseRef(**{k: v for k, v in info.items() if k != "spec_sha256"}))
        assert world.house_id == house and world.spec.single_room == info["room"]
        assert world.spec_sha256 == info["spec_sha256"], house


def test_starts_do_not_see_the_target(suite, cache_dir):
    bathrooms = sorted(h for h in suite["houses"] if room_of(suite, h) == "bathroom")[:3]
    checked = 0
    for house in bathrooms:
        world = World.load(HouseRef(**suite["houses"][house]))
        semantic = np.asarray(HouseCache.open(world, GOAL_CAMERA, cache_dir, progress=False).semantic)
        for split in SPLITS:
            for e in suite["splits"][split]:
                if e["house"] == house:
                    frame = semantic[world.graph.pose_id(*e["start"])]
                    assert not (frame == CATEGORY_IDS[e["target"]]).any(), (split, e)
                    checked += 1
    assert checked > 20


def _far_task(world: World) -> HouseTask:
    """A task whose one goal pose is far from a start that only turns on the spot: never reached."""
    graph = world.graph
    start, goal = 0, graph.num_poses - 1
    steps = int(graph.shortest_steps([goal])[start])
    assert steps > 1
    return HouseTask(world.house_id, graph.pose_of(start), "bed", (graph.pose_of(goal),), steps)


@pytest.mark.parametrize("room, limit", [("kitchen", 100), ("living_room", 200)])
def test_house_env_ends_an_episode_at_its_room_limit(room, limit):
    world = World.load(HouseRef(seed=1000, room=room))
    env = HouseEnv([world], mode="live", max_steps=200, room_max_steps=ROOM_MAX_STEPS)
    env.reset(options={"task": _far_task(world)})
    steps, truncated = 0, False
    while not truncated:
        _, _, terminated, truncated, info = env.step(1)  # turn left, on the spot
        steps += 1
        assert not terminated
    assert steps == info["steps"] == limit == env.step_limit(world)
    # without room limits (every other suite) the env's max_steps is every episode's
    assert HouseEnv([world], max_steps=150).step_limit(world) == 150
    # max_steps caps a room's limit (objsearch-eval --max-steps)
    assert HouseEnv([world], max_steps=50, room_max_steps=ROOM_MAX_STEPS).step_limit(world) == 50
    env.close()


def test_vector_env_ends_each_episode_at_its_room_limit(cache_dir):
    houses = [HouseRef(seed=1000, room="kitchen"), HouseRef(seed=1001, room="living_room")]
    env = HouseVectorEnv(4, houses=houses, max_steps=200, room_max_steps=ROOM_MAX_STEPS, cache_dir=cache_dir)
    env.reset(seed=0)
    ended = Counter()
    for _ in range(400):
        rooms = [env.env.world(env._houses[h]).spec.single_room for h in env.house]
        _, _, terminated, truncated, info = env.step(np.ones(env.num_envs, dtype=np.int64))  # turn on the spot
        assert not terminated.any()  # sampled starts are 6 or more steps from the goal
        for i in np.flatnonzero(truncated):
            assert info["steps"][i] == ROOM_MAX_STEPS[rooms[i]]
            ended[rooms[i]] += 1
    assert ended["kitchen"] and ended["living_room"]
    env.close()


def test_room_limits_are_checked():
    with pytest.raises(ValueError, match="unknown room type 'garage'"):
        HouseEnv([HouseRef(seed=1000, room="kitchen")], room_max_steps={"garage": 100})
    with pytest.raises(ValueError, match="positive integer"):
        HouseEnv([HouseRef(seed=1000, room="kitchen")], room_max_steps={"kitchen": 0})


def test_episodes_carry_no_limit_of_their_own(suite):
    """The limit is the room's (the env's ``room_max_steps``); tasks and records are as in every suite."""
    item = suite["splits"]["unseen-env-unseen-goals"][0]
    assert set(item) == {"house", "start", "target", "min_steps"}
    assert episode_task(suite, item).to_json() == item


def _edited_copy(path, edit) -> str:
    data = json.loads(json.dumps(load_suite_file("rooms")))
    edit(data)
    path.write_text(json.dumps(data))
    return str(path)


def test_an_unknown_room_type_is_one_line_naming_it(tmp_path):
    def garage(data):
        data["houses"]["train_kitchen_001000"]["room"] = "garage"

    path = _edited_copy(tmp_path / "my-rooms.json", garage)
    with pytest.raises(UserError, match=r"houses\.train_kitchen_001000\.room: 'garage' is not one of"):
        load_suite_file(path)
    with pytest.raises(UserError, match=r"room_max_steps\.garage: is not a field here"):
        load_suite_file(_edited_copy(tmp_path / "limits.json", lambda d: d["room_max_steps"].update(garage=100)))
    r = subprocess.run(
        [sys.executable, "-m", "objsearch.cli", "eval", "--agent", "oracle", "--suite", path, "--quiet"],
        capture_output=True,
        text=True,
        env=ENV,
        timeout=120,
    )
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "'garage'" in r.stderr and "kitchen, living_room, bedroom, bathroom" in r.stderr
