"""The house suites in the harness: the shipped ones (``objsearch.sim.suites.SUITE_NAMES``)
and suite files made by ``objsearch suite make``, all played by ``HouseSuite``.

Episodes come from the suite files of ``objsearch.sim.suites``; the env is
``ObjSearch/House-v1`` in ``cached`` mode by default (``live`` for ``house-large-v2``'s suites,
whose caches would take about 40 GB; ``objsearch cache build --suite NAME``
renders the caches ahead; otherwise an evaluation builds the missing ones first, as a stage
of its own, ``HouseSuite.prepare``) or
``live``. Agents see ``objsearch.sim.camera.AGENT_CAMERA``; goal poses come from the suite
files (chosen through ``objsearch.sim.goals.GOAL_CAMERA``). With ``observation="predicted"``
the agent's ``semantic`` and ``depth`` are the perception network's predictions
(``perception``: a checkpoint, default the shipped one, trained on the agent camera's
frames), as in the paper; success is still judged on the ground truth.

A suite's ``protocol`` (its file's, ``objsearch.sim.goals.PROTOCOLS``) says how its episodes
succeed: ``paper``, on reaching a goal pose, or ``objectnav``, on calling STOP at one (the
env's ``stop_action``; agents read ``task.stop_action`` and ``task.goal_rule``). A suite
file's poses are checked on its houses' pose graphs when the houses load
(``objsearch.sim.suite_schema.check_poses``; a shipped file's content is fixed by its digest).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from functools import cached_property, partial
from pathlib import Path

from objsearch.errors import UserError
from objsearch.eval.suites import Episode, step_limit
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.camera import AGENT_CAMERA, check_predictor_camera
from objsearch.sim.env import MODES, OBSERVATIONS, HouseEnv, HouseTask
from objsearch.sim.goals import GoalRule
from objsearch.sim.navgraph import STOP, PoseGraph
from objsearch.sim.suites import MADE_FIX, SUITE_NAMES, episode_task, load_houses, load_suite_file, suite_protocol
from objsearch.sim.world import World


class HousePath:
    """The oracle's view of a house episode: the task (its start and goal poses), whether
    success needs STOP, and the house itself (``world``: its spec, rooms, objects and pose
    graph), which privileged calibration agents read (``objsearch_agents.baselines.room_frontier``).

    ``world`` may be given as a function that loads it: it is called on first use, so listing
    a suite's episodes (as the leaderboard's checks do) loads no house."""

    def __init__(self, task: HouseTask, stop: bool, world: "World | Callable[[], World]"):
        self.task, self.stop, self._world = task, stop, world

    @property
    def world(self) -> World:
        """The house (loaded on first use where a loader was given)."""
        if callable(self._world):
            self._world = self._world()
        return self._world

    @property
    def graph(self) -> PoseGraph:
        """The house's pose graph."""
        return self.world.graph

    def shortest_path(self) -> list[int]:
        """A shortest action sequence from the task's start pose to success: to its nearest
        goal pose, and STOP there where the protocol requires it."""
        g = self.graph
        moves = g.shortest_path(g.pose_id(*self.task.start), [g.pose_id(*p) for p in self.task.goals])
        return moves + [STOP] * self.stop


def default_mode(name: str) -> str:
    """How suite ``name`` renders unless told: ``live`` for a tier whose caches are not kept
    (``large_suite.Tier.keep_goal_caches``: tens of GB), else ``cached``."""
    from objsearch.sim.large_suite import TIERS

    return "live" if name in TIERS and not TIERS[name].keep_goal_caches else "cached"


