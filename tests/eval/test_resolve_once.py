"""An evaluation resolves its config once (``objsearch.eval.plan.resolve``), then the executors
only play the plan: the suite, the agent's class, its training runs and their checkpoints are
each looked up once, all inside ``resolve``, never by an executor or worker."""

import ast
import pickle
import sys
from collections import Counter
from pathlib import Path

import pytest

from objsearch.eval import plan as plan_module
from objsearch.eval import registry, runner, suites
from objsearch.eval.config import EvalConfig
from objsearch.eval.plan import EvalPlan, resolve
from objsearch.eval.runner import evaluate
from objsearch.eval.worker import Worker
from tests.eval.agents_for_tests import RunsAgent

AGENT = "tests.eval.agents_for_tests:RunsAgent"  # three training runs on the grid world
CONFIG = EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1, 5), episodes=3)
EVAL = Path(plan_module.__file__).parent


def inside_resolve() -> bool:
    """Whether a caller on the stack is ``plan.resolve``."""
    frame = sys._getframe(2)
    while frame is not None:
        if frame.f_code.co_name == "resolve" and frame.f_code.co_filename == plan_module.__file__:
            return True
        frame = frame.f_back
    return False


@pytest.fixture
def lookups(monkeypatch):
    """Counts of the look-ups an evaluation makes (suite, agent class, training runs, agent
    builds); a look-up outside ``resolve`` fails the test."""
    calls, outside = Counter(), []

    def spy(module, name):
        real = getattr(module, name)

        def counted(*args, **kwargs):
            calls[name] += 1
            if not inside_resolve():
                outside.append(name)
            return real(*args, **kwargs)

        monkeypatch.setattr(module, name, counted)

    for name in ("make_suite", "check_splits", "resolve_agent", "check_supports", "listed_runs", "check_run_choice"):
        spy(plan_module, name)
    spy(suites, "suite_class")  # every suite look-up by name: make_suite, suite_world, suite_protocol
    spy(registry, "_import_target")  # every agent class import
    real_runs = RunsAgent.training_runs.__func__
    monkeypatch.setattr(
        RunsAgent,
        "training_runs",
        classmethod(lambda cls, suite: calls.update(["training_runs"]) or real_runs(cls, suite)),
    )
    real_for_suite = RunsAgent.for_suite.__func__

    def for_suite(cls, suite, checkpoint=None):
        calls["for_suite" if inside_resolve() else "for_suite played"] += 1
        return real_for_suite(cls, suite, checkpoint)

    monkeypatch.setattr(RunsAgent, "for_suite", classmethod(for_suite))
    yield calls
    assert not outside, f"looked up outside resolve: {outside}"


@pytest.mark.parametrize("batch", [1, 4])
def test_evaluate_resolves_each_part_once(lookups, monkeypatch, batch):
    given = []
    real_run_local = runner.run_local
    monkeypatch.setattr(
        runner, "run_local", lambda plan, play, *a: given.append((plan, play)) or real_run_local(plan, play, *a)
    )

    results = evaluate(CONFIG, progress=False, batch=batch)

    for name in ("make_suite", "check_splits", "resolve_agent", "check_supports", "listed_runs", "training_runs"):
        assert lookups[name] == 1, (name, lookups)
    assert lookups["_import_target"] == 1  # the agent's module, once
    assert lookups["for_suite"] == 3  # each training run's agent built once when resolved (refused there if it must be)
    # playing builds agents from the plan's factory (one a run, or one a lockstep slot), with no look-up
    assert lookups["for_suite played"] == 3 * min(batch, 6)  # 6 units a run
    assert [play for _, play in given] == [0, 1, 2] and all(isinstance(plan, EvalPlan) for plan, _ in given)
    assert len({id(plan) for plan, _ in given}) == 1  # one plan for every run
    assert [run["seed"] for run in results["training_runs"]] == [0, 1, 2]


def test_a_plan_says_what_each_run_plays():
    plan = resolve(CONFIG, out="r.json")
    assert plan.several and plan.recorded == plan.config and plan.config.splits == ("unseen-goals",)
    assert len(plan.units) == 2 * 3 and plan.units[0] == ("unseen-goals", 1, 0)
    assert [p.config.training_run for p in plan.plays] == [0, 1, 2]
    assert [p.agent.checkpoint for p in plan.plays] == [p.loaded for p in plan.plays] == ["run-0", "run-1", "run-2"]
    assert [p.partial for p in plan.plays] == [f"r.json.run{seed}.partial.jsonl" for seed in (0, 1, 2)]
    one = resolve(CONFIG.__class__(**{**CONFIG.__dict__, "training_run": 2}))
    assert not one.several and one.recorded.training_run == 2 and one.plays[0].agent.checkpoint == "run-2"


def test_a_worker_process_plays_the_portable_plan_alike(lookups):
    plan = resolve(CONFIG)
    here = Worker(plan, 1).run_chunk(list(plan.units))
    portable = pickle.loads(pickle.dumps(plan.portable()))  # what a pool process or a Ray actor gets
    assert portable.suite is None and portable.units == () and portable.plays[1].agent.cls is None
    lookups.clear()
    with pytest.MonkeyPatch.context() as mp:  # a worker process rebuilds the suite and imports the class: allowed
        mp.setattr(sys.modules[__name__], "inside_resolve", lambda: True)
        there = Worker(portable, 1).run_chunk(list(plan.units))
    assert there == here


def test_the_executors_import_nothing_that_resolves():
    """The executors get a plan: they never import the registry or the training runs, and
    from the suites only the ``Episode`` record."""
    for name in ("executors.py", "worker.py", "lockstep.py", "episode.py"):
        tree = ast.parse((EVAL / name).read_text())
        imported = [
            (node.module, alias.name)
            for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom)
            for alias in node.names
        ]
        imported += [
            (alias.name, "") for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names
        ]
        bad = [
            f"{module}.{what}"
            for module, what in imported
            if module in ("objsearch.eval.registry", "objsearch.eval.runs")
            or (module == "objsearch.eval.suites" and what != "Episode")
        ]
        assert not bad, f"{name} imports {bad}: resolve in objsearch/eval/plan.py, play the plan here"
