"""Running an ``objsearch reproduce`` plan (``reproduce_plan.Plan``): which steps are done, and
each step, here or as a Ray task. Every step reuses a command's own function: ``objsearch
train``, ``evaluate``, ``objsearch leaderboard add``, ``verify`` and ``render``."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

from objsearch.errors import UserError
from objsearch.leaderboard.reproduce_plan import Plan, Step

REMOTE = ("train", "eval")  # the steps that --executor ray runs as Ray tasks


def is_done(plan: Plan, step: Step) -> bool:
    """Whether ``step``'s output is there and finished (so a rerun skips it)."""
    from objsearch.leaderboard.validate import content_sha256, load_submission, replay_count, replayed_of

    a = step.args
    if step.kind == "train":  # its weights, and finished: recorded here, or no training state kept (a shipped run)
        folder = Path(a["out"])
        return (folder / "policy.pt").is_file() and (plan.record(step).is_file() or not (folder / "state.pt").exists())
    if step.kind == "render" or not Path(a["results"]).is_file():
        return False
    results = load_submission(a["results"])
    if step.kind == "eval":
        return not any("error" in r for r in results["episodes"])
    if not Path(a["stored"]).is_file():
        return False
    stored = load_submission(a["stored"])
    same = content_sha256({k: v for k, v in stored.items() if k != "partial"}) == content_sha256(results)
    if step.kind == "add" or not same:
        return same
    replayed = replayed_of(stored)
    return replayed is not None and replayed[0] >= replay_count(stored, a["episodes"])


def execute(
    plan: Plan, executor: str = "local", address: str | None = None, workers: int | None = None, progress: bool = True
) -> None:
    """Run every step of ``plan`` that is not done, each after those it needs: here, or the
    training runs and evaluations as Ray tasks (``executor`` ray, on the cluster at ``address``
    or a local one of ``workers`` CPUs). Each finished step leaves its record (``Plan.record``)."""
    from objsearch.cluster import one_math_thread

    one_math_thread()  # small networks: more torch threads only fight whatever else runs
    todo = [step for step in plan.steps if not is_done(plan, step)]
    check_replacements([step for step in todo if step.kind == "add"])  # before hours of training, not after
    finished = {step.id for step in plan.steps} - {step.id for step in todo}
    _say(f"{plan.title}: {len(plan.steps)} steps, {len(finished)} done already, {len(todo)} to run ({executor})")
    if executor == "ray":
        _execute_ray(plan, todo, finished, address, workers, progress)
    else:
        for i, step in enumerate(todo):
            _say(f"[{i + 1}/{len(todo)}] {step.id}")
            _finish(plan, step, run_step(step.kind, step.args, progress, workers or 1), executor)
    render = plan.steps[-1].args
    print(
        f"reproduced {plan.title}: entries in {render['leaderboard']}"
        + (f", the table in {render['table']}" if render["heading"] else "")
    )


def check_replacements(adds: list[Step]) -> None:
    """Refuse (``UserError``) add steps whose stored entry the plan did not write (``_own``),
    unless the plan has ``--replace``: a shipped, verified entry is never replaced unasked."""
    theirs = [
        a for a in (step.args for step in adds) if Path(a["stored"]).is_file() and not a["replace"] and not _own(a)
    ]
    if theirs:
        first = theirs[0]["stored"]
        more = f" (and {len(theirs) - 1} more: {', '.join(a['entry'] for a in theirs[1:])})" if len(theirs) > 1 else ""
        raise UserError(
            f"{first} holds an entry that this reproduction did not write ({_described(first)}){more}; it is left "
            "as it is: pass --out DIR to put the reproduction's entries in DIR/leaderboard, or --replace to replace it"
        )


def _own(a: dict) -> bool:
    """Whether the stored entry of the add step ``a`` holds what this plan's add step stored (its record)."""
    from objsearch.leaderboard.validate import content_sha256, load_submission

    try:
        written = json.loads(Path(a["record"]).read_text()).get("stored_sha256")
        return written is not None and written == content_sha256(load_submission(a["stored"]))
    except (OSError, ValueError, AttributeError, UserError):
        return False


