import copy
import html
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from objsearch.eval.runner import EvalConfig, evaluate
from objsearch.leaderboard.render import leaderboard_rows, render, render_markdown, stored_submissions
from objsearch.leaderboard.validate import check_submission

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent


def test_a_fresh_evaluation_is_valid(full_oracle, oracle_results, random_results):
    assert check_submission(full_oracle) == []
    assert check_submission(dict(oracle_results, partial=True)) == []  # fixtures: one split, two seeds
    assert check_submission(json.loads(json.dumps(dict(random_results, partial=True)))) == []


def tampered(results, change):
    bad = copy.deepcopy(dict(results, partial=True))
    change(bad)
    return check_submission(bad)


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda r: r.update(schema_version=99), "schema_version 99"),
        (lambda r: r.update(suite="nosuch"), "unknown suite 'nosuch'"),
        (lambda r: r.update(episode_set_version="gridworld-v0"), "episode set 'gridworld-v0'"),
        (lambda r: r["episodes"].pop(3), "1 missing episode(s), e.g. unseen-goals/seed 1/episode 3"),
        (lambda r: r["episodes"].append(dict(r["episodes"][0])), "1 duplicated episode(s)"),
        (lambda r: r["splits"]["unseen-goals"].update(sr=0.99), "summary (sr) differs"),
        (lambda r: r["episodes"][0].update(min_steps=1), "does not match the suite's episode"),
        (
            lambda r: next(e for e in r["episodes"] if e["success"] and e["min_steps"] > 1).update(steps=1, spl=1.0),
            "fewer than the minimal",
        ),
        (lambda r: r.pop("config"), "missing field(s) config"),
        (
            lambda r: [e.update(error="KeyError: 'image'", success=False, spl=0.0) for e in r["episodes"][:5]],
            "5 episode(s) ended in an agent error, e.g. unseen-goals/seed 1/0: KeyError: 'image'",
        ),
    ],
)
def test_tampered_submissions_are_rejected(random_results, change, message):
    problems = tampered(random_results, change)
    assert problems and any(message in p for p in problems), problems


def test_changed_outcome_breaks_the_summary(random_results):
    def flip(r):
        ep = next(e for e in r["episodes"] if not e["success"])
        ep["success"], ep["spl"] = True, round(min(1.0, ep["min_steps"] / max(ep["min_steps"], ep["steps"])), 4)

    assert any("differs from the one recomputed" in p for p in tampered(random_results, flip))


def test_custom_task_files_do_not_go_on_the_leaderboard(tmp_path):
    from objsearch.gridworld import dataset
    from objsearch.gridworld.maps import save_map
    from objsearch.gridworld.tasks import save_tasks

    save_map(dataset.test_maps()["map_0100"], tmp_path / "maps")
    save_tasks([t for t in dataset.split_tasks("all-goals") if t.map == "map_0100"][:2], tmp_path / "mine.jsonl")
    results = evaluate(
        EvalConfig(
            agent="oracle",
            seeds=(1,),
            suite_config={"maps": str(tmp_path / "maps"), "tasks": str(tmp_path / "mine.jsonl")},
        ),
        progress=False,
    )
    assert any("not a leaderboard episode set" in p for p in check_submission(results))


def cli(*args, cwd):
    return subprocess.run(
        [str(BIN / "objsearch"), "leaderboard", *args], capture_output=True, text=True, cwd=cwd, timeout=300
    )


