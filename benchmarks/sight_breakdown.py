"""Why an agent failed on a large-house suite: never saw the target, saw it and did not reach it,
or STOPped away from it, from what the agent saw at every step.

    OBJSEARCH_CACHE=... MUJOCO_GL=egl .venv/bin/python benchmarks/sight_breakdown.py \\
        --suite house-large --agents frontier room_prior_frontier object_prior_frontier \\
        --out benchmarks/results/sight_house-large.json

The leaderboard's records hold success and steps only, so its tables split failures into STOP
away and out of steps. This replays each agent on the suite's test episodes through
``gymnasium.make("ObjSearch/Suite-v1", ...)`` (the episodes and seeds ``objsearch-eval`` plays:
the records must come out equal to the stored entry's, checked per episode) and watches the
observations the agent got: the first step at which the target covered at least 1 pixel of its
64 x 64 semantic frame, and the first at which it covered ``--pixels`` (default 5, the goal
rule's count) nearer than 1 m. Each failure is then:

* **never saw**: the target never covered a pixel of the agent's frame;
* **glimpsed**: it covered at least one pixel, never the goal rule's count within 1 m;
* **was near, no STOP**: the agent stood where the goal rule held (a goal pose's view) and ran
  out of steps without stopping there;
* **STOP away**: the agent stopped somewhere that is not a goal pose.

Ground-truth observations; one core, about the time of the evaluation itself.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

KINDS = ("success", "never_saw", "glimpsed", "near_no_stop", "stop_away")
NEAR_M = 1.0


def watch(suite: str, agent_name: str, pixels: int, split: str = "test", episodes: int | None = None) -> list[dict]:
    """Play ``agent_name`` on ``suite``'s ``split`` (its standard seeds) and note, per episode, when
    the target was first seen and first seen by the goal rule's count within ``NEAR_M``."""
    import gymnasium

    import objsearch  # noqa: F401  (registers the ids)
    from objsearch.eval.registry import make_agent

    env = gymnasium.make("ObjSearch/Suite-v1", suite=suite, split=split, episodes=episodes, mode="cached")
    agent = make_agent(agent_name, suite=suite)
    out = []
    for _ in range(env.unwrapped.num_episodes):
        obs, info = env.reset()
        task = env.unwrapped.agent_task
        agent.reset(task)
        target = int(obs["target"])
        seen = near = None
        steps, done = 0, False
        while not done:
            mask = obs["semantic"] == target
            if seen is None and mask.any():
                seen = steps
            if near is None and int((mask & (obs["depth"] < NEAR_M)).sum()) >= pixels:
                near = steps
            obs, _, terminated, truncated, step_info = env.step(agent.act(obs))
            steps, done = steps + 1, terminated or truncated
        success = bool(step_info["success"])
        out.append(
            {
                "episode_id": info["episode_id"],
                "seed": info["seed"],
                "success": success,
                "steps": steps,
                "first_seen": seen,
                "first_near": near,
                "stopped": bool(terminated and not success),
            }
        )
    env.close()
    return out


def kind(record: dict) -> str:
    """What became of an episode (``KINDS``)."""
    if record["success"]:
        return "success"
    if record["stopped"]:
        return "stop_away"
    if record["first_seen"] is None:
        return "never_saw"
    return "glimpsed" if record["first_near"] is None else "near_no_stop"


def check_against_entry(suite: str, agent: str, records: list[dict], board: Path) -> str:
    """``ok`` if ``records`` have the stored entry's success and steps episode by episode, else what differs."""
    path = board / "submissions" / suite / f"{agent}.json"
    if not path.exists():
        return f"no stored entry {path}"
    stored = {
        (r["seed"], r["episode_id"]): (r["success"], r["steps"])
        for r in json.loads(path.read_text())["episodes"]
        if r["split"] == "test"
    }
    ours = {(r["seed"], r["episode_id"]): (r["success"], r["steps"]) for r in records}
    differ = [key for key in ours if stored.get(key) != ours[key]]
    return "ok" if not differ else f"{len(differ)} episodes differ from {path}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--suite", default="house-large")
    parser.add_argument("--agents", nargs="+", default=["frontier", "room_prior_frontier", "object_prior_frontier"])
    parser.add_argument("--pixels", type=int, default=5, help="target pixels within 1 m that count as near")
    parser.add_argument("--leaderboard", default="leaderboard", help="folder of the stored entries to check against")
    parser.add_argument("--episodes", type=int, help="only the first N test episodes (a quick look)")
    parser.add_argument("--out", help="JSON to write (the per-episode notes and the summary)")
    args = parser.parse_args(argv)
    report = {"suite": args.suite, "pixels": args.pixels, "near_m": NEAR_M, "agents": {}}
    print("| agent | episodes | " + " | ".join(KINDS) + " | records |")
    print("|---" * (3 + len(KINDS)) + "|")
    for agent in args.agents:
        start = time.perf_counter()
        records = watch(args.suite, agent, args.pixels, episodes=args.episodes)
        counts = {k: sum(kind(r) == k for r in records) for k in KINDS}
        check = check_against_entry(args.suite, agent, records, Path(args.leaderboard))
        report["agents"][agent] = {"counts": counts, "check": check, "episodes": records}
        n = len(records)
        cells = " | ".join(f"{counts[k] / n:.2f}" for k in KINDS)
        print(f"| {agent} | {n} | {cells} | {check} |  ({time.perf_counter() - start:.0f} s)", flush=True)
    if args.out:
        from objsearch.fileio import write_json

        write_json(args.out, report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