def _described(path: str) -> str:
    """A stored entry in a few words: ``1500 episodes, verified by replay`` (or partial)."""
    from objsearch.leaderboard.validate import load_submission, replayed_of

    try:
        entry = load_submission(path)
    except UserError:
        return "not readable as an entry"
    words = [f"{len(entry.get('episodes') or [])} episodes", "verified by replay" if replayed_of(entry) else ""]
    return ", ".join(w for w in [*words, "partial" if entry.get("partial") else ""] if w)


def _execute_ray(plan: Plan, todo: list[Step], finished: set[str], address, workers, progress: bool) -> None:
    """``execute`` on Ray: every training run and evaluation whose needs are done runs as a
    task (1 CPU); add, verify and render run here, one at a time, while the tasks go on."""
    from objsearch.cluster import ray_session

    with ray_session(address, workers) as ray:
        task, running = ray.remote(num_cpus=1)(_remote_step), {}
        while todo or running:
            ready = [step for step in todo if all(need in finished for need in step.needs)]
            for step in ready:
                todo.remove(step)
                if step.kind in REMOTE:
                    running[task.remote(step.kind, step.args)] = step
                    _say(f"started {step.id} (a Ray task)")
            for step in [step for step in ready if step.kind not in REMOTE]:
                _say(step.id)
                _finish(plan, step, run_step(step.kind, step.args, progress), "ray")
                finished.add(step.id)
            if any(all(need in finished for need in step.needs) for step in todo):
                continue
            if not running:  # all done; or what is left needs a step that is neither done nor to run: a plan's fault
                if todo:
                    raise RuntimeError(f"steps {[step.id for step in todo]} wait for steps that no one runs")
                break
            (ref,), _ = ray.wait(list(running), num_returns=1)
            step = running.pop(ref)
            try:
                wall = ray.get(ref)
            except ray.exceptions.RayTaskError as err:
                if isinstance(err.cause, (UserError, KeyboardInterrupt)):
                    raise err.cause from None
                raise
            _finish(plan, step, wall, "ray")
            finished.add(step.id)


def _remote_step(kind: str, args: dict) -> float:
    """A Ray task: one step in a worker, with one math thread; its wall seconds."""
    from objsearch.cluster import one_math_thread

    one_math_thread()
    return run_step(kind, args, progress=False)


def _finish(plan: Plan, step: Step, wall_s: float, executor: str) -> None:
    """Record that ``step`` finished, and how long it took (``--dry-run`` shows it)."""
    from objsearch.fileio import write_json
    from objsearch.leaderboard.validate import content_sha256, load_submission

    record = {"step": step.id, "wall_s": round(wall_s, 1), "executor": executor}
    if step.kind == "add":  # what it stored: a later run of the plan may replace that, and nothing else, unasked
        record["stored_sha256"] = content_sha256(load_submission(step.args["stored"]))
    write_json(plan.record(step), record)
    _say(f"{step.id}: done in {wall_s:.1f} s")


def _say(line: str) -> None:
    print(f"reproduce: {line}", file=sys.stderr, flush=True)


def run_step(kind: str, args: dict, progress: bool = True, workers: int = 1) -> float:
    """Run one step in this process (``workers``: evaluation processes); its wall seconds.
    A step with ``checkpoints`` (a plan with ``--out``) runs with ``CHECKPOINTS_ENV`` set to
    them, so that the agents (and evaluation workers) find the runs the plan trained."""
    from objsearch.eval.agent import CHECKPOINTS_ENV, checkpoints_from

    start = time.monotonic()
    with checkpoints_from(args.get("checkpoints") or os.environ.get(CHECKPOINTS_ENV)):  # without: as it is
        {"train": _train, "eval": _eval, "add": _add, "verify": _verify, "render": _render}[kind](
            args, progress, workers
        )
    return time.monotonic() - start


def _command(argv: list[str]) -> int:
    """Run ``objsearch ARGV`` in this process (its function, as the command line parses it); its status."""
    from objsearch.cli import build_parser

    args = build_parser().parse_args(argv)
    return int(args.func(args) or 0)


