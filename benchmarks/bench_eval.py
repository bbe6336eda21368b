"""Evaluation throughput: episodes per second of the harness, batched (``--batch N``) against
one episode at a time, in the same run, on one worker.

    .venv/bin/python benchmarks/bench_eval.py [--batch 64] [--json]

Measured: the shipped ``hrl_grg`` and ``dqn`` on the grid world (split ``all-goals``, seed
1: 100 episodes; the full protocol is 15 x that), and ``random`` and the shipped
house-single ``hrl_grg`` on ``house-single`` (split ``seen-goals``, seed 1: 100 episodes;
the full protocol is 10 x that). Each pair also checks that the records are identical.
With ``--json`` the last line is one JSON object: for each ``<suite>/<agent>``,
``{"batched": episodes/s, "single": episodes/s, "speedup": x, "identical": bool}``.
"""

from __future__ import annotations

import argparse
import json
import os
import time

os.environ.setdefault("MUJOCO_GL", "egl")

from objsearch.eval.runner import EvalConfig, evaluate  # noqa: E402

CASES = (("gridworld", "hrl_grg", "all-goals"), ("gridworld", "dqn", "all-goals"),
         ("house-single", "random", "seen-goals"), ("house-single", "hrl_grg", "seen-goals"))


def measure(suite: str, agent: str, split: str, batch: int) -> dict:
    config = EvalConfig(agent=agent, suite=suite, splits=(split,), seeds=(1,))
    evaluate(config, progress=False, batch=batch)  # warm-up: caches, tables, imports
    out, records = {}, {}
    for label, n in (("batched", batch), ("single", 1)):
        start = time.perf_counter()
        results = evaluate(config, progress=False, batch=n)
        out[label] = round(len(results["episodes"]) / (time.perf_counter() - start), 2)
        records[label] = results["episodes"]
    out["speedup"] = round(out["batched"] / out["single"], 1)
    out["identical"] = records["batched"] == records["single"]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=64, help="episodes in lockstep (default: 64)")
    parser.add_argument("--json", action="store_true", help="end with one JSON line")
    args = parser.parse_args()
    figures = {}
    for suite, agent, split in CASES:
        figures[f"{suite}/{agent}"] = m = measure(suite, agent, split, args.batch)
        print(f"{suite:13s} {agent:8s} {m['batched']:>8.1f} episodes/s batched, {m['single']:>7.1f} one at a time "
              f"({m['speedup']}x), records identical: {m['identical']}")
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
