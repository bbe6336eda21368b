"""Hand-edited partial-results and results files are not resumed from silently: every line of
``OUT.partial.jsonl`` (and its header) carries a digest, a line that does not match is named
on stderr by episode and played again; ``--retry-failed`` refuses a results file whose records
do not give its summaries. Old partial files without digests still resume (unverified, said once)."""

import json
import re
from pathlib import Path

import pytest
from agents_for_tests import InterruptedAgent

from objsearch.cli import eval_main
from objsearch.errors import UserError
from objsearch.eval.partial import DIGEST, line_digest, run_key
from objsearch.eval.runner import EvalConfig, evaluate

CONFIG = EvalConfig(agent="agents_for_tests:InterruptedAgent", splits=("unseen-goals",), seeds=(1,))
KEPT = 10


def interrupted(tmp_path) -> tuple[Path, Path]:
    """``out`` and its partial file after a run interrupted once ``KEPT`` episodes were saved."""
    out = tmp_path / "r.json"
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = KEPT, 0
    with pytest.raises(KeyboardInterrupt):
        evaluate(CONFIG, progress=False, out=out)
    partial = Path(f"{out}.partial.jsonl")
    assert len(partial.read_text().splitlines()) == 1 + KEPT
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = None, 0
    return out, partial


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> str:
    """The bytes of the results file of an uninterrupted run."""
    out = tmp_path_factory.mktemp("fresh") / "r.json"
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = None, 0
    evaluate(CONFIG, progress=False, out=out)
    return out.read_text()


def lines_of(partial: Path) -> list[dict]:
    return [json.loads(line) for line in partial.read_text().splitlines()]


def write_lines(partial: Path, lines: list[dict]) -> None:
    partial.write_text("".join(json.dumps(x) + "\n" for x in lines))


def test_every_line_carries_a_digest_and_an_untouched_file_resumes_quietly(tmp_path, capsys, fresh):
    out, partial = interrupted(tmp_path)
    header, *records = lines_of(partial)
    key = header[DIGEST]
    assert len(key) == 64 and int(key, 16) >= 0  # the digest of the settings the run played
    for line in records:
        digest = line.pop(DIGEST)
        assert digest == line_digest(key, line)
    capsys.readouterr()
    evaluate(CONFIG, progress=False, out=out)
    err = capsys.readouterr().err
    assert f"resuming: {KEPT} of 100 episodes done" in err and "warning" not in err
    assert InterruptedAgent.resets == 100 - KEPT
    # the results file is the one an uninterrupted run writes, byte for byte: no digest in its records
    assert out.read_text() == fresh and DIGEST not in json.loads(out.read_text())["episodes"][0]


@pytest.mark.parametrize(
    "edit",
    [{"success": False}, {"steps": 3}, {"min_steps": 99}, {"task": {"edited": True}}],
)
def test_an_edited_line_is_named_by_episode_and_played_again(tmp_path, capsys, fresh, edit):
    out, partial = interrupted(tmp_path)
    lines = lines_of(partial)
    lines[3].update(edit)  # line 4 of the file: its digest is the one objsearch wrote
    write_lines(partial, lines)
    capsys.readouterr()
    evaluate(CONFIG, progress=False, out=out)
    err = capsys.readouterr().err
    episode = f"unseen-goals/seed 1/{lines[3]['episode_id']}"
    assert f"{partial} line 4 (episode {episode}) does not match its digest: edited by hand? dropped" in err
    assert f"resuming: {KEPT - 1} of 100 episodes done" in err
    assert InterruptedAgent.resets == 100 - KEPT + 1, "the edited episode was played again, not kept"
    assert out.read_text() == fresh and not partial.exists()


def test_a_line_without_its_digest_or_copied_from_another_run_is_played_again(tmp_path, capsys, fresh):
    out, partial = interrupted(tmp_path)
    lines = lines_of(partial)
    del lines[2][DIGEST]  # a bare record in a file with digests
    other_key = run_key(EvalConfig(**{**CONFIG.__dict__, "seeds": (5,)}))
    record = {k: v for k, v in lines[5].items() if k != DIGEST}
    lines[5][DIGEST] = line_digest(other_key, record)  # signed for another evaluation
    write_lines(partial, lines)
    capsys.readouterr()
    evaluate(CONFIG, progress=False, out=out)
    err = capsys.readouterr().err
    assert f"line 3 (episode unseen-goals/seed 1/{lines[2]['episode_id']}) carries no digest" in err
    assert f"line 6 (episode unseen-goals/seed 1/{record['episode_id']}) does not match its digest" in err
    assert InterruptedAgent.resets == 100 - KEPT + 2
    assert out.read_text() == fresh


def test_a_header_whose_digest_was_edited_drops_every_line(tmp_path, capsys, fresh):
    out, partial = interrupted(tmp_path)
    lines = lines_of(partial)
    lines[0][DIGEST] = "0" * 64
    write_lines(partial, lines)
    capsys.readouterr()
    evaluate(CONFIG, progress=False, out=out)
    err = capsys.readouterr().err
    assert "its header's digest does not match its settings" in err and f"its {KEPT} line(s) are not trusted" in err
    assert InterruptedAgent.resets == 100
    assert out.read_text() == fresh


