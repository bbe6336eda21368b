"""Who is who: every leaderboard row names the agent its results came from, and agents that
read ground truth beyond their observations (``privileged = True``: the oracle,
``oracle_rooms_frontier``) are marked and never ranked, under whatever entry name."""

import copy
import json
import subprocess
import sys
from pathlib import Path

from objsearch.eval.registry import agent_label, is_privileged
from objsearch.leaderboard.headline import headline_tables
from objsearch.leaderboard.render import PRIVILEGED, leaderboard_rows, render

BIN = Path(sys.executable).parent


def test_the_registry_says_which_agents_are_privileged(tmp_path):
    assert is_privileged("oracle") and is_privileged("oracle_rooms_frontier")
    assert is_privileged("objsearch_agents.baselines.oracle:OracleAgent")  # its registered module:Class
    assert not is_privileged("random") and not is_privileged("frontier") and not is_privileged("no_such_agent")
    # a file agent is never imported to ask (rendering runs no code a submission names)
    marker = tmp_path / "imported"
    agent = tmp_path / "sneaky.py"
    agent.write_text(f"open({str(marker)!r}, 'w').close()\nclass Agent:\n    privileged = True\n")
    assert not is_privileged(f"{agent}:Agent") and not marker.exists()
    assert not is_privileged("some_unregistered_module:Agent")
    assert agent_label(f"{agent}:Agent") == "sneaky.py:Agent"
    assert agent_label("oracle") == "oracle" and agent_label("pkg.mod:Cls") == "pkg.mod:Cls"


def test_privileged_rows_come_after_the_ranked_ones_whatever_their_entry_name(oracle_results, random_results):
    renamed = copy.deepcopy(oracle_results)  # the oracle's results under a learned agent's name
    rooms_known = copy.deepcopy(random_results)
    rooms_known["agent"] = "oracle_rooms_frontier"
    submissions = [("hrl_grg_v3", renamed), ("oracle", oracle_results), ("random", random_results), ("z", rooms_known)]
    rows = leaderboard_rows(submissions)["gridworld"]["unseen-goals"]
    assert [(r["rank"], r["name"], r["agent"]) for r in rows] == [
        (1, "random", "random"),
        (PRIVILEGED, "hrl_grg_v3", "oracle (privileged)"),
        (PRIVILEGED, "oracle", "oracle (privileged)"),
        (PRIVILEGED, "z", "oracle_rooms_frontier (privileged)"),
    ]


def test_adding_the_oracle_under_another_name_shows_it_privileged_on_every_page(tmp_path, full_oracle, full_random):
    (tmp_path / "oracle.json").write_text(json.dumps(full_oracle))
    (tmp_path / "random.json").write_text(json.dumps(full_random))
    objsearch = str(BIN / "objsearch")
    for name, file in (("hrl_grg_v3", "oracle.json"), ("random", "random.json")):
        out = subprocess.run(
            [objsearch, "leaderboard", "add", file, "--name", name, "--create"],
            capture_output=True, text=True, cwd=tmp_path, timeout=300,
        )  # fmt: skip
        assert out.returncode == 0, out.stderr
    readme = (tmp_path / "leaderboard/README.md").read_text()
    table = readme.split("## gridworld — seen-goals")[1].split("##")[0]
    rows = [line for line in table.splitlines() if line.startswith("| ") and not line.startswith(("| #", "| |"))]
    assert rows[0].startswith("| 1 | random | random | gt |")
    assert rows[1].startswith("| privileged | hrl_grg_v3 | oracle (privileged) | gt | 1.00 |")
    assert len(rows) == 2
    page = (tmp_path / "leaderboard/index.html").read_text()
    assert '"name": "hrl_grg_v3", "agent": "oracle (privileged)", "privileged": true' in page
    assert '"rank": "privileged"' in page and '"rank": 1' in page


def test_the_headline_table_marks_the_oracle_privileged(oracle_results, random_results):
    table = headline_tables([("oracle", oracle_results), ("random", random_results)])
    assert "| `oracle` (privileged) | – | 1.00 / 1.00 | – |" in table
    assert "| `random` | – |" in table and "*privileged*: reads ground truth" in table
    assert "privileged" not in headline_tables([("random", random_results)])


def test_render_marks_a_file_agent_by_its_file(tmp_path, oracle_results):
    store = tmp_path / "submissions" / "gridworld"
    store.mkdir(parents=True)
    mine = dict(oracle_results, agent="/home/someone/agents/my_agent.py:Agent")
    (store / "mine.json").write_text(json.dumps(mine))
    render(tmp_path)
    assert "| 1 | mine | my_agent.py:Agent | gt | 1.00 |" in (tmp_path / "README.md").read_text()


def test_agents_declare_themselves_training_free_and_the_board_shows_no_runs_for_them(tmp_path):
    from objsearch.eval.registry import is_training_free
    from objsearch.leaderboard.labels import runs_label, training

    def runs(agent, weights=None):
        return runs_label(training({"agent": agent, "config": {"weights_sha256": weights}})[0])

    # a prior counted on training houses records the prior's digest as weights, and is still training-free
    assert runs("object_prior_frontier", "ab" * 32) == runs("inspect_frontier") == runs("frontier") == "–"
    assert runs("objsearch_agents.baselines.random_agent:RandomAgent") == "–"
    # learned agents without recorded runs count as one run, marked; grg_frontier's GRG is learned
    assert runs("hrl_grg", "cd" * 32) == runs("grg_frontier", "cd" * 32) == runs("scene_priors") == "1*"
    # a file agent is never imported to ask
    marker = tmp_path / "imported"
    agent = tmp_path / "mine.py"
    agent.write_text(f"open({str(marker)!r}, 'w').close()\nclass Agent:\n    training_free = True\n")
    assert not is_training_free(f"{agent}:Agent") and runs(f"{agent}:Agent") == "1*" and not marker.exists()