class HouseSuite:
    """A house suite: ``name`` is a shipped suite's name or a suite file's path. Options:
    ``mode`` (``cached`` or ``live``; default ``default_mode``), ``cache_dir``, ``max_steps``, ``observation`` (``gt`` or
    ``predicted``), ``perception`` (the predicted mode's checkpoint; default: the shipped one)
    and ``perception_key`` (if given, the checkpoint must have this key: results record it, so
    a resumed or validated run uses the same network)."""

    world = "house"
    options = ("mode", "cache_dir", "max_steps", "observation", "perception", "perception_key")

    def __init__(
        self,
        name: str,
        mode: str | None = None,
        cache_dir: str | None = None,
        max_steps: int | None = None,
        observation: str = "gt",
        perception: str | None = None,
        perception_key: str | None = None,
    ):
        mode = default_mode(name) if mode is None else mode
        if mode not in MODES:
            raise UserError(f"unknown render mode {mode!r}; use one of {', '.join(MODES)}")
        if observation not in OBSERVATIONS:
            raise UserError(f"unknown observation {observation!r}; use one of {', '.join(OBSERVATIONS)}")
        if observation != "predicted" and (perception or perception_key):
            raise UserError("a perception checkpoint applies to predicted observations only (--observation predicted)")
        self.name, self.data = name, load_suite_file(name)
        self.protocol = suite_protocol(self.data).name
        self.mode, self.cache_dir = mode, cache_dir
        self.max_steps = step_limit(self.data["max_steps"] if max_steps is None else max_steps)
        self.episode_set_version = self.data["version"]
        self.splits = tuple(self.data["splits"])
        self.observation, self.predictor, self.perception = observation, None, None
        if observation == "predicted":
            from objsearch.perception.inference import Predictor, resolve_checkpoint

            self.perception = str(resolve_checkpoint(perception))
            self.perception_given = perception  # what results record: None for the shipped network, on any machine
            self.predictor = Predictor.from_checkpoint(self.perception, device="cpu")
            check_predictor_camera(self.predictor, AGENT_CAMERA)  # what the suite's env renders
            if perception_key is not None and perception_key != self.predictor.key:
                raise UserError(
                    f"perception checkpoint {self.perception} has key {self.predictor.key}, "
                    f"not {perception_key} as recorded; pass the checkpoint the results were made with"
                )

    def config(self) -> dict:
        """The config that rebuilds this suite; with predicted observations also the perception checkpoint and key."""
        config = {"mode": self.mode, "cache_dir": self.cache_dir, "max_steps": self.max_steps}
        if self.predictor is not None:
            config.update(observation="predicted", perception=self.perception_given, perception_key=self.predictor.key)
        return config

    @cached_property
    def worlds(self) -> dict[str, World]:
        """The suite's houses by house id, loaded (or regenerated) on first use; a suite file's
        poses are checked on them (``check_poses``)."""
        worlds = load_houses(self.data)
        if self.name not in SUITE_NAMES:
            from objsearch.sim.suite_schema import check_poses

            check_poses(self.data, worlds, self.name, MADE_FIX)
        return worlds

    def world_of(self, house: str) -> World:
        """The loaded house ``house`` (``worlds``: all of them load on first use)."""
        return self.worlds[house]

    def episodes(self, split: str) -> list[Episode]:
        """The fixed episodes of ``split``, in the suite file's order (ids 0, 1, ...); their
        houses load when an episode's ground truth is first read (``HousePath``)."""
        out = []
        for i, item in enumerate(self.data["splits"][split]):
            task = episode_task(self.data, item)
            out.append(
                Episode(
                    episode_id=i,
                    task=task,
                    goal=CATEGORY_IDS[task.target],
                    goal_name=task.target,
                    min_steps=task.min_steps,
                    describe=task.to_json(),
                    privileged=HousePath(task, suite_protocol(self.data).stop, partial(self.world_of, task.house)),
                )
            )
        return out

    def missing_caches(self, house_ids) -> list[str]:
        """The houses of ``house_ids`` whose observation cache (and, with predicted
        observations, predictions) is not built yet in ``cache_dir``; none in live mode. A cache
        that is there but damaged or stale is left to the env, which rebuilds it."""
        from objsearch.sim.cache import cache_key, default_cache_dir

        if self.mode != "cached":
            return []
        root = Path(self.cache_dir) if self.cache_dir is not None else default_cache_dir()
        missing = []
        for house_id in sorted(set(house_ids)):
            folder = root / f"{house_id}-{cache_key(self.worlds[house_id], AGENT_CAMERA)}"
            folders = [folder] + (
                [folder.parent / f"{folder.name}-pred-{self.predictor.key}"] if self.predictor else []
            )
            if not all((f / "meta.json").is_file() for f in folders):
                missing.append(house_id)
        return missing

    def prepare(self, units, workers: int = 1, progress: bool = True) -> None:
        """Build the missing caches of the houses that ``units`` ((split, seed, episode_id))
        play, as a stage of its own before the first episode (in ``workers`` processes, a
        house each), so that the episodes' progress and ETA count episodes only. ``progress``:
        a line before and after (and a bar on a terminal)."""
        import time

        from objsearch.perception.cache_cli import build_caches
        from objsearch.sim.cache import default_cache_dir

        wanted = {(split, i) for split, _, i in units}
        houses = {
            ep.task.house
            for split in {u[0] for u in units}
            for ep in self.episodes(split)
            if (split, ep.episode_id) in wanted
        }
        missing = self.missing_caches(houses)
        if not missing:
            return
        root = Path(self.cache_dir) if self.cache_dir is not None else default_cache_dir()
        say = (lambda text: print(text, file=sys.stderr)) if progress else (lambda text: None)
        say(
            f"building the observation caches of {len(missing)} of {len(houses)} house(s) in {root} before the "
            "first episode (once; the episodes' ETA starts after)"
        )
        start = time.monotonic()
        build_caches(
            {house: self.data["houses"][house] for house in missing},
            root,
            perception=self.perception,
            workers=min(workers, len(missing)),
            desc="building caches",
            progress=progress,
        )
        say(f"built {len(missing)} house cache(s) in {time.monotonic() - start:.0f} s")

    def make_env(self) -> HouseEnv:
        """A ``HouseEnv`` over the suite's houses with its render mode, observation, camera, step
        limits (``max_steps``, and ``room_max_steps`` below it in single rooms) and protocol (STOP,
        and the goal rule agents are told)."""
        rule = {key: value for key, value in self.data["goal_rule"].items() if key != "version"}
        return HouseEnv(
            list(self.worlds.values()),
            mode=self.mode,
            settings=AGENT_CAMERA,
            max_steps=self.max_steps,
            stop_action=suite_protocol(self.data).stop,
            goal_rule=GoalRule(**rule),
            cache_dir=self.cache_dir,
            observation=self.observation,
            predictor=self.predictor,
            room_max_steps=self.data.get("room_max_steps"),
        )

    def write_video(self, directory: str, record: dict, episode: Episode, trajectory: list) -> None:
        """Write the video of one episode into ``directory`` as ``<split>_seed<seed>_ep<id>``.

        ``trajectory``: the episode's (observation, info) pairs, from the reset on.
        """
        from pathlib import Path

        from objsearch.sim.video import write_episode

        stem = Path(directory) / f"{record['split']}_seed{record['seed']}_ep{record['episode_id']:04d}"
        poses = [info["pose"] for _, info in trajectory]
        observations = [obs for obs, _ in trajectory]
        write_episode(
            stem, self.worlds[episode.task.house], episode.task, poses, observations, success=record["success"]
        )
