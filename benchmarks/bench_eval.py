"""Evaluation throughput: episodes per second of the harness, batched (``--batch N``) against
one episode at a time, in the same run, on one worker.

    .venv/bin/python benchmarks/bench_eval.py [--batch 64] [--suite gridworld] [--json]

Measured: the shipped ``hrl_grg`` and ``dqn`` on the grid world (split ``all-goals``, seed
1: 100 episodes; the full protocol is 15 x that), and ``random`` and the shipped
house-single ``hrl_grg`` on ``house-single`` (split ``seen-goals``, seed 1: 100 episodes;
the full protocol is 10 x that). Each pair also checks that the records are identical.
Then the wall time of one learned agent's full protocol (every split, the paper's 5 seeds),
as ``objsearch-eval --batch N --workers 2`` runs it, start-up included: ``hrl_grg`` on the
grid world (1,500 episodes; one at a time and ``--batch 64``) and on ``house-single``
(1,000; ``--batch 32``).
With ``--json`` the last line is one JSON object: for each ``<suite>/<agent>``,
``{"batched": episodes/s, "single": episodes/s, "speedup": x, "identical": bool}``, and
``"protocol": {"<suite>/<agent>/batch<N>": {"episodes": n, "wall_s": s}}``.
``--suite gridworld`` (repeatable) measures only that suite's cases (the house ones take
minutes).
"""

from __future__ import annotations

import argparse
import json
import os
import time

os.environ.setdefault("MUJOCO_GL", "egl")

from objsearch.eval.runner import EvalConfig, evaluate  # noqa: E402

PROTOCOL = (("gridworld", "hrl_grg", 1), ("gridworld", "hrl_grg", 64), ("house-single", "hrl_grg", 32))
CASES = (
    ("gridworld", "hrl_grg", "all-goals"),
    ("gridworld", "dqn", "all-goals"),
    ("house-single", "random", "seen-goals"),
    ("house-single", "hrl_grg", "seen-goals"),
)


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
    suites = sorted({case[0] for case in CASES})
    parser.add_argument(
        "--suite",
        action="append",
        choices=suites,
        help=f"measure only this suite's cases (repeatable; default: all of {', '.join(suites)})",
    )
    args = parser.parse_args()
    chosen = set(args.suite or suites)
    figures = {}
    for suite, agent, split in CASES:
        if suite not in chosen:
            continue
        figures[f"{suite}/{agent}"] = m = measure(suite, agent, split, args.batch)
        print(
            f"{suite:13s} {agent:8s} {m['batched']:>8.1f} episodes/s batched, {m['single']:>7.1f} one at a time "
            f"({m['speedup']}x), records identical: {m['identical']}"
        )
    figures["protocol"] = {}
    for suite, agent, batch in PROTOCOL:
        if suite not in chosen:
            continue
        start = time.perf_counter()
        results = evaluate(EvalConfig(agent=agent, suite=suite), progress=False, workers=2, batch=batch)
        wall = round(time.perf_counter() - start, 1)
        figures["protocol"][f"{suite}/{agent}/batch{batch}"] = {"episodes": len(results["episodes"]), "wall_s": wall}
        print(
            f"{suite:13s} {agent:8s} full protocol: {len(results['episodes'])} episodes in {wall} s "
            f"(--workers 2 --batch {batch})"
        )
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
