"""What each rule of frontier's earned STOP buys, on predicted observations, validation splits only.

    OBJSEARCH_CACHE=... MUJOCO_GL=egl .venv/bin/python benchmarks/stop_rules.py \\
        --variant "one frame:stop_views=1,stop_margin=0,stop_share=0" \\
        --variant "two cells:stop_views=2,stop_margin=0,stop_share=0" \\
        --out benchmarks/results/stop_rules.json

Each ``--variant "LABEL:field=value,field=value"`` plays ``frontier`` with those
``FrontierConfig`` fields (``agents/baselines/frontier.py``; ``stop_views``, ``stop_match``,
``stop_margin``, ``stop_pixels``, ``stop_share`` and ``vote_range`` are the earned STOP's; fields
not named keep the defaults, the chosen rule) on the suite's validation splits with the
perception network's predictions, and reports per split SR, SPL and how its failures split:

* **false STOP**: the agent called STOP where the goal rule does not hold (the episode ended
  before ``max_steps``, unsuccessfully);
* **out of steps**: it never called STOP.

The test splits are never played here: rules are chosen on validation, then the chosen agent
is evaluated on test with ``objsearch-eval`` (docs/frontier.md).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")


def parse_variant(text: str) -> tuple[str, dict]:
    """``"LABEL:field=value,..."`` -> (label, FrontierConfig overrides); values are numbers."""
    from objsearch.errors import UserError
    from objsearch_agents.baselines.frontier import FrontierConfig

    label, _, fields = text.partition(":")
    known = {f.name: f.type for f in dataclasses.fields(FrontierConfig)}
    changes = {}
    for item in filter(None, fields.split(",")):
        key, _, value = item.partition("=")
        if key not in known:
            raise UserError(f"--variant {text!r}: {key!r} is not a FrontierConfig field (one of {', '.join(known)})")
        try:
            changes[key] = int(value) if known[key] in (int, "int") else float(value)
        except ValueError:
            raise UserError(f"--variant {text!r}: {key}={value!r} is not a number") from None
    if not label:
        raise UserError(f"--variant {text!r}: give a label before the colon, e.g. 'two cells:stop_views=2'")
    return label, changes


def failure_split(records: list[dict], max_steps: int) -> dict:
    """SR and the failures as false STOPs and out-of-steps, from the records alone."""
    failed = [r for r in records if not r["success"]]
    false_stops = sum(r["steps"] < max_steps for r in failed)
    return {
        "episodes": len(records),
        "success": len(records) - len(failed),
        "false_stop": false_stops,
        "out_of_steps": len(failed) - false_stops,
    }


def run(suite: str, label: str, changes: dict, seeds: list[int], splits: list[str]) -> dict:
    import objsearch
    from objsearch_agents.baselines.frontier import FrontierAgent, FrontierConfig

    agent = FrontierAgent()
    agent.config = dataclasses.replace(FrontierConfig(), **changes)
    start = time.perf_counter()
    results = objsearch.evaluate(agent, suite, seeds=seeds, split=splits, batch=32, observation="predicted")
    max_steps = results["config"]["suite_config"]["max_steps"]
    out = {"label": label, "config": changes, "seconds": round(time.perf_counter() - start, 1), "splits": {}}
    for split in splits:
        records = [r for r in results["episodes"] if r["split"] == split]
        row = failure_split(records, max_steps)
        row.update(sr=results["splits"][split]["sr"], spl=results["splits"][split]["spl"])
        out["splits"][split] = row
    return out


def table(rows: list[dict]) -> str:
    lines = [
        "| rule | split | SR | SPL | false STOPs | out of steps | false STOPs / failures |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        for split, s in row["splits"].items():
            failures = s["episodes"] - s["success"]
            share = f"{s['false_stop'] / failures:.2f}" if failures else "-"
            lines.append(
                f"| {row['label']} | {split} | {s['sr']:.3f} | {s['spl']:.3f} | {s['false_stop']} | {s['out_of_steps']} | {share} |"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    from objsearch.errors import UserError

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--suite", default="house-gen-v2-objectnav")
    parser.add_argument("--variant", action="append", required=True, help="LABEL:field=value,... (repeatable)")
    parser.add_argument("--seeds", default="1", help="comma-separated evaluation seeds (default: 1)")
    parser.add_argument("--splits", default="val-seen,val-unseen", help="validation splits only (default: both)")
    parser.add_argument("--out", help="JSON to write (rows are added to it when it exists)")
    args = parser.parse_args(argv)
    try:
        splits = args.splits.split(",")
        if any(s.startswith("test") for s in splits):
            raise UserError(
                f"--splits {args.splits}: rules are chosen on validation splits; test is for the chosen agent"
            )
        variants = [parse_variant(v) for v in args.variant]
        seeds = [int(s) for s in args.seeds.split(",")]
    except (UserError, ValueError) as e:
        print(f"stop_rules: {e}", file=sys.stderr)
        return 2
    rows = []
    if args.out and Path(args.out).exists():
        rows = json.loads(Path(args.out).read_text())["rows"]
    for label, changes in variants:
        row = run(args.suite, label, changes, seeds, splits)
        row.update(suite=args.suite, seeds=seeds)
        rows = [r for r in rows if r["label"] != label] + [row]
        print(table([row]).splitlines()[-len(splits) :], flush=True)
        if args.out:
            from objsearch.fileio import write_json

            write_json(args.out, {"command": " ".join(sys.argv), "rows": rows})
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
