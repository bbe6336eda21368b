"""Every field of EvalConfig reaches the results: evaluate fills in some, keeps the rest."""

import dataclasses
from dataclasses import dataclass

from objsearch import digests
from objsearch.eval import runner
from objsearch.eval.config import EvalConfig
from objsearch.eval.runner import evaluate
from objsearch_agents.baselines.oracle import OracleAgent


class LoadingOracle(OracleAgent):
    """An oracle that takes a checkpoint (any file) and names its digest, as trained agents do."""

    def load(self, path):
        self.weights_sha256 = digests.of_files([path])


@dataclass(frozen=True)
class ConfigWithANewField(EvalConfig):
    """EvalConfig with one more field, as a later change would add one."""

    new_field: str = "default"


# What evaluate sets: the splits it runs, the suite's full options, the loaded weights' digest.
FILLED_IN = {"splits", "suite_config", "weights_sha256"}
# Fields that exclude one that this test sets, with the test that follows them instead.
EXCLUSIVE = {"training_run": "checkpoint (tests/eval/test_training_runs.py: the run's seed reaches the results)"}


def a_config_unlike_the_defaults(checkpoint) -> ConfigWithANewField:
    values = dict(
        agent="test_eval_config:LoadingOracle",
        suite="gridworld",
        splits=("unseen-goals",),
        seeds=(5,),
        checkpoint=str(checkpoint),
        suite_config={"max_steps": 77},
        step_time_limit=3.5,
        weights_sha256="a stale digest",
        episodes=4,
        checkpoints=str(checkpoint.parent),  # as a replay of an entry recording its folder gives it: kept
        new_field="kept",
    )
    config = ConfigWithANewField(**values)
    defaults = ConfigWithANewField(agent="x")
    for f in dataclasses.fields(ConfigWithANewField):
        if f.name in EXCLUSIVE:
            continue
        assert f.name in values, f"give EvalConfig's new field {f.name!r} a value in this test"
        if f.name not in ("agent", "suite"):  # suite: the grid world is the quick one (and the default)
            assert getattr(config, f.name) != getattr(defaults, f.name), f"{f.name}: pick a value unlike the default"
    return config


def test_every_field_survives_evaluate(tmp_path, monkeypatch):
    checkpoint = tmp_path / "weights.bin"
    checkpoint.write_bytes(b"weights")
    config = a_config_unlike_the_defaults(checkpoint)
    ran = []
    real_play_units = runner.play_units
    monkeypatch.setattr(
        runner,
        "play_units",
        lambda plan, play, *args, **kwargs: (
            ran.append(plan.plays[play].config) or real_play_units(plan, play, *args, **kwargs)
        ),
    )

    results = evaluate(config, progress=False, out=tmp_path / "results.json")

    (used,) = ran
    assert type(used) is ConfigWithANewField
    for f in dataclasses.fields(used):
        if f.name not in FILLED_IN:
            assert getattr(used, f.name) == getattr(config, f.name), f.name
    assert used.splits == ("unseen-goals",)
    assert used.suite_config["max_steps"] == 77 and {"maps", "tasks"} <= used.suite_config.keys()
    assert used.weights_sha256 == digests.of_files([checkpoint])
    assert results["config"] == used.to_json()
    assert results["config"]["new_field"] == "kept" and results["config"]["step_time_limit"] == 3.5
