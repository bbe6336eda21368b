"""The leaderboard trusts nothing it has not checked: coverage, field types, the folder it
writes to, entry names, and a replay of a sample of every entry's episodes."""

import copy
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from objsearch.cli import main
from objsearch.eval.metrics import summarize
from objsearch.leaderboard.cli import default_name
from objsearch.leaderboard.render import leaderboard_rows, render
from objsearch.leaderboard.validate import (
    check_submission,
    fresh_rng,
    replay_sample,
    sample_size,
    verify_submission,
)

BIN = Path(sys.executable).parent


def run(capsys, *args) -> tuple[int, str, str]:
    """``objsearch leaderboard ARGS`` in this process: (exit status, stdout, stderr)."""
    code = main(["leaderboard", *map(str, args)])
    out = capsys.readouterr()
    return code, out.out, out.err


def one_error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("objsearch: error: ") and "Traceback" not in err, err
    return lines[0]


def test_a_submission_covers_every_split_with_the_standard_seeds_unless_marked_partial(full_oracle, oracle_results):
    assert check_submission(full_oracle) == []
    (problem,) = check_submission(oracle_results)  # one split, seeds 1,5
    assert (
        "covers splits unseen-goals with seeds 1,5, not every split of gridworld (seen-goals, unseen-goals, "
        "all-goals) with seeds 1,5,13,45,99"
        in problem
        and "--partial" in problem
    )
    assert check_submission(dict(oracle_results, partial=True)) == []
    (problem,) = check_submission(dict(full_oracle, partial=True))
    assert "is marked partial but covers every split" in problem


def test_check_accepts_a_partial_file_only_with_partial(tmp_path, capsys, oracle_results):
    (tmp_path / "part.json").write_text(json.dumps(oracle_results))
    code, _, err = run(capsys, "check", tmp_path / "part.json")
    assert code == 2 and "covers splits unseen-goals with seeds 1,5" in one_error_line(err)
    code, out, _ = run(capsys, "check", "--partial", tmp_path / "part.json")
    assert code == 0 and "(partial, oracle on gridworld, 200 episodes)" in out


def test_partial_entries_are_listed_apart_and_never_ranked(tmp_path, full_random, oracle_results):
    store = tmp_path / "submissions" / "gridworld"
    store.mkdir(parents=True)
    (store / "random.json").write_text(json.dumps(full_random))
    (store / "oracle_part.json").write_text(json.dumps(dict(oracle_results, partial=True)))
    render(tmp_path)
    readme = (tmp_path / "README.md").read_text()
    ranked, apart = readme.split("## Partial submissions (not ranked)")
    assert "| 1 | random |" in ranked and "oracle_part" not in ranked
    assert (
        "### gridworld — unseen-goals (partial)" in apart
        and "| – | oracle_part | oracle (privileged) | gt | 1.00 |" in apart
    )
    assert "oracle_part" not in (tmp_path / "index.html").read_text()
    assert "oracle_part" not in (tmp_path / "paper_tables.md").read_text()
    submissions = [("random", full_random), ("oracle_part", dict(oracle_results, partial=True))]
    assert [r["name"] for r in leaderboard_rows(submissions)["gridworld"]["unseen-goals"]] == ["random"]


def _first(key):
    return lambda r: r["episodes"][0].pop(key)


