"""Suite files are input, and users edit them: every hand edit that breaks a field is exit 2
with one line naming the file, the field's path in it and what it must be (never a
traceback, never a silently wrong result), and the version results record is computed from
the content, so an edit that keeps the file valid changes it and is reported."""

import json
import shutil

import pytest
from own_houses import assert_clean_error, run

from objsearch.cli import eval_main

SPLIT = "my-suite"


def _edit(data: dict, how: str) -> None:
    episode = data["splits"][SPLIT][3]
    house, target = episode["house"], episode["target"]
    if how == "start in a wall":
        episode["start"] = [0, 0, 0]
    elif how == "goal pose in a wall":
        data["goals"][house][target][0] = [0, 0, 1]
    elif how == "empty goal-pose list":
        data["goals"][house][target] = []
    elif how == "wrong min_steps":
        episode["min_steps"] += 2
    elif how == "empty split":
        data["splits"][SPLIT] = []
    elif how == "no split":
        data["splits"] = {}
    elif how == "unknown target":
        episode["target"] = "unicorn"
    elif how == "target without goal poses in the house":
        del data["goals"][house][target]
    elif how == "unknown house":
        episode["house"] = "train_999999"
    elif how == "houses a list":
        data["houses"] = []
    elif how == "start a string":
        episode["start"] = "2,3,0"
    elif how == "start of two numbers":
        episode["start"] = episode["start"][:2]
    elif how == "heading 4":
        episode["start"][2] = 4
    elif how == "episode a number":
        data["splits"][SPLIT][3] = 7
    elif how == "min_steps a float":
        episode["min_steps"] = 12.5
    elif how == "max_steps a string":
        data["max_steps"] = "500"
    elif how == "max_steps -5":
        data["max_steps"] = -5
    elif how == "unknown protocol":
        data["protocol"] = "habitat"
    elif how == "misspelt field":
        data["max_step"] = data.pop("max_steps")
    elif how == "unknown field":
        data["max_step"] = 10
    elif how == "house without seed or path":
        del data["houses"][house]["path"]
    elif how == "bad spec hash":
        data["houses"][house]["spec_sha256"] = "abc"
    elif how == "goal rule of another protocol":
        data["protocol"] = "objectnav"
    elif how == "other pose graph":
        data["navgraph"] = "navgraph-v0"


CASES = [
    ("start in a wall", "splits.my-suite[3].start", "not on a free cell"),
    ("goal pose in a wall", "goals.{house}.{target}[0]", "not on a free cell"),
    ("empty goal-pose list", "goals.{house}.{target}", "is empty"),
    ("wrong min_steps", "splits.my-suite[3].min_steps", "the pose graph says"),
    ("empty split", "splits.my-suite", "is empty"),
    ("no split", "splits", "is empty"),
    ("unknown target", "splits.my-suite[3].target", "'unicorn' has no goal poses in house"),
    ("target without goal poses in the house", "splits.my-suite[3].target", "has no goal poses in house"),
    ("unknown house", "splits.my-suite[3].house", "'train_999999' is not in houses"),
    ("houses a list", "houses", "is not of type 'object'"),
    ("start a string", "splits.my-suite[3].start", "is not of type 'array'"),
    ("start of two numbers", "splits.my-suite[3].start", "has 2 item(s)"),
    ("heading 4", "splits.my-suite[3].start[2]", "maximum"),
    ("episode a number", "splits.my-suite[3]", "is not of type 'object'"),
    ("min_steps a float", "splits.my-suite[3].min_steps", "is not of type 'integer'"),
    ("max_steps a string", "max_steps", "is not of type 'integer'"),
    ("max_steps -5", "max_steps", "less than the minimum of 1"),
    ("unknown protocol", "protocol", '\'habitat\' is not one of ["paper", "objectnav"]'),
    ("misspelt field", "max_steps", "is missing (the file has 'max_step': misspelt?)"),
    ("unknown field", "max_step", "is not a field here"),
    ("house without seed or path", "houses.{house}", "neither a seed nor a path"),
    ("bad spec hash", "houses.{house}.spec_sha256", "does not match"),
    ("goal rule of another protocol", "goal_rule.kind", "'near_visible'"),
    ("other pose graph", "navgraph", "navgraph-v1"),
]


