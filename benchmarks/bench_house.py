"""House sensing and navigation throughput: live rendering, the naive baseline, the
observation cache (build time per house, cached env steps per second).

    .venv/bin/python benchmarks/bench_house.py [--seed 2] [--json]
    .venv/bin/python benchmarks/bench_house.py --cached-only [--repeat 3]   # env steps only
    .venv/bin/python benchmarks/bench_house.py --digest 100000   # records, not speed

``--digest STEPS`` prints the sha256 of seeded rollouts on the house's cache in
``$OBJSEARCH_CACHE`` (one ``HouseEnv`` with and without STOP, and ``HouseVectorEnv``;
random actions, 300-step episodes; every observation's dtype, shape and bytes, rewards,
flags and info): the same digests before and after a change mean the same records.

``--cached-only`` measures only the cached env figures, on the house's cache in
``$OBJSEARCH_CACHE`` (built there if missing, not timed), ``--repeat`` times each
(``cached_steps_per_s`` and the others are then lists, one value a run).

With ``--json`` the last line is one JSON object with ``live_fps_64``, ``live_fps_128``,
``naive_fps_64``, ``naive_fps_128``, ``cached_steps_per_s`` (one ``HouseEnv``),
``cached_vector_steps_per_s`` (``HouseVectorEnv`` of 256), ``cache_build_s_per_house`` and
``poses``. Rendering figures come from ``bench_render.py`` (same folder). Steps per second
are also given per CPU second (``*_cpu``), which a busy machine changes less.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")
sys.path.insert(0, str(Path(__file__).parent))

import numpy as np  # noqa: E402
from bench_render import measure_live_fps, measure_naive_fps  # noqa: E402

from objsearch.sim.cache import HouseCache  # noqa: E402
from objsearch.sim.camera import AGENT_CAMERA, RenderSettings  # noqa: E402
from objsearch.sim.env import HouseEnv  # noqa: E402
from objsearch.sim.vector import HouseVectorEnv  # noqa: E402
from objsearch.sim.world import HouseRef, World  # noqa: E402


def cached_steps_per_s(ref: HouseRef, cache_dir: str, steps: int = 200_000) -> tuple[float, float]:
    """Random actions through ``HouseEnv`` in cached mode, resets included, one process:
    (steps per wall second, steps per CPU second)."""
    env = HouseEnv([ref], mode="cached", cache_dir=cache_dir)
    env.reset(seed=0)
    actions = np.random.default_rng(0).integers(6, size=steps).tolist()
    wall, cpu = time.perf_counter(), time.process_time()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    return steps / (time.perf_counter() - wall), steps / (time.process_time() - cpu)


def cached_vector_steps_per_s(
    ref: HouseRef, cache_dir: str, num_envs: int = 256, steps: int = 400
) -> tuple[float, float]:
    """The same through ``HouseVectorEnv`` (same-step autoreset), ``num_envs`` at a time."""
    env = HouseVectorEnv(num_envs, houses=[ref], cache_dir=cache_dir)
    env.reset(seed=0)
    actions = np.random.default_rng(0).integers(6, size=(steps, num_envs))
    wall, cpu = time.perf_counter(), time.process_time()
    for batch in actions:
        env.step(batch)
    total = steps * num_envs
    return total / (time.perf_counter() - wall), total / (time.process_time() - cpu)


def rollout_digest(ref: HouseRef, cache_dir: str, steps: int) -> dict[str, str]:
    """sha256 of seeded random rollouts (see ``--digest``): {"single", "single_stop", "vector"}."""

    def add(h, obs: dict) -> None:
        for key in sorted(obs):
            value = np.asarray(obs[key])
            h.update(f"{key}{value.dtype}{value.shape}".encode() + value.tobytes())

    out = {}
    for name, stop in (("single", False), ("single_stop", True)):
        env = HouseEnv([ref], mode="cached", cache_dir=cache_dir, max_steps=300, stop_action=stop)
        h = hashlib.sha256()
        obs, info = env.reset(seed=0)
        add(h, obs)
        actions = np.random.default_rng(1).integers(int(env.action_space.n), size=steps).tolist()
        for action in actions:
            obs, reward, terminated, truncated, info = env.step(action)
            add(h, obs)
            h.update(repr((reward, terminated, truncated, sorted(info.items()))).encode())
            if terminated or truncated:
                obs, _ = env.reset()
                add(h, obs)
        out[name] = h.hexdigest()
    env = HouseVectorEnv(16, houses=[ref], cache_dir=cache_dir, max_steps=300)
    h = hashlib.sha256()
    obs, _ = env.reset(seed=0)
    add(h, obs)
    for batch in np.random.default_rng(2).integers(6, size=(steps // 16, 16)):
        obs, reward, terminated, truncated, _ = env.step(batch)
        add(h, {**obs, "reward": reward, "terminated": terminated, "truncated": truncated})
    out["vector"] = h.hexdigest()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=2, help="generator seed of the house (default: a medium one)")
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--cached-only", action="store_true", help="only the cached env steps, on $OBJSEARCH_CACHE")
    parser.add_argument("--repeat", type=int, default=1, help="--cached-only: runs of each measurement")
    parser.add_argument("--digest", type=int, metavar="STEPS", help="print the records' sha256 instead of speeds")
    args = parser.parse_args()

    ref = HouseRef(seed=args.seed, size_class="medium")
    world = World.load(ref)
    if args.digest:
        cache_dir = str(HouseCache.open(world, AGENT_CAMERA, progress=False).directory.parent)
        print(
            json.dumps({"house": world.house_id, "steps": args.digest, **rollout_digest(ref, cache_dir, args.digest)})
        )
        return
    if args.cached_only:
        cache_dir = str(HouseCache.open(world, AGENT_CAMERA, progress=False).directory.parent)
        out = {"house": world.house_id, "poses": world.graph.num_poses}
        runs = [cached_steps_per_s(ref, cache_dir) for _ in range(args.repeat)]
        out["cached_steps_per_s"], out["cached_steps_per_s_cpu"] = ([round(r[i]) for r in runs] for i in (0, 1))
        runs = [cached_vector_steps_per_s(ref, cache_dir) for _ in range(args.repeat)]
        out["cached_vector_steps_per_s"], out["cached_vector_steps_per_s_cpu"] = (
            [round(r[i]) for r in runs] for i in (0, 1)
        )
        out["load_average"] = round(os.getloadavg()[0], 2)
        print(json.dumps(out) if args.json else "\n".join(f"{key:<32}{value}" for key, value in out.items()))
        return
    graph = world.graph
    poses = graph.world_poses(np.random.default_rng(0).choice(graph.num_poses, size=256, replace=False))
    out = {"house": world.house_id, "poses": graph.num_poses, "objects": len(world.spec.objects)}
    for size in (64, 128):
        settings = RenderSettings(width=size, height=size)
        out[f"live_fps_{size}"] = round(measure_live_fps(world.model, settings, poses), 1)
        out[f"naive_fps_{size}"] = round(measure_naive_fps(world.model, settings, poses[:64]), 1)
    with tempfile.TemporaryDirectory() as cache_dir:
        start = time.perf_counter()
        HouseCache.open(world, AGENT_CAMERA, cache_dir, progress=False)
        out["cache_build_s_per_house"] = round(time.perf_counter() - start, 2)
        out["cached_steps_per_s"], out["cached_steps_per_s_cpu"] = map(round, cached_steps_per_s(ref, cache_dir))
        out["cached_vector_steps_per_s"], out["cached_vector_steps_per_s_cpu"] = map(
            round, cached_vector_steps_per_s(ref, cache_dir)
        )
    out["speedup_64"] = round(out["live_fps_64"] / out["naive_fps_64"], 1)
    if args.json:
        print(json.dumps(out))
        return
    for key, value in out.items():
        print(f"{key:<26}{value}")


if __name__ == "__main__":
    main()