MUTATIONS = [
    (lambda r: r["episodes"].__setitem__(0, "an episode"), "episodes[0] is 'an episode', not an object"),
    (lambda r: r.update(config=None), "results field 'config' is None, not an object"),
    (lambda r: r.update(episodes={"0": {}}), "results field 'episodes' is {'0': {}}, not a list"),
    (lambda r: r.update(seeds=["1", "5"]), "results field 'seeds' is ['1', '5'], not a list of non-negative integers"),
    (lambda r: r["config"].update(seeds=[1.0, 5]), "config field 'seeds' is [1.0, 5]"),
    (lambda r: r["episodes"][1].update(success="yes"), "episodes[1] field 'success' is 'yes', not true or false"),
    (lambda r: r["episodes"][2].update(episode_id=[2]), "episodes[2] field 'episode_id' is [2], not an integer"),
    (lambda r: r["episodes"][0].update(steps="12"), "episodes[0] field 'steps' is '12', not an integer"),
    (_first("min_steps"), "episodes[0] has no field 'min_steps'"),
    (lambda r: r["splits"].update({"unseen-goals": [0.5]}), "summary of split 'unseen-goals' is [0.5], not an object"),
    (lambda r: r["config"].update(suite_config=["maps"]), "config field 'suite_config' is ['maps'], not an object"),
    (
        lambda r: r["config"].update(suite_config={"max_steps": "many"}),
        "suite configuration {'max_steps': 'many'} is not valid",
    ),
    (lambda r: r.update(episode_set_version=7), "results field 'episode_set_version' is 7, not a version"),
    (lambda r: r.update(partial="yes"), "results field 'partial' is 'yes', not true or false"),
]


@pytest.mark.parametrize("change, message", MUTATIONS)
def test_wrong_typed_fields_are_problems_not_tracebacks(tmp_path, capsys, oracle_results, change, message):
    bad = copy.deepcopy(dict(oracle_results, partial=True))
    change(bad)
    problems = check_submission(bad)
    assert any(message in p for p in problems), problems
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    code, _, err = run(capsys, "check", tmp_path / "bad.json")
    assert code == 2 and message in one_error_line(err)


