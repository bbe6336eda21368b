"""Training-loop throughput of the house agents: environment steps per second of each
method's main phase on ``house-single``'s training house (tables built first, not timed).

    .venv/bin/python benchmarks/bench_house_train.py [--seconds 20] [--json]

Each method runs its real training step (acting, replay or rollouts, learning) with its
default config (32 episodes in lockstep, one torch thread), after a warm-up that fills
the replay memory. With ``--json`` the last line is one JSON object
``{"a3c": steps/s, "dqn": ..., "hdqn": ..., "hrl_grg": ..., "*_cpu": steps per CPU second}``
(CPU seconds change less on a busy machine).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from dataclasses import replace

os.environ.setdefault("MUJOCO_GL", "egl")

import torch  # noqa: E402

from objsearch_agents.house.config import HouseAgentConfig  # noqa: E402
from objsearch_agents.house.train import suite_training_houses  # noqa: E402
from objsearch_agents.house.train_run import HouseTrainRun  # noqa: E402

METHODS = ("a3c", "dqn", "hdqn", "hrl_grg")


def steps_per_s(method: str, houses, seconds: float) -> tuple[float, float]:
    config = replace(HouseAgentConfig(), method=method)
    with tempfile.TemporaryDirectory() as out:
        run = HouseTrainRun(config, out, houses)
        run.begin()
        while run.counters.env_steps < 2 * config.learning_starts:  # warm-up: replay filled, learning on
            run.step()
        start, wall, cpu = run.counters.env_steps, time.perf_counter(), time.process_time()
        while time.perf_counter() - wall < seconds:
            run.step()
        steps = run.counters.env_steps - start
        return steps / (time.perf_counter() - wall), steps / (time.process_time() - cpu)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=20.0, help="timed seconds per method")
    parser.add_argument("--json", action="store_true", help="end with one JSON line")
    args = parser.parse_args()
    torch.set_num_threads(1)
    houses = suite_training_houses("house-single", progress=False)
    out = {}
    for method in METHODS:
        out[method], out[f"{method}_cpu"] = (round(v) for v in steps_per_s(method, houses, args.seconds))
        print(f"{method:8s} {out[method]:>8,} env steps/s ({out[f'{method}_cpu']:,} per CPU second)")
    if args.json:
        print(json.dumps(out))


if __name__ == "__main__":
    main()
