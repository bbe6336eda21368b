"""Memory follows the houses in play: envs of one process read a house's cache through one
set of files (read frame by frame, not mapped), and let go of it when they move on."""

import gc
import os
from pathlib import Path

import numpy as np
import pytest

from objsearch.eval.lockstep import play_lockstep
from objsearch.eval.suites import Episode
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.cache import HouseCache, cache_key, open_cache_folders
from objsearch.sim.camera import AGENT_CAMERA
from objsearch.sim.env import HouseEnv
from objsearch.sim.world import HouseRef, World
from objsearch_agents.baselines.random_agent import RandomAgent

OTHER_HOUSE = HouseRef(seed=4, size_class="small")  # ~1850 poses


@pytest.fixture(scope="module")
def houses(tmp_path_factory, small_world):
    """Two houses, a cache folder of their own (nothing else in the session holds these
    caches) and three tasks in each: (worlds, cache_dir, {house id: [tasks]})."""
    cache_dir = str(tmp_path_factory.mktemp("release-cache"))
    worlds = [small_world, World.load(OTHER_HOUSE)]
    env = HouseEnv(worlds, cache_dir=cache_dir)
    rng, tasks = np.random.default_rng(0), {w.house_id: [] for w in worlds}
    while min(map(len, tasks.values())) < 3:
        task = env.sample_task(rng)
        tasks[task.house] += [task][: 3 - len(tasks[task.house])]
    env.close()
    del env
    gc.collect()
    return worlds, cache_dir, tasks


class CountingEnv(HouseEnv):
    """A ``HouseEnv`` that counts the steps of all its instances."""

    steps = 0

    def step(self, action):
        CountingEnv.steps += 1
        return super().step(action)


def folder_of(world, cache_dir) -> Path:
    return Path(cache_dir) / f"{world.house_id}-{cache_key(world, AGENT_CAMERA)}"


def files_in_use(folder: Path) -> tuple[list[str], list[str]]:
    """The files under ``folder`` this process maps (``/proc/self/maps``) and holds open (``/proc/self/fd``)."""
    prefix = f"{folder}{os.sep}"
    maps = [line.split()[-1] for line in Path("/proc/self/maps").read_text().splitlines() if prefix in line]
    fds = []
    for fd in os.listdir("/proc/self/fd"):
        try:
            target = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        fds += [target] if target.startswith(prefix) else []
    return maps, sorted(fds)


def test_envs_share_a_house_and_let_go_of_it_when_they_move_on(houses):
    worlds, cache_dir, tasks = houses
    a, b = (w.house_id for w in worlds)
    folder = folder_of(worlds[0], cache_dir)
    envs = [HouseEnv(worlds, cache_dir=cache_dir) for _ in range(3)]
    for env in envs:
        env.reset(options={"task": tasks[a][0]})
        env.step(0)
    assert all(env._source_now is envs[0]._source_now for env in envs)  # opened once for the process
    assert open_cache_folders().count(folder) == 1
    maps, fds = files_in_use(folder)
    assert maps == []  # frames are read, not mapped: nothing of the house stays in memory
    assert [Path(f).name for f in fds] == ["frames.npy"]  # one file, one read a step
    for env in envs:
        env.reset(options={"task": tasks[b][0]})
    assert folder not in open_cache_folders()
    assert files_in_use(folder) == ([], [])
    for env in envs:
        env.close()
    assert files_in_use(folder_of(worlds[1], cache_dir)) == ([], [])


def test_mapped_layers_go_with_the_last_user(houses):
    worlds, cache_dir, _ = houses
    folder = folder_of(worlds[0], cache_dir)
    cache = HouseCache.open(worlds[0], AGENT_CAMERA, cache_dir, progress=False)
    assert HouseCache.open(worlds[0], AGENT_CAMERA, cache_dir, progress=False) is cache
    np.testing.assert_array_equal(cache.frame("rgb", 5), cache.rgb[5])
    np.testing.assert_array_equal(cache.frame("depth", 5), cache.depth[5])
    np.testing.assert_array_equal(cache.frames("semantic", 3, 7), cache.semantic[3:7])
    assert len(files_in_use(folder)[0]) == 1  # the file mapped once, for every layer
    del cache
    assert files_in_use(folder) == ([], [])


def test_lockstep_lets_go_of_a_house_once_its_episodes_are_done(houses):
    worlds, cache_dir, tasks = houses
    a, b = (w.house_id for w in worlds)
    folders = {w.house_id: folder_of(w, cache_dir) for w in worlds}
    episodes = [
        Episode(i, task, CATEGORY_IDS[task.target], task.target, task.min_steps, task.to_json())
        for i, task in enumerate(tasks[a] + tasks[b])  # house a's episodes first, then b's
    ]
    units = [("split", 1, e.episode_id) for e in episodes]
    envs = [CountingEnv(worlds, cache_dir=cache_dir, max_steps=4) for _ in range(2)]
    done, in_play = [], []  # (episode id, env steps so far) of each record; houses open then
    for record in play_lockstep(units, envs, RandomAgent, lambda split, i: episodes[i], "two-houses", None):
        done.append((record["episode_id"], CountingEnv.steps))
        in_play.append({h for h, folder in folders.items() if folder in open_cache_folders()})
    assert sorted(e for e, _ in done) == list(range(6))
    a_done = max(steps for e, steps in done if e < 3)  # when house a's last episode ended
    assert a in in_play[0]
    later = [now for (_, steps), now in zip(done, in_play) if steps > a_done]  # the slots have moved on since
    assert later and all(a not in now for now in later), (done, in_play)
    assert files_in_use(folders[a]) == ([], [])
    for env in envs:
        env.close()
    assert not {folders[a], folders[b]} & set(open_cache_folders())