def test_the_installed_command_says_one_line_for_a_wrong_typed_field(tmp_path, oracle_results):
    bad = dict(copy.deepcopy(oracle_results), partial=True)
    bad["episodes"][4]["seed"] = "five"
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    out = subprocess.run(
        [str(BIN / "objsearch"), "leaderboard", "check", "bad.json"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert out.returncode == 2 and "episodes[4] field 'seed' is 'five', not an integer" in one_error_line(out.stderr)


def test_add_writes_nothing_when_another_stored_entry_is_bad(tmp_path, capsys, oracle_results, random_results):
    board = tmp_path / "board"
    (tmp_path / "oracle.json").write_text(json.dumps(oracle_results))
    (tmp_path / "random.json").write_text(json.dumps(random_results))
    assert run(capsys, "--dir", board, "add", tmp_path / "oracle.json", "--partial", "--create")[0] == 0
    pages = {p: (board / p).read_text() for p in ("README.md", "index.html", "paper_tables.md")}
    stored = board / "submissions" / "gridworld"
    (stored / "broken.json").write_text(json.dumps(dict(oracle_results, partial=True, config=None)))
    code, _, err = run(capsys, "--dir", board, "add", tmp_path / "random.json", "--partial")
    assert code == 2 and "broken.json is rejected: results field 'config' is None" in one_error_line(err)
    assert sorted(p.name for p in stored.iterdir()) == ["broken.json", "oracle.json"]
    assert pages == {p: (board / p).read_text() for p in pages}


def test_add_refuses_a_folder_that_is_not_a_leaderboard(tmp_path, capsys, oracle_results):
    (tmp_path / "oracle.json").write_text(json.dumps(oracle_results))
    code, _, err = run(capsys, "--dir", tmp_path / "elsewhere", "add", tmp_path / "oracle.json", "--partial")
    line = one_error_line(err)
    assert code == 2 and f"{tmp_path / 'elsewhere'} is not a leaderboard folder (it has no submissions/ folder)" in line
    assert "--create" in line and not (tmp_path / "elsewhere").exists()
    out = subprocess.run(
        [str(BIN / "objsearch"), "leaderboard", "add", "oracle.json", "--partial"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert out.returncode == 2 and "leaderboard is not a leaderboard folder" in out.stderr
    assert not (tmp_path / "leaderboard").exists()
    assert (
        run(capsys, "--dir", tmp_path / "elsewhere", "add", tmp_path / "oracle.json", "--partial", "--create")[0] == 0
    )
    assert (tmp_path / "elsewhere/submissions/gridworld/oracle.json").is_file()


def test_a_module_class_agent_gets_a_default_name_and_a_bad_name_is_refused(tmp_path, capsys, oracle_results):
    assert default_name("mymodule:MyAgent") == "mymodule.MyAgent"
    assert default_name("my pkg.mod:Agent<v2>") == "my_pkg.mod.Agent_v2_"
    assert default_name("random") == "random"
    plugin = copy.deepcopy(oracle_results)
    plugin["agent"] = plugin["config"]["agent"] = "mypkg.mymodule:MyAgent"
    (tmp_path / "plugin.json").write_text(json.dumps(plugin))
    board = tmp_path / "board"
    assert run(capsys, "--dir", board, "add", tmp_path / "plugin.json", "--partial", "--create")[0] == 0
    assert (board / "submissions/gridworld/mypkg.mymodule.MyAgent.json").is_file()
    for name in ("abc\n", "-abc", "a/b", ""):
        code, _, err = run(capsys, "--dir", board, "add", tmp_path / "plugin.json", "--partial", f"--name={name}")
        assert code == 2 and f"entry name {name!r} must start with a letter or digit" in err and "Traceback" not in err
    assert sorted(p.name for p in (board / "submissions/gridworld").iterdir()) == ["mypkg.mymodule.MyAgent.json"]


def test_the_replayed_sample_is_drawn_by_the_verifiers_randomness_not_the_content(random_results):
    rng = lambda seed: np.random.default_rng(seed)
    sample = replay_sample(random_results, 8, rng(0))
    assert len(set(sample)) == 8 and sample == replay_sample(copy.deepcopy(random_results), 8, rng(0))
    assert sample == replay_sample(dict(random_results, git_commit="another"), 8, rng(0))  # no free field moves it
    assert sample != replay_sample(random_results, 8, rng(1))
    fresh = [replay_sample(random_results, None, fresh_rng()) for _ in range(3)]  # OS randomness, drawn now
    assert all(len(s) == sample_size(200) for s in fresh) and len({tuple(s) for s in fresh}) == 3


def test_verify_replays_genuine_entries(random_results):
    assert verify_submission(dict(random_results, partial=True), 4) == []


def test_a_renamed_agent_fails_verify(random_results):
    renamed = copy.deepcopy(dict(random_results, partial=True))
    renamed["agent"] = renamed["config"]["agent"] = "oracle"  # random's records, claimed as the oracle's
    assert check_submission(renamed) == []
    problems = verify_submission(renamed, 4)
    assert problems and all("when replayed with agent 'oracle'" in p for p in problems[:3]), problems
    assert any(": success is False in the submission but True" in p for p in problems), problems


def test_a_self_consistent_fake_fails_verify(tmp_path, capsys, random_results):
    fake = copy.deepcopy(dict(random_results, partial=True))
    for r in fake["episodes"]:
        r.update(success=True, steps=r["min_steps"], spl=1.0)
    fake["splits"] = {
        split: summarize([r for r in fake["episodes"] if r["split"] == split]) for split in fake["splits"]
    }
    assert check_submission(fake) == []  # every check on its own content passes
    problems = verify_submission(fake, 4)
    assert problems and "in the submission but" in problems[0] and "when replayed with agent 'random'" in problems[0]

    board = tmp_path / "board"
    (tmp_path / "fake.json").write_text(json.dumps(fake))
    (tmp_path / "genuine.json").write_text(json.dumps(random_results))
    assert run(capsys, "--dir", board, "add", tmp_path / "genuine.json", "--partial", "--create")[0] == 0
    code, out, _ = run(capsys, "--dir", board, "verify", "gridworld/random", "--episodes", "2")
    assert code == 0 and "verified: " in out and "(2 of 200 episodes, drawn at random, replayed identical" in out
    assert run(capsys, "--dir", board, "add", tmp_path / "fake.json", "--partial", "--name", "fake")[0] == 0
    code, out, err = run(capsys, "--dir", board, "verify", "--all", "--episodes", "2")
    (line,) = [line for line in err.splitlines() if line.startswith("objsearch: error: ")]  # one error line
    assert "Traceback" not in err and "verified: " in out, "the entries after the failed one are verified too"
    assert code == 2 and "fake.json fails verification: episode unseen-goals/seed " in line
    assert "is True in the submission but False when replayed" in line or "steps is" in line
    code, _, err = run(capsys, "--dir", board, "verify", "gridworld/nosuch")
    assert code == 2 and "no stored entry 'gridworld/nosuch'" in one_error_line(err)


def _suite_config(r):
    return r["config"].setdefault("suite_config", {})


# (change, the field named, what it must be): every string a submission holds has a declared format
HOSTILE_FIELDS = [
    (lambda r: r.update(agent="<!--<script>"), "results field 'agent' is '<!--<script>'", "not an agent name"),
    (lambda r: r["config"].update(agent="a b"), "config field 'agent' is 'a b'", "not an agent name"),
    (lambda r: r.update(suite="x" * 101), "results field 'suite'", "a name: a letter or digit"),
    (
        lambda r: r.update(objsearch_version="0.1|x<img src=x onerror=alert(1)>"),
        "results field 'objsearch_version'",
        "not a version",
    ),
    (lambda r: r.update(episode_set_version="v1\n"), "results field 'episode_set_version'", "not a version"),
    (lambda r: r.update(git_commit="</script>"), "results field 'git_commit'", "7 to 64 lowercase hex digits"),
    (lambda r: r["config"].update(splits=["a|b"]), "config field 'splits' is ['a|b']", "a list of names"),
    (lambda r: r["config"].update(checkpoint="ckpt\x1b[2J"), "config field 'checkpoint'", "no control characters"),
    (lambda r: r["config"].update(weights_sha256="abc"), "config field 'weights_sha256'", "64 lowercase hex digits"),
    (
        lambda r: _suite_config(r).update(perception_key="<b>"),
        "config.suite_config field 'perception_key' is '<b>'",
        "a perception key",
    ),
    (lambda r: _suite_config(r).update(tasks="t\u2028.jsonl"), "config.suite_config field 'tasks'", "a path"),
    (lambda r: r["episodes"][0].update(goal="g0<b>"), "episodes[0] field 'goal'", "not a name"),
    (lambda r: r["episodes"][1].update(split="x" * 101), "episodes[1] field 'split'", "at most 100 characters"),
    (lambda r: r["episodes"][2].update(error="\x1b]0;owned\x07"), "episodes[2] field 'error'", "text of at most"),
    (lambda r: r["episodes"][3].update(traceback="x" * 20001), "episodes[3] field 'traceback'", "20000 characters"),
]


@pytest.mark.parametrize("change, field, what", HOSTILE_FIELDS)
def test_a_string_out_of_its_declared_format_is_refused_naming_the_field(
    tmp_path, capsys, oracle_results, change, field, what
):
    bad = copy.deepcopy(dict(oracle_results, partial=True))
    change(bad)
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    code, _, err = run(capsys, "check", tmp_path / "bad.json")
    line = one_error_line(err)
    assert code == 2 and field in line and what in line, line
    assert "\x1b" not in line and "\u2028" not in line  # shown escaped, never sent to the terminal


def test_an_entry_name_has_a_declared_format_also_when_stored_by_hand(tmp_path, capsys, oracle_results):
    board = tmp_path / "board"
    (tmp_path / "oracle.json").write_text(json.dumps(oracle_results))
    assert run(capsys, "--dir", board, "add", tmp_path / "oracle.json", "--partial", "--create", "--name", "a")[0] == 0
    code, _, err = run(capsys, "--dir", board, "add", tmp_path / "oracle.json", "--partial", "--name", "x" * 101)
    assert code == 2 and "entry name 'xxx" in one_error_line(err) and "at most 100 characters" in err
    (board / "submissions/gridworld/<!--<script>.json").write_text(json.dumps(dict(oracle_results, partial=True)))
    code, _, err = run(capsys, "--dir", board, "check")
    line = one_error_line(err)
    assert code == 2 and "stored entry " in line and "entry name '<!--<script>' must start" in line
    assert "rename the file" in line
    code, _, err = run(capsys, "--dir", board, "add", tmp_path / "oracle.json", "--partial", "--name", "b")
    assert code == 2 and "entry name '<!--<script>'" in one_error_line(err)  # the pages would show it
    assert sorted(p.name for p in (board / "submissions/gridworld").iterdir()) == ["<!--<script>.json", "a.json"]


@pytest.mark.parametrize(
    "content, message",
    [
        (b'{"schema_version": ' + b"1" * 5000 + b"}", "a number of 5000 digits (at most 20)"),
        (b'{"seeds": [-' + b"9" * 21 + b"]}", "a number of 21 digits (at most 20)"),
        (b"[" * 100_000 + b"]" * 100_000, "nests deeper than 16 levels"),
        (b'{"a": ' + b"[" * 17 + b"]" * 17 + b"}", "nests deeper than 16 levels"),
        (b'{"sr": NaN}', "NaN is not a number JSON allows"),
        (b'{"sr": 1e999}', "the number 1e999 is out of range"),
        (b'{"agent": "\xff"}', "can't decode byte 0xff"),
        (b'{"agent": "x"', "Expecting ',' delimiter"),
        (b"[1, 2]", "is not a results object"),
    ],
)
def test_hostile_json_is_refused_within_parsing_limits(tmp_path, capsys, content, message):
    (tmp_path / "hostile.json").write_bytes(content)
    code, _, err = run(capsys, "check", tmp_path / "hostile.json")
    line = one_error_line(err)
    assert code == 2 and f"submission {tmp_path / 'hostile.json'} " in line and message in line, line


def test_the_parsing_limits_look_outside_strings(tmp_path):
    from objsearch.leaderboard.validate import load_submission

    text = '{"a": "[[[[[[[[[[[[[[[[[[ \\" 123456789012345678901234567890", "b": [[[[[[[[[[[[[[[1.5e-300]]]]]]]]]]]]]]]}'
    (tmp_path / "ok.json").write_text(text)
    assert load_submission(tmp_path / "ok.json") == json.loads(text)  # 16 levels deep, the digits in a string


def test_a_file_past_the_size_limit_is_refused_unread(tmp_path, capsys):
    from objsearch.leaderboard.validate import MAX_BYTES

    (tmp_path / "big.json").write_text('{"agent": "' + "x" * MAX_BYTES + '"}')
    code, _, err = run(capsys, "check", tmp_path / "big.json")
    assert code == 2 and "big.json is larger than the limit of 32 MiB" in one_error_line(err)


def test_every_shipped_entry_names_a_registered_agent():
    """``verify --all`` replays the shipped entries without ``--trust``: each names its agent
    by a registered name or a registered ``module:Class`` (the greedy entries record
    ``objsearch_agents.hrl_grg:HRLGRGGreedyAgent`` and the like, which must stay registered
    targets when the agents' modules move: issue 44)."""
    from objsearch.leaderboard.replay import untrusted_code

    root = Path(__file__).resolve().parents[2] / "leaderboard" / "submissions"
    agents = {json.loads(p.read_text())["agent"] for p in root.glob("*/*.json")}
    assert len(agents) > 10
    assert not {agent: untrusted_code(agent) for agent in agents if untrusted_code(agent)}
