"""The results table objsearch-eval prints explains itself: its last line says what every
column and row label means."""

from test_metrics import rec

from objsearch.eval.metrics import summarize
from objsearch.eval.results import TABLE_LEGEND, format_table


def results(records: list[dict], training_runs: list[dict] = ()) -> dict:
    return {
        "agent": "random",
        "suite": "gridworld",
        "episode_set_version": "gridworld-v1",
        "seeds": [1, 5],
        "config": {},
        "splits": {"seen-goals": summarize(records)},
        "training_runs": list(training_runs),
    }


RECORDS = [rec(True, 12, 6, seed, 0) for seed in (1, 5)] + [rec(False, 100, 30, seed, 1) for seed in (1, 5)]


def test_the_table_ends_with_a_legend_of_its_labels():
    lines = format_table(results(RECORDS)).splitlines()
    assert lines[-1] == TABLE_LEGEND
    assert lines[-2].startswith("suite gridworld")  # the footer stays just above it
    for label in ("SR", "SPL", "AS / MS", "95% CI", "std/seeds"):
        assert label in "\n".join(lines[:-1]), label  # a label of the table...
        assert f"{label}:" in lines[-1], label  # ...is explained in the legend
    assert "successful episodes only" in lines[-1]  # why a weak agent's MS is below the oracle's


def test_the_legend_explains_std_over_runs_when_the_table_has_it():
    records = [{**r, "training_run": run} for run in (1, 2) for r in RECORDS]
    runs = [{"seed": 1}, {"seed": 2}]
    table = format_table(results(records, runs))
    assert "\n  std/runs " in table and "std/runs:" in table.splitlines()[-1]
    assert "std/runs" not in format_table(results(RECORDS))


def test_the_spread_over_one_seed_is_not_a_number():
    one = [r for r in RECORDS if r["seed"] == 1]
    line = next(x for x in format_table({**results(one), "seeds": [1]}).splitlines() if "std/seeds" in x)
    assert line.split("|")[1].split() == ["n/a", "n/a"]  # not "0.00": one seed has no spread
    line = next(x for x in format_table(results(RECORDS)).splitlines() if "std/seeds" in x)
    assert "n/a" not in line