@pytest.mark.parametrize("how, where, problem", CASES, ids=[c[0] for c in CASES])
def test_a_broken_field_is_exit_2_naming_its_path_and_the_fix(made, cache_dir, tmp_path, capsys, how, where, problem):
    shutil.copytree(made / "houses", tmp_path / "houses")
    data = json.loads((made / "my-suite.json").read_text())
    episode = data["splits"][SPLIT][3]
    _edit(data, how)
    (tmp_path / "edited.json").write_text(json.dumps(data))
    capsys.readouterr()
    args = ["--agent", "oracle", "--suite", str(tmp_path / "edited.json"), "--seeds", "1", "--cache-dir", cache_dir]
    assert eval_main([*args, "--quiet"]) == 2
    err = capsys.readouterr().err
    line = err.strip().splitlines()[-1]  # a pose found wrong after the edit was read follows its version warning
    where = where.format(**episode)
    assert f"suite file {tmp_path / 'edited.json'}: {where}: " in line, line
    assert problem in line and "objsearch suite make" in line and "Traceback" not in err, line


def test_max_steps_minus_5_is_refused_in_the_cli_not_scored(made, tmp_path):
    """Before: exit 0 and SR 0.00 for the oracle."""
    shutil.copytree(made / "houses", tmp_path / "houses")
    data = json.loads((made / "my-suite.json").read_text())
    (tmp_path / "edited.json").write_text(json.dumps({**data, "max_steps": -5}))
    out = run("objsearch-eval", "--agent", "oracle", "--suite", "edited.json", "--seeds", "1", cwd=tmp_path)
    assert_clean_error(out, "suite file edited.json: max_steps: -5", "positive integer")


def test_a_file_that_is_no_suite_file_is_refused(tmp_path, capsys):
    for text, needle in (("[1, 2]", "the file: [1, 2] is not of type 'object'"), ("{}", "suite: is missing")):
        (tmp_path / "s.json").write_text(text)
        assert eval_main(["--suite", str(tmp_path / "s.json"), "--seeds", "1", "--quiet"]) == 2
        assert needle in capsys.readouterr().err


def test_the_version_is_the_contents_so_a_valid_edit_changes_it_and_is_reported(made, cache_dir, tmp_path, capsys):
    from objsearch.sim.suite_schema import content_digest

    shutil.copytree(made / "houses", tmp_path / "houses")
    data = json.loads((made / "my-suite.json").read_text())
    assert data["version"] == f"custom:{content_digest(data)[:12]}"  # as made: the field is the content's
    edited = {**data, "max_steps": 60}  # valid, but not the suite that was made: another version
    (tmp_path / "edited.json").write_text(json.dumps(edited))
    out = tmp_path / "r.json"
    args = ["--agent", "oracle", "--suite", str(tmp_path / "edited.json"), "--seeds", "1", "--cache-dir", cache_dir]
    assert eval_main([*args, "--quiet", "--out", str(out)]) == 0
    results = json.loads(out.read_text())
    version = f"custom:{content_digest(edited)[:12]}"
    assert results["episode_set_version"] == version != data["version"]
    assert results["splits"][SPLIT]["sr"] == 1.0  # the oracle's paths are 40 steps at most
    err = capsys.readouterr().err
    assert f"its version field says {data['version']}, its content is {version}" in err
    assert version in format_footer(results)


def format_footer(results: dict) -> str:
    from objsearch.eval.results import format_table

    return next(line for line in format_table(results).splitlines() if line.startswith("suite "))


def test_a_shipped_file_edited_in_place_is_refused(monkeypatch, tmp_path):
    """A shipped suite's version holds only for the content it was made with."""
    from objsearch.errors import UserError
    from objsearch.sim import suites

    data = json.loads((suites.DATA_DIR / "house-multi.json").read_text())
    data["max_steps"] = 50
    (tmp_path / "house-multi.json").write_text(json.dumps(data))
    monkeypatch.setattr(suites, "DATA_DIR", tmp_path)
    suites._shipped_suite_file.cache_clear()
    try:
        with pytest.raises(UserError, match="house-multi.json was edited.*objsearch suite rebuild house-multi"):
            suites.load_suite_file("house-multi")
    finally:
        suites._shipped_suite_file.cache_clear()
