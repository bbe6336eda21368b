"""Training-loop throughput of the grid-world agents: environment steps per second of each
agent's real main-phase training step (acting, env, replay, learning) with the paper's
config (64 envs, one update per level per 10 transitions, batch 64), against another
checkout of the code (``--reference``) in the same run, interleaved.

    git worktree add /tmp/oldtree 172a729      # the code before issue 16
    .venv/bin/python benchmarks/bench_grid_train.py --reference /tmp/oldtree [--seconds 15] [--rounds 2] [--json]

Every measurement runs in its own subprocess (this checkout, or the ``--reference`` one
imported ahead of the installed package), after a warm-up that fills the replay memories
past ``learning_starts`` (no pretraining phase: its weights do not change the speed). The
rounds alternate new and reference, agent by agent, so both see the same load on a busy
machine. With ``--json`` the last line is one JSON object ``{"new": {AGENT: steps/s},
"new_cpu": {AGENT: steps per CPU second}, "new_learn_share": {AGENT: fraction of the CPU
time spent in the gradient updates}, "reference": ..., "reference_cpu": ...,
"reference_learn_share": ...}`` (medians over rounds; CPU seconds change less on a busy
machine).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

AGENTS = ("dqn", "hdqn", "hrl_grg")  # each agent's loop is its method's (the ablations share hrl_grg's)


def measure(agent: str, seconds: float) -> dict:
    """Steps/s of ``agent``'s training loop, in this process, with whatever code it imports."""
    from dataclasses import replace

    import torch

    from objsearch.gridworld.dataset import train_maps
    from objsearch_agents.gridworld import train as gridworld_train
    from objsearch_agents.gridworld.config import GridAgentConfig

    torch.set_num_threads(1)  # as ``gridworld.train.train`` sets it
    config = replace(GridAgentConfig(), method=agent, pretrain_episodes=0)
    with tempfile.TemporaryDirectory() as out:
        run = gridworld_train.TrainRun(config, Path(out), list(train_maps().values()))
        run.begin()
        need = max(config.learning_starts, config.batch_size)
        memories = [m for m in (run.low_replay, run.high_replay) if m is not None]
        while min(len(m) for m in memories) < need:  # warm-up: every level learning
            run.step()
        for _ in range(20):
            run.step()
        learn, learn_cpu = run._learn, [0.0]

        def timed_learn(transitions: int) -> None:  # the gradient updates' share of the loop
            t = time.process_time()
            learn(transitions)
            learn_cpu[0] += time.process_time() - t

        run._learn = timed_learn
        start, wall, cpu = run.counters["env_steps"], time.perf_counter(), time.process_time()
        while time.perf_counter() - wall < seconds:
            run.step()
        steps, cpu = run.counters["env_steps"] - start, time.process_time() - cpu
        return {
            "steps_s": steps / (time.perf_counter() - wall),
            "cpu_steps_s": steps / cpu,
            "learn_share": learn_cpu[0] / cpu,
        }


def _subprocess(agent: str, seconds: float, code: Path | None) -> dict:
    """Run ``measure`` in a fresh interpreter; ``code``: a checkout whose ``objsearch`` and
    ``agents`` are imported instead of the installed ones (None: this checkout)."""
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as shim:
        if code is not None:  # sys.path comes before the editable install's finder
            os.symlink(code / "objsearch", Path(shim) / "objsearch")
            os.symlink(code / "agents", Path(shim) / "objsearch_agents")
            env["PYTHONPATH"] = shim + os.pathsep + env.get("PYTHONPATH", "")
        cmd = [sys.executable, __file__, "--worker", agent, "--seconds", str(seconds)]
        out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=15.0, help="timed seconds per measurement")
    parser.add_argument("--rounds", type=int, default=2, help="measurements per agent and code")
    parser.add_argument("--agents", default=",".join(AGENTS), help="comma-separated subset of " + ",".join(AGENTS))
    parser.add_argument("--reference", type=Path, help="another checkout to measure in the same run (e.g. a worktree)")
    parser.add_argument("--json", action="store_true", help="end with one JSON line")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        print(json.dumps(measure(args.worker, args.seconds)))
        return
    codes = {"new": None} | ({"reference": args.reference.resolve()} if args.reference else {})
    agents = args.agents.split(",")
    runs = {(name, agent): [] for name in codes for agent in agents}
    for r in range(args.rounds):
        for agent in agents:
            for name, code in codes.items() if r % 2 == 0 else reversed(codes.items()):
                res = _subprocess(agent, args.seconds, code)
                runs[name, agent].append(res)
                print(
                    f"round {r + 1} {name:9s} {agent:8s} {res['steps_s']:8.0f} env steps/s "
                    f"({res['cpu_steps_s']:.0f} per CPU s, {res['learn_share']:.0%} of it in the updates)",
                    flush=True,
                )
    out = {}
    for name in codes:
        out[name] = {a: round(statistics.median(x["steps_s"] for x in runs[name, a])) for a in agents}
        out[name + "_cpu"] = {a: round(statistics.median(x["cpu_steps_s"] for x in runs[name, a])) for a in agents}
        out[name + "_learn_share"] = {
            a: round(statistics.median(x["learn_share"] for x in runs[name, a]), 3) for a in agents
        }
    for a in agents:
        line = f"{a:8s} new {out['new'][a]:7,} steps/s ({out['new_cpu'][a]:,}/CPU s)"
        if args.reference:
            ratio = out["new"][a] / max(out["reference"][a], 1)
            line += f"  reference {out['reference'][a]:7,} ({out['reference_cpu'][a]:,}/CPU s)  x{ratio:.2f}"
        print(line)
    if args.json:
        print(json.dumps(out))


if __name__ == "__main__":
    main()
