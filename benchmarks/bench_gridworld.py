"""Grid-world simulation throughput: objsearch's env, single and batched, beside MiniGrid.

Counts env steps per second with observations produced every step (random actions,
episodes reset as they end). The peer is MiniGrid's simplest env, ``MiniGrid-Empty-5x5-v0``:
one env, and a Gymnasium ``SyncVectorEnv`` of 64 (MiniGrid has no batched simulator).

    .venv/bin/python benchmarks/bench_gridworld.py [--seconds 2] [--json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")


def timed(step, seconds: float) -> tuple[int, float]:
    """Call ``step()`` (returns env steps done) until ``seconds`` have passed."""
    step()  # warm-up
    count, start = 0, time.perf_counter()
    while (elapsed := time.perf_counter() - start) < seconds:
        count += step()
    return count, elapsed


def bench_single(seconds: float) -> float:
    from objsearch.gridworld.env import GridWorldEnv

    env = GridWorldEnv(observation="goal")
    env.reset(seed=0)
    actions = np.random.default_rng(0).integers(4, size=1 << 16).tolist()
    i = 0

    def step():
        nonlocal i
        for _ in range(1000):
            _, _, terminated, truncated, _ = env.step(actions[i & 0xFFFF])
            i += 1
            if terminated or truncated:
                env.reset()
        return 1000

    count, elapsed = timed(step, seconds)
    return count / elapsed


def bench_batched(num_envs: int, observation: str, seconds: float) -> float:
    from objsearch.gridworld import dataset
    from objsearch.gridworld.batched import BatchedGridWorld

    world = BatchedGridWorld(
        list(dataset.train_maps().values()), num_envs, observation=observation, rng=np.random.default_rng(0)
    )
    world.reset()
    actions = np.random.default_rng(1).integers(4, size=(64, num_envs))
    i = 0

    def step():
        nonlocal i
        world.step(actions[i & 63])
        i += 1
        return num_envs

    count, elapsed = timed(step, seconds)
    return count / elapsed


def bench_minigrid(num_envs: int, seconds: float) -> float | None:
    try:
        import gymnasium
        import minigrid  # noqa: F401  (registers the MiniGrid envs)
    except ImportError:
        return None
    if num_envs == 1:
        env = gymnasium.make("MiniGrid-Empty-5x5-v0")
        env.reset(seed=0)
        rng = np.random.default_rng(0)

        def step():
            for a in rng.integers(3, size=1000):
                _, _, terminated, truncated, _ = env.step(int(a))
                if terminated or truncated:
                    env.reset()
            return 1000

    else:
        env = gymnasium.vector.SyncVectorEnv([lambda: gymnasium.make("MiniGrid-Empty-5x5-v0")] * num_envs)
        env.reset(seed=0)
        rng = np.random.default_rng(0)

        def step():
            env.step(rng.integers(3, size=num_envs))
            return num_envs

    count, elapsed = timed(step, seconds)
    env.close()
    return count / elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="time per measurement")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    args = parser.parse_args()

    rows: list[tuple[str, int, float | None]] = [("objsearch GridWorld-v0 (gymnasium)", 1, bench_single(args.seconds))]
    for observation in ("goal", "all_goals"):
        for n in (1, 64, 1024, 4096):
            rows.append(
                (f"objsearch BatchedGridWorld, obs={observation}", n, bench_batched(n, observation, args.seconds))
            )
    rows.append(("MiniGrid-Empty-5x5-v0", 1, bench_minigrid(1, args.seconds)))
    rows.append(("MiniGrid-Empty-5x5-v0 (SyncVectorEnv)", 64, bench_minigrid(64, args.seconds)))

    if args.json:
        print(json.dumps({f"{name} [N={n}]": (None if v is None else round(v)) for name, n, v in rows}))
        return
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; {args.seconds:.0f} s per row"
    )
    print(f"{'env':<46}{'batch':>7}{'steps/s':>14}")
    for name, n, value in rows:
        print(f"{name:<46}{n:>7}{'n/a' if value is None else f'{value:,.0f}':>14}")


if __name__ == "__main__":
    main()
