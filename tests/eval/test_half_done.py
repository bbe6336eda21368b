"""Half-done and impossible outputs: partial-results files with stray lines or of another
run, and --out / --video places that cannot be written, refused before the first episode."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from objsearch.errors import UserError
from objsearch.eval.runner import EvalConfig, evaluate

BIN = Path(sys.executable).parent
CONFIG = EvalConfig(agent="oracle", splits=("unseen-goals",), seeds=(1,))


def partial_lines(out: Path) -> list:
    return [json.loads(line) for line in Path(f"{out}.partial.jsonl").read_text().splitlines()]


def interrupted_run(tmp_path, records: int = 5) -> Path:
    """The partial file of a run interrupted after ``records`` episodes."""
    out = tmp_path / "r.json"
    evaluate(CONFIG, progress=False, out=out)
    results = json.loads(out.read_text())
    lines = [{"partial_results_of": results["config"]}]
    lines += [{k: v for k, v in r.items() if k != "spl"} for r in results["episodes"][:records]]
    Path(f"{out}.partial.jsonl").write_text("".join(json.dumps(x) + "\n" for x in lines))
    out.unlink()
    return out


@pytest.mark.parametrize("stray", ["{}", "[]", "3", '{"split": "unseen-goals"}'])
def test_a_line_that_is_not_a_record_is_dropped_with_a_warning_and_the_run_resumes(tmp_path, capsys, stray):
    out = interrupted_run(tmp_path)
    partial = Path(f"{out}.partial.jsonl")
    lines = partial.read_text().splitlines()
    partial.write_text("\n".join([*lines[:3], stray, *lines[3:]]) + "\n")
    results = evaluate(CONFIG, progress=False, out=out)
    assert f"{partial} line 4 is not an episode record" in capsys.readouterr().err
    assert len(results["episodes"]) == 100 and results["splits"]["unseen-goals"]["sr"] == 1.0
    assert not partial.exists() and json.loads(out.read_text()) == results


@pytest.mark.parametrize(
    "change, named",
    [
        ({"agent": "random"}, "agent: 'oracle' there, 'random' now"),
        ({"seeds": (1, 5)}, "seeds: [1] there, [1, 5] now"),
        ({"splits": ("all-goals",)}, "splits: ['unseen-goals'] there, ['all-goals'] now"),
        ({"suite_config": {"max_steps": 50}}, "suite_config.max_steps: 100 there, 50 now"),
    ],
)
def test_the_mismatch_message_names_the_setting_that_differs(tmp_path, change, named):
    out = interrupted_run(tmp_path)
    other = EvalConfig(**{**CONFIG.__dict__, **change})
    with pytest.raises(UserError, match="partial results of another evaluation") as err:
        evaluate(other, progress=False, out=out)
    assert named in str(err.value) and "delete it or choose another --out" in str(err.value)


def test_a_file_that_is_not_a_partial_results_file_is_refused(tmp_path):
    out = tmp_path / "r.json"
    Path(f"{out}.partial.jsonl").write_text("[]\n")
    with pytest.raises(UserError, match="is not a partial-results file"):
        evaluate(CONFIG, progress=False, out=out)


def run_cli(*args):
    return subprocess.run([str(BIN / args[0]), *args[1:]], capture_output=True, text=True, timeout=120)


def assert_refused_at_once(out, *words):
    assert out.returncode == 2, out.stderr
    assert "Traceback" not in out.stderr and all(w in out.stderr for w in words), out.stderr
    assert "results written" not in out.stderr and "Unseen Goals" not in out.stdout  # no episode ran


def test_an_out_that_is_a_folder_is_refused_before_the_first_episode(tmp_path):
    out = run_cli(
        "objsearch-eval", "--agent", "oracle", "--suite", "gridworld", "--seeds", "1", "--quiet", "--out", str(tmp_path)
    )
    assert_refused_at_once(out, "--out", "is a folder", "results.json")


@pytest.mark.parametrize("place", ["chmod", "proc"])
def test_an_unwritable_out_is_refused_before_the_first_episode(tmp_path, place):
    if place == "chmod" and os.geteuid() == 0:
        pytest.skip("root writes anywhere")
    locked = Path("/proc/objsearch-test")
    if place == "chmod":
        locked = tmp_path / "locked"
        locked.mkdir(mode=0o500)
    out = run_cli(
        "objsearch-eval",
        "--agent",
        "oracle",
        "--suite",
        "gridworld",
        "--seeds",
        "1",
        "--quiet",
        "--out",
        str(locked / "sub" / "r.json"),
    )
    assert_refused_at_once(out, "--out", "cannot write in", "choose a place you can write to")
    generate = run_cli("objsearch", "generate", "--out", str(locked / "houses"), "--quiet")
    assert generate.returncode == 2 and "cannot write in" in generate.stderr, generate.stderr
    assert "Traceback" not in generate.stderr


def test_a_generate_out_that_is_a_file_is_refused(tmp_path):
    (tmp_path / "houses").write_text("")
    out = run_cli("objsearch", "generate", "--out", str(tmp_path / "houses"), "--quiet")
    assert out.returncode == 2 and "is a file, not a folder" in out.stderr and "Traceback" not in out.stderr