def test_an_old_file_without_digests_resumes_unverified_with_one_warning(tmp_path, capsys, fresh):
    out, partial = interrupted(tmp_path)
    header, *records = lines_of(partial)
    old = [{k: v for k, v in x.items() if k != DIGEST} for x in (header, *records)]
    write_lines(partial, old[:6])  # as objsearch wrote it before digests: 5 records
    capsys.readouterr()
    InterruptedAgent.interrupt_after = 20  # interrupted again: new lines are appended with digests
    with pytest.raises(KeyboardInterrupt):
        evaluate(CONFIG, progress=False, out=out)
    err = capsys.readouterr().err
    assert err.count("kept unverified") == 1 and "its 5 record(s) without one are kept unverified" in err
    again = lines_of(partial)
    assert DIGEST not in again[0], "an old file is never rewritten with digests its lines did not have"
    assert [DIGEST in x for x in again[1:]] == [False] * 5 + [True] * 20
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = None, 0
    evaluate(CONFIG, progress=False, out=out)
    err = capsys.readouterr().err
    assert "its 5 record(s) without one are kept unverified" in err and "does not match" not in err
    assert InterruptedAgent.resets == 100 - 25
    assert out.read_text() == fresh


# --retry-failed reads a finished results file: its records must give its summaries

RETRY = EvalConfig(agent="agents_for_tests:FlakyAgent", splits=("unseen-goals",), seeds=(1,))


def flaky_results(tmp_path, monkeypatch) -> Path:
    out = tmp_path / "r.json"
    monkeypatch.setenv("FLAKY_AGENT_FAILS", "even")
    evaluate(RETRY, progress=False, out=out)
    monkeypatch.delenv("FLAKY_AGENT_FAILS")
    return out


def failure_made_a_success(results: dict) -> None:
    record = next(r for r in results["episodes"] if "error" in r)
    del record["error"]
    record.pop("traceback", None)
    record.update(success=True, steps=record["min_steps"], spl=1.0)


def steps_of_a_success(results: dict) -> None:
    record = next(r for r in results["episodes"] if r["success"])
    record["steps"] += 4  # its spl kept: the record no longer gives it


def spl_and_steps_of_a_success(results: dict) -> None:
    record = next(r for r in results["episodes"] if r["success"] and r["min_steps"] > 0)
    record["steps"] += 4
    record["spl"] = round(record["min_steps"] / record["steps"], 4)  # consistent, but the summary is not


def a_record_dropped(results: dict) -> None:
    results["episodes"].pop()


@pytest.mark.parametrize(
    "edit, named",
    [
        (failure_made_a_success, "splits.unseen-goals: sr: 0.5 there, 0.51 from its records"),
        (steps_of_a_success, r"episodes\[\d+\].spl is"),
        (spl_and_steps_of_a_success, "splits.unseen-goals: spl: 0.5 there, 0.4"),
        (a_record_dropped, "splits.unseen-goals: "),
    ],
)
def test_retry_failed_refuses_a_results_file_whose_records_were_edited(tmp_path, monkeypatch, edit, named):
    out = flaky_results(tmp_path, monkeypatch)
    results = json.loads(out.read_text())
    edit(results)
    out.write_text(json.dumps(results, indent=1) + "\n")
    before = out.read_text()
    with pytest.raises(UserError, match=f"--retry-failed: {out}'s records do not give its summaries") as err:
        evaluate(RETRY, progress=False, out=out, retry_failed=True)
    assert re.search(named, str(err.value)), str(err.value)
    assert out.read_text() == before and not Path(f"{out}.partial.jsonl").exists()


def test_retry_failed_on_an_edited_file_exits_2_with_one_line_naming_it(tmp_path, monkeypatch, capsys):
    out = flaky_results(tmp_path, monkeypatch)
    results = json.loads(out.read_text())
    failure_made_a_success(results)
    out.write_text(json.dumps(results, indent=1) + "\n")
    argv = ["--agent", RETRY.agent, "--suite", "gridworld", "--split", "unseen-goals", "--seeds", "1"]
    assert eval_main([*argv, "--out", str(out), "--retry-failed", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"objsearch-eval: error: --retry-failed: {out}'s records do not")


def test_retry_failed_writes_partial_files_with_digests(tmp_path, monkeypatch):
    out = flaky_results(tmp_path, monkeypatch)
    monkeypatch.setenv("FLAKY_AGENT_FAILS", "all")  # interrupting is not needed: look at what it resumes from
    from objsearch.eval import partial as partial_module

    seen = {}
    real = partial_module.PartialResults.__init__

    def spy(self, path, config):
        seen["lines"] = lines_of(Path(path))
        real(self, path, config)

    monkeypatch.setattr(partial_module.PartialResults, "__init__", spy)
    evaluate(RETRY, progress=False, out=out, retry_failed=True)
    header, *records = seen["lines"]
    assert len(records) == 50 and all(r[DIGEST] == line_digest(header[DIGEST], _bare(r)) for r in records)


def _bare(line: dict) -> dict:
    return {k: v for k, v in line.items() if k != DIGEST}


def test_retry_failed_checks_each_training_runs_summaries(tmp_path):
    config = EvalConfig(agent="tests.eval.agents_for_tests:RunsAgent", splits=("unseen-goals",), seeds=(1,))
    out = tmp_path / "r.json"
    first = evaluate(config, progress=False, out=out)
    assert len(first["training_runs"]) == 3
    again = evaluate(config, progress=False, out=out, retry_failed=True)  # untouched: nothing to replay
    assert again["episodes"] == first["episodes"] and not list(tmp_path.glob("*.partial.jsonl"))
    # a failure of run 2 made a success and every split summary recomputed: run 2's summary still differs
    results = json.loads(out.read_text())
    record = next(r for r in results["episodes"] if r["training_run"] == 2 and not r["success"])
    record.update(success=True, steps=max(record["min_steps"], 1), spl=1.0)
    from objsearch.eval.metrics import summarize

    results["splits"]["unseen-goals"] = summarize([r for r in results["episodes"]])
    out.write_text(json.dumps(results, indent=1) + "\n")
    with pytest.raises(UserError, match=r"training_runs\[seed 2\].splits.unseen-goals: sr: "):
        evaluate(config, progress=False, out=out, retry_failed=True)
