"""One registry of suites: every list of names comes from ``SUITES``, each suite class
declares the options it takes, and ``objsearch suite`` lists and rebuilds them."""

import inspect
import json
import subprocess
import sys

import pytest

from objsearch.cli import main
from objsearch.errors import UserError
from objsearch.eval.suites import SUITES, WORLDS, make_suite, suite_class, suites_taking
from objsearch.sim import suite_build
from objsearch.sim import suites as sim_suites


def test_the_registry_holds_the_grid_world_and_the_shipped_house_suites():
    assert list(SUITES) == ["gridworld", *sim_suites.SUITE_NAMES]
    assert {suite_class(name).world for name in sim_suites.SUITE_NAMES} == {"house"}
    assert suite_class("my-suite.json") is suite_class("house-single")  # a suite file is a house suite


@pytest.mark.parametrize("name", [*SUITES, "my-suite.json"])
def test_declared_options_are_the_constructor_arguments(name):
    cls = suite_class(name)
    assert cls.world in WORLDS
    params = list(inspect.signature(cls).parameters)
    assert params[0] == "name" and tuple(params[1:]) == cls.options


def test_an_option_the_suite_lacks_is_refused_naming_the_suites_that_take_it():
    with pytest.raises(
        UserError, match="suite 'gridworld' takes no option 'mode'.*house-single, house-multi, house-gen"
    ):
        make_suite("gridworld", mode="live")
    assert suites_taking("maps") == ["gridworld"]
    assert suites_taking("max_steps") == [*SUITES, "suite files (.json)"]


def test_suite_list_prints_every_suite_with_its_protocol_splits_episodes_and_seeds(capsys):
    assert main(["suite", "list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    rows = {line.split()[0]: line for line in lines[1 : 1 + len(SUITES)]}
    assert list(rows) == list(SUITES)
    assert rows["gridworld"].split()[1:4] == ["gridworld", "paper", "100"]
    assert "seen-goals 100, unseen-goals 100, all-goals 100  1,5,13,45,99" in rows["gridworld"]
    assert rows["house-large"].split()[1:4] == ["house", "objectnav", "500"]
    assert rows["house-large"].endswith("val 100, test 200  1")
    assert "options of the gridworld suites: maps, tasks, max_steps" in lines
    assert any(line.startswith("options of the house suites (and FILE.json") for line in lines)


def test_suite_rebuild_writes_the_builders_file_where_the_harness_reads_it(monkeypatch, tmp_path, capsys):
    built = {"suite": "house-multi", "version": "house-multi-v1", "houses": {}}
    monkeypatch.setattr(sim_suites, "DATA_DIR", tmp_path)
    monkeypatch.setattr(suite_build, "build_suite", lambda name, cache_dir=None: {**built, "suite": name})
    assert main(["suite", "rebuild", "house-multi", "--cache-dir", str(tmp_path)]) == 0
    assert (tmp_path / "house-multi.json").read_text() == json.dumps(built) + "\n"  # one line, as shipped
    assert f"wrote {tmp_path / 'house-multi.json'}" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exit_:
        main(["suite", "rebuild", "house-x"])
    assert exit_.value.code == 2


def test_the_old_module_entry_points_to_the_rebuild_subcommand():
    out = subprocess.run(
        [sys.executable, "-m", "objsearch.sim.suites", "house-single"], capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 1 and "objsearch suite rebuild NAME" in out.stderr
