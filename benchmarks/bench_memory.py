"""Peak memory of evaluations (issue 29's goal: at most 2 GB for any shipped suite, cold or warm).

    .venv/bin/python benchmarks/bench_memory.py [--suite house-multi --suite house-gen]
        [--agent random] [--batch 32] [--seeds 1] [--split NAME] [--case warm --case cold]
        [--cache-dir DIR] [--json]

Each case runs ``objsearch-eval --agent A --suite S --batch B --quiet`` (or, for ``build``,
``objsearch cache build --suite S``) in a child process and samples it (and its children)
every ``--interval`` seconds: ``/proc/<pid>/smaps_rollup`` (``Rss``, ``Pss``, ``Pss_Anon``,
``Pss_File``) and ``/proc/<pid>/status`` (``RssAnon``, ``RssFile``), keeping each figure's
peak over the run (summed over the process tree at each sample); at the end the child's
``ru_maxrss`` (``os.wait4``: the largest of the tree's processes, which sampling cannot miss).

Cases:

* ``warm``: the caches already built, in ``--cache-dir`` (default: the usual cache folder);
* ``cold``: an empty temporary cache folder, so the run builds every cache it plays (removed after);
* ``build``: ``objsearch cache build --suite S`` into an empty temporary folder (removed after);
* ``predicted``: ``--observation predicted`` with a temporary folder holding links to the
  warm gt caches, so the run computes every house's predictions (removed after).

``--seeds`` / ``--split`` restrict the evaluation (default: seed 1, every split, to keep
it short); the suite's houses are all played with any seed, and the full protocol
(``--seeds 1,5,13,45,99``, 5x the time) peaks where one seed does (benchmarks/RESULTS.md). With ``--json`` the last line is one JSON
object: ``{"<suite>/<case>": {"command": ..., "wall_s", "peak_rss_mb", "peak_pss_mb",
"peak_pss_anon_mb", "peak_pss_file_mb", "peak_rss_anon_mb", "peak_rss_file_mb",
"ru_maxrss_mb", "rc"}}`` (MB = 10^6 bytes).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = ("warm", "cold", "build", "predicted")
ROLLUP = {"Rss": "rss", "Pss": "pss", "Pss_Anon": "pss_anon", "Pss_File": "pss_file"}
STATUS = {"RssAnon": "rss_anon", "RssFile": "rss_file"}


def tree(pid: int) -> list[int]:
    """``pid`` and its descendants (from ``/proc/<pid>/task/*/children``)."""
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        try:
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children") as f:
                    todo += [int(c) for c in f.read().split()]
        except OSError:
            pass
    return out


def sample(pid: int) -> dict[str, int]:
    """Memory of the process tree under ``pid`` now, in kB, by figure name."""
    total = dict.fromkeys([*ROLLUP.values(), *STATUS.values()], 0)
    for p in tree(pid):
        for path, names in ((f"/proc/{p}/smaps_rollup", ROLLUP), (f"/proc/{p}/status", STATUS)):
            try:
                with open(path) as f:
                    for line in f:
                        key, _, rest = line.partition(":")
                        if key in names:
                            total[names[key]] += int(rest.split()[0])
            except (OSError, ValueError, IndexError):
                pass  # the process ended between listing and reading
    return total


def measure(command: list[str], interval: float, env: dict | None = None) -> dict:
    """Run ``command``, sampling its memory; its peak figures (MB), wall time and exit status."""
    start = time.perf_counter()
    child = subprocess.Popen(command, cwd=ROOT, env=env, stdout=subprocess.DEVNULL)
    peak: dict[str, int] = {}
    while True:
        now = sample(child.pid)
        for key, kb in now.items():
            peak[key] = max(peak.get(key, 0), kb)
        done, status, usage = os.wait4(child.pid, os.WNOHANG)
        if done:
            break
        time.sleep(interval)
    child.returncode = os.waitstatus_to_exitcode(status)
    out = {"command": " ".join(command), "wall_s": round(time.perf_counter() - start, 1), "rc": child.returncode}
    out.update({f"peak_{key}_mb": round(kb * 1024 / 1e6) for key, kb in sorted(peak.items())})
    out["ru_maxrss_mb"] = round(usage.ru_maxrss * 1024 / 1e6)  # kB on Linux
    return out


def link_caches(source: Path, target: Path) -> None:
    """Fill ``target`` with links to the gt caches of ``source`` (not the predicted ones)."""
    for folder in source.iterdir():
        if folder.is_dir() and not folder.name.startswith(".") and "-pred-" not in folder.name:
            (target / folder.name).symlink_to(folder)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--suite", action="append", help="house suite (repeatable; default: house-multi, house-gen)")
    parser.add_argument("--case", action="append", choices=CASES, help="repeatable (default: warm, cold)")
    parser.add_argument("--agent", default="random", help="agent to evaluate (default: random)")
    parser.add_argument("--batch", type=int, default=32, help="episodes in lockstep (default: 32)")
    parser.add_argument("--seeds", default="1", help="evaluation seeds (default: 1)")
    parser.add_argument("--split", action="append", help="split to run (repeatable; default: all)")
    parser.add_argument("--cache-dir", help="the warm caches (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)")
    parser.add_argument("--interval", type=float, default=0.2, help="seconds between samples (default: 0.2)")
    parser.add_argument("--json", action="store_true", help="end with one JSON line")
    args = parser.parse_args()
    from objsearch.sim.cache import default_cache_dir

    warm = Path(args.cache_dir) if args.cache_dir else default_cache_dir()
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    bin_dir = Path(sys.executable).parent
    results = {}
    for suite in args.suite or ["house-multi", "house-gen"]:
        for case in args.case or ["warm", "cold"]:
            with tempfile.TemporaryDirectory(prefix="bench-memory-", dir=warm.parent) as tmp:
                cache_dir = warm if case == "warm" else Path(tmp)
                if case == "predicted":
                    link_caches(warm, cache_dir)
                if case == "build":
                    command = [str(bin_dir / "objsearch"), "cache", "build", "--suite", suite]
                else:
                    command = [str(bin_dir / "objsearch-eval"), "--agent", args.agent, "--suite", suite]
                    command += ["--batch", str(args.batch), "--seeds", args.seeds, "--quiet"]
                    command += [arg for split in args.split or [] for arg in ("--split", split)]
                    if case == "predicted":
                        command += ["--observation", "predicted"]
                command += ["--cache-dir", str(cache_dir)]
                result = measure(command, args.interval, env)
                if case != "warm":
                    shutil.rmtree(tmp, ignore_errors=True)
            results[f"{suite}/{case}"] = result
            print(
                f"{suite}/{case}: peak RSS {result['peak_rss_mb']} MB (file {result['peak_rss_file_mb']}, "
                f"anon {result['peak_rss_anon_mb']}), PSS {result['peak_pss_mb']} MB, ru_maxrss "
                f"{result['ru_maxrss_mb']} MB, {result['wall_s']} s, rc {result['rc']}",
                flush=True,
            )
    if args.json:
        print(json.dumps(results))


if __name__ == "__main__":
    main()