def _train(a: dict, progress: bool, workers: int) -> None:
    """``objsearch train`` with the step's recipe; it resumes a run it finds in the folder."""
    from objsearch.fileio import atomic_write
    from objsearch.interrupt import Terminated

    out = Path(a["out"])
    out.mkdir(parents=True, exist_ok=True)
    with atomic_write(out / "command.txt") as f:
        f.write(a["command"] + "\n")
    status = _command(["train", *a["argv"], *([] if progress else ["--quiet"])])
    if status:
        saved = f"training run {a['suite']}/{a['agent']} seed {a['seed']} stopped, its checkpoint in {out}; rerun the same command to resume"
        raise (Terminated if status == 143 else KeyboardInterrupt)(saved)


def _eval(a: dict, progress: bool, workers: int) -> None:
    """``objsearch-eval --out RESULTS``: it resumes its episodes, and plays again those of a
    finished run that ended in an error (``--retry-failed``)."""
    from objsearch.eval.config import EvalConfig
    from objsearch.eval.runner import evaluate

    config = EvalConfig(
        agent=a["agent"], suite=a["suite"], splits=tuple(a["splits"]), seeds=tuple(a["seeds"]),
        checkpoint=a["checkpoint"], suite_config=dict(a["suite_config"]),
    )  # fmt: skip
    retry = Path(a["results"]).is_file()
    results = evaluate(config, workers, progress, out=a["results"], batch=a["batch"], retry_failed=retry)
    failed = sum("error" in r for r in results["episodes"])
    if failed:
        raise UserError(
            f"{failed} episode(s) of {a['agent']} on {a['suite']} ended in an agent error ({a['results']}); rerun to play them again"
        )


def _add(a: dict, progress: bool, workers: int) -> None:
    """``objsearch leaderboard add`` (``--partial`` for results of some splits or seeds), with
    ``--replace`` only where the plan may replace the stored entry: it wrote it, or was given
    ``--replace``; a partial entry takes a full one's place only with ``--replace``."""
    from objsearch.leaderboard.validate import check_submission, load_submission

    results = load_submission(a["results"])
    partial = bool(check_submission(results)) and not check_submission({**results, "partial": True})
    stored = Path(a["stored"])
    replacing = stored.is_file()
    if replacing:
        check_replacements([Step("add", a["entry"], args=a)])
        old = load_submission(stored)
        if partial and not old.get("partial") and not a["replace"]:
            raise UserError(
                f"{stored} is full ({_described(stored)}); this reproduction's entry is partial "
                f"({len(results['episodes'])} episodes: some splits, seeds or settings) and would take its place: "
                "pass --out DIR to keep it apart, or --replace to replace the full one"
            )
        print(f"reproduce: replacing {stored} ({_described(stored)})", file=sys.stderr)
    flags = ["--name", a["entry"], "--create"] + ["--replace"] * replacing + ["--partial"] * partial
    _command(["leaderboard", "--dir", a["leaderboard"], "add", a["results"], *flags])


def _verify(a: dict, progress: bool, workers: int) -> None:
    """``objsearch leaderboard verify ENTRY`` (``--episodes K`` if the plan sets it)."""
    episodes = [] if a["episodes"] is None else ["--episodes", str(a["episodes"])]
    _command(["leaderboard", "--dir", a["leaderboard"], "verify", a["stored"], *episodes])


def _render(a: dict, progress: bool, workers: int) -> None:
    """``objsearch leaderboard render``, and the table's section of ``paper_tables.md`` over
    every stored entry, partial ones included, in the plan's table file."""
    from objsearch.fileio import atomic_write
    from objsearch.leaderboard.render import render_paper_tables, stored_submissions

    _command(["leaderboard", "--dir", a["leaderboard"], "render"])
    if not a["heading"]:
        return
    entries = stored_submissions(a["leaderboard"])
    lines = render_paper_tables(entries).splitlines()
    start = next((i for i, line in enumerate(lines) if line.startswith(a["heading"])), None)
    if start is None:  # e.g. Table 4 with random's entry alone: every row is read against it
        print(f"{a['heading'][3:]} has no row yet: {a['leaderboard']} holds none of its methods' entries")
        return
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    partial = sorted(f"{r['suite']}/{name}" for name, r in entries if r.get("partial"))
    partial = f"; partial (some splits, seeds or settings): {', '.join(partial)}" if partial else ""
    note = f"From the entries of {a['leaderboard']}{partial}."
    with atomic_write(a["table"]) as f:
        f.write("\n".join([lines[start], "", note, *lines[start + 1 : end]]).rstrip() + "\n")