def test_add_check_and_render_through_the_cli(tmp_path, full_oracle, full_random):
    (tmp_path / "oracle.json").write_text(json.dumps(full_oracle))
    (tmp_path / "random.json").write_text(json.dumps(full_random))
    bad = copy.deepcopy(full_random)
    bad["episodes"].pop()
    (tmp_path / "bad.json").write_text(json.dumps(bad))

    for name in ("oracle", "random"):
        out = cli("add", f"{name}.json", "--create", cwd=tmp_path)
        assert out.returncode == 0, out.stderr
    out = cli("add", "bad.json", "--name", "bad", cwd=tmp_path)
    assert out.returncode == 2 and "bad.json is rejected: 1 missing episode(s)" in out.stderr
    assert "Traceback" not in out.stderr
    assert not (tmp_path / "leaderboard/submissions/gridworld/bad.json").exists()
    out = cli("add", "oracle.json", cwd=tmp_path)
    assert out.returncode == 2 and "--replace" in out.stderr

    out = cli("check", cwd=tmp_path)
    assert out.returncode == 0 and out.stdout.count("ok: ") == 2
    out = cli("check", "bad.json", cwd=tmp_path)
    assert out.returncode == 2

    readme = (tmp_path / "leaderboard/README.md").read_text()
    rows = [line for line in readme.splitlines() if line.startswith(("| 1 ", "| 2 ", "| privileged "))]
    # the oracle reads ground truth: shown after the ranked rows, marked and unranked
    assert rows[0].startswith("| 1 | random | random | gt |")
    assert rows[1].startswith("| privileged | oracle | oracle (privileged) | gt | 1.00")
    assert "*paper: HRL-GRG* | | *gt*" in readme


