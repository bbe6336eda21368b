"""Bounded work: checkpoints are read only from regular files within a size limit, --batch and
--workers never exceed the episodes, and partial-results files with conflicting or wrong-typed
records are refused or repaired, never a traceback."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from objsearch.errors import UserError
from objsearch.eval import executors, runner
from objsearch.eval.runner import EvalConfig, evaluate
from objsearch.fileio import open_regular

BIN = Path(sys.executable).parent
CONFIG = EvalConfig(agent="oracle", splits=("unseen-goals",), seeds=(1,))


def objsearch_eval(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(BIN / "objsearch-eval"), *map(str, args)], capture_output=True, text=True, timeout=120, cwd=cwd
    )


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize("checkpoint", ["/dev/zero", "fifo"])
def test_a_checkpoint_that_is_not_a_regular_file_is_refused_at_once(tmp_path, checkpoint):
    if checkpoint == "fifo":
        checkpoint = tmp_path / "policy.pt"
        os.mkfifo(checkpoint)  # no writer: opening it for reading the usual way blocks forever
    out = objsearch_eval(
        "--agent", "dqn", "--suite", "gridworld", "--split", "unseen-goals", "--seeds", "1", "--quiet",
        "--checkpoint", checkpoint,
    )  # fmt: skip
    line = one_line(out.stderr)
    assert out.returncode == 2 and f"checkpoint {checkpoint} is a " in line and "not a regular file" in line


def test_open_regular_names_the_size_limit(tmp_path):
    (tmp_path / "big.pt").write_bytes(b"x" * 2000)
    with pytest.raises(UserError) as err:
        open_regular(tmp_path / "big.pt", "checkpoint", 1000, "expected a policy.pt")
    assert "checkpoint " in str(err.value) and "above the limit of 1 KB; expected a policy.pt" in str(err.value)
    with open_regular(tmp_path / "big.pt", "checkpoint", 4000) as f:
        assert len(f.read()) == 2000


def test_batch_and_workers_are_capped_by_the_episodes(monkeypatch):
    seen = []
    real = executors.run_local

    def spy(plan, play, todo, workers, done, batch):
        seen.append((len(todo), workers, batch))
        return real(plan, play, todo, workers, done, batch)

    monkeypatch.setattr(runner, "run_local", spy)
    units = [("unseen-goals", 1, i) for i in range(3)]
    records = runner.run_units(CONFIG, units, workers=1, batch=100_000, progress=False)
    assert seen == [(3, 1, 3)] and len(records) == 3
    seen.clear()
    runner.run_units(CONFIG, units[:2], workers=64, batch=1, progress=False)
    assert seen == [(2, 2, 1)]


def interrupted(tmp_path, records: int = 4) -> Path:
    out = tmp_path / "r.json"
    evaluate(CONFIG, progress=False, out=out)
    results = json.loads(out.read_text())
    lines = [{"partial_results_of": results["config"]}]
    lines += [{k: v for k, v in r.items() if k != "spl"} for r in results["episodes"][:records]]
    Path(f"{out}.partial.jsonl").write_text("".join(json.dumps(x) + "\n" for x in lines))
    out.unlink()
    return out


def test_a_conflicting_second_record_of_an_episode_is_refused_naming_it(tmp_path):
    out = interrupted(tmp_path)
    partial = Path(f"{out}.partial.jsonl")
    lines = partial.read_text().splitlines()
    other = dict(json.loads(lines[2]), success=not json.loads(lines[2])["success"])
    partial.write_text("\n".join([*lines, json.dumps(other)]) + "\n")
    with pytest.raises(UserError) as err:
        evaluate(CONFIG, progress=False, out=out)
    first = json.loads(lines[2])
    assert f"two different records of episode unseen-goals/seed 1/{first['episode_id']} (lines 3 and 6)" in str(
        err.value
    )
    partial.write_text("\n".join([*lines, lines[2]]) + "\n")  # the same record twice: one is kept
    results = evaluate(CONFIG, progress=False, out=out)
    assert len(results["episodes"]) == 100 and results["splits"]["unseen-goals"]["sr"] == 1.0


@pytest.mark.parametrize("change", [{"steps": "abc"}, {"episode_id": [1]}, {"success": 1}, {"steps": -4}])
def test_a_record_with_wrong_typed_fields_is_dropped_and_played_again(tmp_path, capsys, change):
    out = interrupted(tmp_path)
    partial = Path(f"{out}.partial.jsonl")
    lines = partial.read_text().splitlines()
    lines[3] = json.dumps({**json.loads(lines[3]), **change})
    partial.write_text("\n".join(lines) + "\n")
    results = evaluate(CONFIG, progress=False, out=out)
    assert "line 4 is not an episode record" in capsys.readouterr().err
    assert len(results["episodes"]) == 100 and results["splits"]["unseen-goals"]["sr"] == 1.0


@pytest.mark.parametrize("episodes", [{"a": 1}, [1, 2], [{"split": "x"}]])
def test_retry_failed_on_a_file_whose_episodes_are_not_records_is_refused(tmp_path, episodes):
    out = tmp_path / "r.json"
    evaluate(CONFIG, progress=False, out=out)
    results = json.loads(out.read_text())
    out.write_text(json.dumps(dict(results, episodes=episodes)))
    done = objsearch_eval(
        "--agent", "oracle", "--suite", "gridworld", "--split", "unseen-goals", "--seeds", "1", "--quiet",
        "--out", out, "--retry-failed",
    )  # fmt: skip
    line = one_line(done.stderr)
    assert done.returncode == 2 and "--retry-failed: " in line and "is not a results file written by" in line