def test_add_stores_several_files_in_one_write_or_none(tmp_path, full_oracle, full_random):
    (tmp_path / "oracle.json").write_text(json.dumps(full_oracle))
    (tmp_path / "random.json").write_text(json.dumps(full_random))
    bad = copy.deepcopy(full_random)
    bad["episodes"].pop()
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    stored = tmp_path / "leaderboard/submissions/gridworld"

    out = cli("add", "oracle.json", "bad.json", "--create", cwd=tmp_path)
    assert out.returncode == 2 and "bad.json is rejected" in out.stderr
    assert not (tmp_path / "leaderboard").exists()  # --create made nothing for files that did not pass
    out = cli("add", "oracle.json", "random.json", "--name", "mine", "--create", cwd=tmp_path)
    assert out.returncode == 2 and "--name names one entry" in out.stderr
    out = cli("add", "oracle.json", "oracle.json", "--create", cwd=tmp_path)
    assert out.returncode == 2 and "would both be the entry" in out.stderr and "Traceback" not in out.stderr

    out = cli("add", "oracle.json", "random.json", "--create", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert sorted(p.name for p in stored.iterdir()) == ["oracle.json", "random.json"]
    assert out.stdout.count("added ") == 2
    readme = (tmp_path / "leaderboard/README.md").read_text()
    assert "| 1 | random | random | gt |" in readme and "| privileged | oracle |" in readme


def test_pages_come_from_the_stored_submissions_alone(tmp_path, oracle_results):
    store = tmp_path / "submissions" / "gridworld"
    store.mkdir(parents=True)
    (store / "oracle.json").write_text(json.dumps(oracle_results))
    render(tmp_path)
    pages = ("README.md", "index.html", "paper_tables.md")
    first = {p: (tmp_path / p).read_text() for p in pages}
    render(tmp_path)
    assert first == {p: (tmp_path / p).read_text() for p in pages}
    tables = first["paper_tables.md"]  # Tables 1 and 2: ours in bold, the paper's in brackets
    assert (
        "| Oracle | not run (1.00) | not run (1.00) | not run (11.81 / 11.81) | **1.00** (1.00) | **1.00** (1.00) |"
        in tables
    )
    assert "| HRL-GRG | not run (0.57) | not run (0.33) |" in tables
    # Table 3 (House3D): SR / SPL per suite split, a gt and a predicted row per learned method,
    # the training runs behind each row (none stored here: "–")
    assert "| HRL-GRG | gt | – | not run (0.88 / 0.33) | not run (0.79 / 0.21) |" in tables
    assert "| HRL-GRG | predicted | – | not run | not run |" in tables and tables.count("| HRL-GRG |") == 4
    assert tables.count("| HRL-GRG + explorer (ours) |") == 2  # the extension: its own rows, after the paper's


def test_rows_say_whether_the_agent_saw_ground_truth_or_predictions(oracle_results):
    predicted = copy.deepcopy(oracle_results)
    predicted["config"]["suite_config"] = {"observation": "predicted", "perception_key": "e0415a3134cf0e34"}
    tables = leaderboard_rows([("oracle", oracle_results), ("oracle_pred", predicted)])
    rows = {r["name"]: r["observation"] for r in tables["gridworld"]["unseen-goals"]}
    assert rows == {"oracle": "gt", "oracle_pred": "predicted e0415a3134cf0e34"}
    assert "| oracle_pred | oracle (privileged) | predicted e0415a3134cf0e34 | 1.00 |" in render_markdown(tables)


def test_the_repository_leaderboard_is_valid_and_up_to_date(tmp_path):
    board = ROOT / "leaderboard"
    submissions = stored_submissions(board)
    assert submissions, "leaderboard/submissions/ holds the results of the shipped agents"
    for name, results in submissions:
        assert check_submission(results) == [], name
    shutil.copytree(board / "submissions", tmp_path / "submissions")
    render(tmp_path)
    for page in ("README.md", "index.html", "paper_tables.md"):
        assert (tmp_path / page).read_text() == (board / page).read_text(), (
            f"run: objsearch leaderboard render ({page})"
        )


def test_index_html_renders_the_rows_in_headless_chromium(tmp_path, page_dom, oracle_results, random_results):
    store = tmp_path / "submissions" / "gridworld"
    store.mkdir(parents=True)
    (store / "oracle.json").write_text(json.dumps(oracle_results))
    (store / "random.json").write_text(json.dumps(random_results))
    render(tmp_path)
    dom = page_dom(tmp_path / "index.html")
    assert dom.count('<section class="board"') == 1
    assert dom.count('<tr class="entry">') == 2
    assert dom.count('<tr class="paper">') == 8
    assert dom.index("<td>1</td><td>random</td><td>random</td>") < dom.index(
        "<td>privileged</td><td>oracle</td><td>oracle (privileged)</td><td>gt</td>"
    ), "ranked by SPL, the privileged oracle after the ranked rows, unranked"
    assert dom.count('class="point"') == 2 and dom.count('class="bar"') == 2 * 4  # 4 unseen goals each


# Strings that, written raw, would end the page's script, open a comment or a tag in it, end a
# JavaScript string (U+2028 in older engines), or add Markdown table cells and tags.
HOSTILE_NAME = "<!--<script>"
HOSTILE = "x</script><script>document.body.remove()</script>\u2028<!--|y<img src=x onerror=alert(1)>&amp;"


def hostile_board(root, oracle_results, random_results, name, text):
    """A leaderboard with random and oracle (stored as ``name``; its free strings all ``text``),
    put in place by hand: the pages escape what no check has seen."""
    store = root / "submissions" / "gridworld"
    store.mkdir(parents=True)
    hostile = copy.deepcopy(oracle_results)
    hostile.update(agent=text, objsearch_version=text, git_commit=text)
    hostile["config"]["suite_config"]["perception_key"] = text
    (store / f"{name}.json").write_text(json.dumps(hostile))
    (store / "random.json").write_text(json.dumps(random_results))
    render(root)
    return root


def dom_rows(dom: str) -> list[list[str]]:
    rows = re.findall(r'<tr class="(?:entry|paper)">(.*?)</tr>', dom)
    return [[html.unescape(cell) for cell in re.findall(r"<td>(.*?)</td>", row)] for row in rows]


def test_hostile_strings_leave_the_page_rows_as_they_were_in_headless_chromium(
    tmp_path, page_dom, oracle_results, random_results
):
    plain = hostile_board(tmp_path / "plain", oracle_results, random_results, "oracle", "abc")
    hostile = hostile_board(tmp_path / "hostile", oracle_results, random_results, HOSTILE_NAME, HOSTILE)
    expected = [
        [
            HOSTILE_NAME
            if c == "oracle"
            else HOSTILE
            if c == "abc"
            else f"predicted {HOSTILE}"
            if c == "predicted abc"
            else c
            for c in row
        ]
        for row in dom_rows(page_dom(plain / "index.html"))
    ]
    rows = dom_rows(page_dom(hostile / "index.html"))
    assert len(rows) == 2 + 8 and rows == expected  # 2 entries, 8 rows of the paper
    assert [HOSTILE_NAME, HOSTILE, f"predicted {HOSTILE}"] == rows[0][1:4]


def test_hostile_strings_stay_in_their_markdown_cells(tmp_path, oracle_results, random_results):
    board = hostile_board(tmp_path, oracle_results, random_results, HOSTILE_NAME, HOSTILE)
    readme = (board / "README.md").read_text()
    header = next(line for line in readme.splitlines() if line.startswith("| # |"))
    rows = [line for line in readme.splitlines() if line.startswith(("| 1 |", "| 2 |"))]
    assert len(rows) == 2 and "<" not in readme and "\u2028" not in readme
    for row in rows:  # as many cells as the header: every | of the text is escaped
        assert len(re.findall(r"(?<!\\)\|", row)) == header.count("|"), row
    assert "| &lt;!--&lt;script&gt; |" in readme and "y&lt;img src=x onerror=alert(1)&gt;&amp;amp;" in readme


def test_table3_has_a_trained_on_predictions_row_only_for_a_method_that_has_one():
    from objsearch.leaderboard.render import render_paper_tables

    splits = {"seen-goals": {"sr": 0.9, "spl": 0.4}, "unseen-goals": {"sr": 0.8, "spl": 0.3}}
    entry = {"suite": "house-single", "splits": splits, "agent": "hrl_grg", "config": {"weights_sha256": "0" * 64}}
    tables = render_paper_tables([("hrl_grg_predicted_trained", entry)])
    assert (
        "| HRL-GRG | predicted, trained on it | 1* | **0.90 / 0.40** | **0.80 / 0.30** | not run | not run |" in tables
    )
    assert "| A3C | predicted, trained on it |" not in tables and tables.count("| A3C |") == 2


def test_add_checks_again_only_the_stored_entries_that_changed_since_it_checked_them(
    tmp_path, full_oracle, full_random
):
    from objsearch.leaderboard.checked import MEMO

    (tmp_path / "oracle.json").write_text(json.dumps(full_oracle))
    (tmp_path / "random.json").write_text(json.dumps(full_random))
    assert cli("add", "oracle.json", "random.json", "--create", cwd=tmp_path).returncode == 0
    memo = tmp_path / "leaderboard" / MEMO
    assert len(next(iter(json.loads(memo.read_text()).values()))) == 2  # both entries as stored
    # an unchanged stored entry is not checked again, so another entry goes in
    out = cli("add", "random.json", "--name", "random2", cwd=tmp_path)
    assert out.returncode == 2 and "holds the same results as the stored entry" in out.stderr  # still compared
    # a stored entry edited by hand is checked again, and refused, whatever the memo says
    stored = tmp_path / "leaderboard/submissions/gridworld/random.json"
    edited = json.loads(stored.read_text())
    edited["episodes"].pop()
    stored.write_text(json.dumps(edited))
    out = cli("add", "oracle.json", "--replace", "--name", "oracle", cwd=tmp_path)
    assert out.returncode == 2 and "random.json is rejected: 1 missing episode(s)" in out.stderr, out.stderr
    # a memo that is not one (damaged, or another's) only costs time
    memo.write_text("not json")
    stored.write_text(json.dumps(full_random))
    out = cli("add", "oracle.json", "--replace", "--name", "oracle", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
