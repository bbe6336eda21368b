"""Generating ``leaderboard/README.md``, ``leaderboard/index.html``,
``leaderboard/paper_tables.md`` (the paper's Tables 1-4 beside ours) and, once the size sweep
has entries, ``leaderboard/size_sweep.svg`` (``sweep``) from the stored submissions alone (``leaderboard/submissions/<suite>/<name>.json``).

Partial submissions (``"partial": true``: fewer splits or seeds than the suite's standard)
are never ranked: README.md lists them apart, after the ranked tables; index.html and
paper_tables.md show the full submissions only."""

from __future__ import annotations

import contextlib
import json
from importlib.resources import files
from pathlib import Path

from objsearch.errors import UserError
from objsearch.fileio import atomic_write
from objsearch.leaderboard.markdown import markdown_text
from objsearch.leaderboard.paper import (
    GREEDY_SUFFIX,
    GRIDWORLD_SPLITS,
    GRIDWORLD_TABLES,
    HOUSE3D_SPLITS,
    HOUSE3D_TABLE,
    PAPER_NAMES,
    PREDICTED_SUFFIX,
    TRAINED_ON_PREDICTED_SUFFIX,
    TRAINING_FREE,
    paper_gridworld,
    paper_house3d,
    paper_rows,
)
from objsearch.leaderboard.relations import (
    breakdown_rows,
    gain_rows,
    owed_rows,
    relations_rows,
    render_breakdown,
    render_gains,
    render_owed,
    render_relations,
)
from objsearch.leaderboard.sweep import SVG_FILE, render_sweep, sweep_rows, sweep_svg
from objsearch.leaderboard.table4 import ordering_cells, render_ordering, render_table4, table4_rows

SUBMISSIONS = "submissions"


def _stored(root: str | Path) -> dict[Path, dict]:
    from objsearch.leaderboard.validate import load_submission

    return {path: load_submission(path) for path in sorted(Path(root, SUBMISSIONS).glob("*/*.json"))}


def stored_submissions(root: str | Path) -> list[tuple[str, dict]]:
    """(name, results) of every stored submission, sorted by suite then name."""
    return [(path.stem, results) for path, results in _stored(root).items()]


def observation_label(results: dict) -> str:
    """What the agent saw: ``gt`` (ground-truth segmentation and depth) or ``predicted <network key>``."""
    key = results["config"].get("suite_config", {}).get("perception_key")
    return f"predicted {key}" if key else "gt"


def training(results: dict) -> tuple[int | None, int | None]:
    """(training runs, mean training environment steps of a run) of a submission: (None, None)
    for a shipped training-free agent (``TRAINING_FREE``), (1, None) for any other that
    reports no runs."""
    runs = results.get("training_runs")
    if runs:
        steps = [run["env_steps"] for run in runs]
        return len(runs), None if None in steps else round(sum(steps) / len(steps))
    learned = results["config"].get("weights_sha256") or results["agent"] not in TRAINING_FREE
    return (1, None) if learned else (None, None)


def runs_label(runs: int | None) -> str:
    """``3``; ``1*`` for one training run (marked: its interval covers episodes, not training); ``–`` for none."""
    return "–" if runs is None else f"{runs}*" if runs == 1 else str(runs)


def steps_label(steps: int | None) -> str:
    """``20M`` (environment steps, rounded); ``–`` when unknown."""
    return "–" if steps is None else f"{steps / 1e6:.0f}M" if steps >= 1e6 else f"{steps / 1e3:.0f}k"


def replayed_label(results: dict) -> str:
    """``90/1500``: episodes that ``objsearch leaderboard verify`` replayed identical, of the
    entry's, as recorded for its present content; ``–`` when none were."""
    from objsearch.leaderboard.validate import replayed_of

    replayed = replayed_of(results)
    return "–" if replayed is None else f"{replayed[0]}/{replayed[1]}"


def nonstandard_settings(results: dict) -> list[str]:
    """The suite settings of ``results`` that are not its suite's standard (``validate.nonstandard_settings``)."""
    from objsearch.leaderboard.validate import nonstandard_settings as differing

    return differing(results)


PRIVILEGED = "privileged"  # the rank cell of a privileged agent's row


def leaderboard_rows(submissions: list[tuple[str, dict]], partial: bool = False) -> dict[str, dict[str, list[dict]]]:
    """{suite: {split: [row, ...]}} of the full submissions, rows ranked by SPL, then SR (best
    first), each row's ``rank`` its place; rows of privileged agents (``registry.is_privileged``:
    the oracle, agents that read ground truth) after them, in name order, ranked ``PRIVILEGED``.
    With ``partial``, of the partial submissions instead, in name order, ranked ``–``."""
    from objsearch.eval.registry import agent_label, is_privileged

    tables: dict[str, dict[str, list[dict]]] = {}
    for name, results in submissions:
        if bool(results.get("partial")) != partial:
            continue
        privileged = is_privileged(results["agent"])
        runs, steps = training(results)
        replayed = replayed_label(results)
        settings = "; ".join(nonstandard_settings(results)) if partial else ""
        for split, s in results["splits"].items():
            tables.setdefault(results["suite"], {}).setdefault(split, []).append(
                {
                    "name": name,
                    "agent": agent_label(results["agent"]) + (f" ({PRIVILEGED})" if privileged else ""),
                    "privileged": privileged,
                    "observation": observation_label(results) + (f"; {settings}" if settings else ""),
                    "sr": s["sr"],
                    "spl": s["spl"],
                    "sr_ci": s["sr_ci"],
                    "spl_ci": s["spl_ci"],
                    "as": s["as"],
                    "ms": s["ms"],
                    "episodes": s["episodes"],
                    "seeds": len(results["seeds"]),
                    "runs": runs_label(runs),
                    "train_steps": steps_label(steps),
                    "replayed": replayed,
                    "version": results["objsearch_version"],
                    "commit": (results.get("git_commit") or "")[:8],
                    "per_goal": {goal: g["sr"] for goal, g in s["per_goal"].items()},
                }
            )
    for splits in tables.values():
        for rows in splits.values():
            rows.sort(
                key=lambda r: (
                    r["name"]
                    if partial
                    else (r["privileged"], *((r["name"],) if r["privileged"] else (-r["spl"], -r["sr"], r["name"])))
                )
            )
            for place, r in enumerate(rows, start=1):
                r["rank"] = "–" if partial else PRIVILEGED if r["privileged"] else place
    return tables


def _num(value) -> str:
    return "–" if value is None else f"{value:.2f}"


def _markdown_row(r: dict) -> str:
    name, agent, observation, version, commit = (
        markdown_text(r[k]) for k in ("name", "agent", "observation", "version", "commit")
    )
    return (
        f"| {r['rank']} | {name} | {agent} | {observation} | {_num(r['sr'])} | {_num(r['sr_ci'][0])}–{_num(r['sr_ci'][1])} | "
        f"{_num(r['spl'])} | {_num(r['spl_ci'][0])}–{_num(r['spl_ci'][1])} | "
        f"{_num(r['as'])} / {_num(r['ms'])} | {r['episodes']} | {r['seeds']} | {r['runs']} | {r['train_steps']} | "
        f"{version} | {commit} | {r['replayed']} |"
    )


_MARKDOWN_HEADER = [
    "| # | entry | agent | observation | SR | SR 95% CI | SPL | SPL 95% CI | AS / MS | episodes | seeds | training runs "
    "| training steps | objsearch | commit | replayed |",
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
]


def render_markdown(tables: dict, partial: dict | None = None) -> str:
    """The ranked ``tables``, then the ``partial`` ones (``leaderboard_rows(..., partial=True)``) apart."""
    lines = [
        "# objsearch leaderboard",
        "",
        "Generated by `objsearch leaderboard render` from the validated submissions in",
        "`submissions/` (add one with `objsearch leaderboard add RESULTS.json`); do not edit by hand.",
        "Ranked by SPL, then SR. Intervals are 95% bootstrap intervals over tasks and, for learned agents",
        "shipped as several training runs, over runs too: the figures are then the mean over runs",
        "(`docs/evaluation.md`). *training runs*: `1*` marks an entry from a single training run, whose interval",
        "does not cover how another training seed would do; *training steps*: environment steps of one run,",
        "those of the checkpoints it starts from included. *observation*: `gt` when",
        "the agent saw ground-truth segmentation and depth, `predicted KEY` when it saw the perception network",
        "KEY's predictions (`objsearch-eval --observation predicted`). *replayed*: how many of the entry's",
        "episodes `objsearch leaderboard verify` last replayed, drawn at random, and found identical (– when none",
        "were; `docs/failure_modes.md` says what a replay proves). *agent*: the agent the results came from, by its",
        "registered name, `module:Class` or file (`my_agent.py:Class`); an agent that reads ground truth beyond",
        "its observations (the oracle's shortest path, the rooms that hold the target) is marked *privileged*",
        "and listed after the ranked rows, unranked. The paper's",
        "numbers (Ye et al., CVPR 2021) close each table in italics, for reference; they were",
        "measured on the authors' maps and task lists, not ours.",
        "An interactive version: `index.html`.",
    ]
    for suite, splits in tables.items():
        for split, rows in splits.items():
            lines += ["", f"## {markdown_text(suite)} — {markdown_text(split)}", "", *_MARKDOWN_HEADER]
            lines += [_markdown_row(r) for r in rows]
            for p in paper_rows(suite, split):
                lines.append(
                    f"| | *paper: {p['name']}* | | *{p['observation']}* | *{_num(p['sr'])}* | | *{_num(p['spl'])}* | | "
                    f"*{_num(p['as'])} / {_num(p['ms'])}* | | | | | | | |"
                )
    if partial:
        lines += [
            "",
            "## Partial submissions (not ranked)",
            "",
            "Entries added with `--partial`: they cover fewer splits or seeds than the suite's standard, or were",
            "made with other suite settings (named in the observation column), so they are not comparable with",
            "the ranked rows above.",
        ]
        for suite, splits in partial.items():
            for split, rows in splits.items():
                lines += ["", f"### {markdown_text(suite)} — {markdown_text(split)} (partial)", "", *_MARKDOWN_HEADER]
                lines += [_markdown_row(r) for r in rows]
    return "\n".join(lines) + "\n"


def render_paper_tables(submissions: list[tuple[str, dict]], relations: list[dict] = ()) -> str:
    """The paper's Tables 1 and 2 laid out with our grid-world results beside its numbers, its
    Table 3 beside our house suites and its Table 4 beside our single rooms (``table4``)."""
    ours = {name: results for name, results in submissions if results["suite"] == "gridworld"}
    lines = [
        "# The paper's Tables 1 and 2 (grid world), 3 (House3D) and 4 (AI2-THOR), reproduced",
        "",
        "Generated by `objsearch leaderboard render` from `submissions/gridworld/`; do not edit by hand.",
        "Each cell is **ours** (paper). Ours: the shipped checkpoints (`agents/checkpoints/gridworld/`) on our",
        "20 unseen test maps and 3 x 100 test tasks, seeds 1, 5, 13, 45, 99, evaluated with epsilon 0.1 at both",
        "levels as the authors evaluated; rows marked *greedy* are the same checkpoints with epsilon 0.",
        "The paper's numbers (Ye et al., CVPR 2021) were measured on the authors' maps and tasks, not ours;",
        "its grid-world protocol and what we changed are in `docs/gridworld_agents.md`.",
    ]
    header = (
        "| Method | " + " | ".join(f"{split} SR | {split} SPL | {split} AS / MS" for split in GRIDWORLD_SPLITS) + " |"
    )

    def cells(s: dict | None, paper: tuple | None) -> list[str]:
        ours = [None] * 3 if s is None else [_num(s["sr"]), _num(s["spl"]), f"{_num(s['as'])} / {_num(s['ms'])}"]
        theirs = (
            [None] * 3 if paper is None else [_num(paper[0]), _num(paper[3]), f"{_num(paper[1])} / {_num(paper[2])}"]
        )
        return [
            ("not run" if o is None else f"**{o}**") + ("" if t is None else f" ({t})") for o, t in zip(ours, theirs)
        ]

    for title, names in GRIDWORLD_TABLES.items():
        lines += ["", f"## {title}", "", header, "|---" * (1 + 3 * len(GRIDWORLD_SPLITS)) + "|"]
        for name in names:
            paper, splits = paper_gridworld(name), ours.get(name, {}).get("splits", {})
            row = [c for split in GRIDWORLD_SPLITS for c in cells(splits.get(split), paper[split])]
            lines.append(f"| {PAPER_NAMES[name]} | " + " | ".join(row) + " |")
            if name + GREEDY_SUFFIX in ours:
                greedy = ours[name + GREEDY_SUFFIX]["splits"]
                row = [c for split in GRIDWORLD_SPLITS for c in cells(greedy.get(split), None)]
                lines.append(f"| {PAPER_NAMES[name]} *greedy* | " + " | ".join(row) + " |")
    table4 = render_table4(table4_rows(submissions, lambda results: runs_label(training(results)[0])))
    if table4:
        table4 += render_ordering(ordering_cells(submissions))
    return (
        "\n".join(
            lines
            + _table3(submissions)
            + table4
            + _beyond_the_paper(submissions)
            + render_relations(relations)
            + render_gains(gain_rows(submissions))
            + render_owed(owed_rows(submissions))
            + render_breakdown(breakdown_rows(submissions))
            + render_sweep(sweep_rows(submissions))
        )
        + "\n"
    )


def _observation_rows(name: str, entries: set[str]) -> dict[str, str]:
    """observation label -> entry name of a method's rows: gt and predicted always (random
    only gt: it ignores what it sees), trained on predictions where ``entries`` has one."""
    rows = {"gt": name} if name == "random" else {"gt": name, "predicted": name + PREDICTED_SUFFIX}
    if name + TRAINED_ON_PREDICTED_SUFFIX in entries:
        rows["predicted, trained on it"] = name + TRAINED_ON_PREDICTED_SUFFIX
    return rows


def _table3(submissions: list[tuple[str, dict]]) -> list[str]:
    """The paper's Table 3 (House3D) beside our ``house-single`` and ``house-multi`` rows."""
    ours = {(results["suite"], name): results for name, results in submissions}
    keys = list(HOUSE3D_SPLITS)
    lines = [
        "",
        "## Table 3: House3D, beside our house-single and house-multi",
        "",
        "Each cell is **ours** (paper), SR / SPL. Ours: the shipped checkpoints (`agents/checkpoints/<suite>/`) on the",
        "suites' 100 episodes a split, seeds 1, 5, 13, 45, 99; *gt* rows saw ground-truth segmentation and depth,",
        "*predicted* rows the shipped perception network's predictions (the checkpoints trained on ground truth),",
        "*predicted, trained on it* rows checkpoints trained on the predictions too. The paper's agents saw its",
        "DeepLabv3+'s predictions in House3D houses, in training and evaluation, not ours; protocol and",
        "deviations: `docs/house_agents.md`.",
        "",
        "*runs*: training runs behind each row (`1*`: one run, `–`: no training); with several, the",
        "cell is their mean and [the 95% interval of SR over runs and episodes] (`docs/evaluation.md`).",
        "",
        "| Method | observation | runs | " + " | ".join(f"{suite} {split}" for suite, split in keys) + " |",
        "|---" * (3 + len(keys)) + "|",
    ]
    for name in HOUSE3D_TABLE:
        paper = paper_house3d(name)
        for seen, entry in _observation_rows(name, {entry for _, entry in ours}).items():
            row, runs = [], set()
            for suite, split in keys:
                results = ours.get((suite, entry), {})
                s = results.get("splits", {}).get(split)
                mine = "not run" if s is None else _cell(s, results)
                if results:
                    runs.add(runs_label(training(results)[0]))
                row.append(
                    mine
                    + (
                        f" ({_num(paper[(suite, split)][0])} / {_num(paper[(suite, split)][1])})"
                        if seen == "gt" and paper is not None
                        else ""
                    )
                )
            lines.append(
                f"| {PAPER_NAMES[name]} | {seen} | {' / '.join(sorted(runs)) or '–'} | " + " | ".join(row) + " |"
            )
    return lines


def _cell(s: dict, results: dict) -> str:
    """A table cell of our SR / SPL, with the SR interval across runs for several runs."""
    cell = f"**{_num(s['sr'])} / {_num(s['spl'])}**"
    if len(results.get("training_runs", [])) > 1:
        cell += f" [{_num(s['sr_ci'][0])}–{_num(s['sr_ci'][1])}]"
    return cell


# The suites beyond the paper that paper_tables.md shows, and what each one is.
BEYOND_THE_PAPER = {
    "house-gen": (
        "SR / SPL of Table 3's methods trained on house-gen's 40 training houses and evaluated on its 10",
        "validation and 10 test houses, generated as test houses (unseen object instances), seen and unseen",
        "target categories; 100 episodes a split, seeds 1, 5, 13, 45, 99.",
    ),
    "house-gen-v2": (
        "The same protocol on houses of the generator house-gen-2 (a public core that bedrooms and",
        "bathrooms open onto, rooms of real sizes, an entrance): trained on house-gen-v2's 40 training houses,",
        "evaluated on its 10 validation and 10 test houses; 100 episodes a split, seeds 1, 5, 13, 45, 99.",
    ),
}


def _beyond_the_paper(submissions: list[tuple[str, dict]]) -> list[str]:
    """Our rows on the ``BEYOND_THE_PAPER`` suites, which no paper has: Table 3's methods on
    unseen houses with unseen object instances."""
    lines = []
    for suite, about in BEYOND_THE_PAPER.items():
        ours = {name: results for name, results in submissions if results["suite"] == suite}
        if not ours:
            continue
        splits = list(next(iter(ours.values()))["splits"])
        lines += ["", f"## Beyond the paper: {suite}", "", *about, ""]
        header = " | ".join(markdown_text(split) for split in splits)
        lines += [f"| Method | observation | runs | {header} |", "|---" * (3 + len(splits)) + "|"]
        for name in ("oracle",) + HOUSE3D_TABLE:
            for seen, entry in _observation_rows(name, set(ours)).items():
                if entry not in ours:
                    continue
                got = ours[entry]["splits"]
                row = ["not run" if split not in got else _cell(got[split], ours[entry]) for split in splits]
                runs = runs_label(training(ours[entry])[0])
                lines.append(f"| {PAPER_NAMES[name]} | {seen} | {runs} | " + " | ".join(row) + " |")
    return lines


# The page around the data: HTML, CSS and JS in a file of its own, shipped with the package.
# Its one placeholder is a bare word, not string.Template's $name or str.format's {name}: the
# JS uses ${...} template literals and the CSS and JS braces throughout.
PAGE_TEMPLATE = "templates/index.html"
DATA_PLACEHOLDER = "__DATA__"


def page_template() -> str:
    """The text of ``templates/index.html``: the page, with ``DATA_PLACEHOLDER`` once where its data goes."""
    return files("objsearch.leaderboard").joinpath(PAGE_TEMPLATE).read_text(encoding="utf-8")


def render_html(tables: dict, relations: list[dict] = ()) -> str:
    """``index.html``: the page template with ``tables`` and the paper's rows as its data, as
    JSON that cannot end its script element: ``<``, ``>`` and ``&`` are written as ``\\u003c``,
    ``\\u003e`` and ``\\u0026`` (the same strings to the script), U+2028/9 as ``\\u2028/9``.
    The suites come in the page's order: the default suite first, then the registry's, then others."""
    from objsearch.eval.suites import DEFAULT_SUITE, SUITES

    order = [DEFAULT_SUITE, *(suite for suite in SUITES if suite != DEFAULT_SUITE)]
    rank = lambda suite: (order.index(suite), "") if suite in order else (len(order), suite)
    tables = {suite: tables[suite] for suite in sorted(tables, key=rank)}
    paper = {suite: {split: paper_rows(suite, split) for split in splits} for suite, splits in tables.items()}
    data = json.dumps(
        {"tables": tables, "paper": paper, "relations": list(relations), "default_suite": DEFAULT_SUITE},
        ensure_ascii=True,
    )  # ensure_ascii: also U+2028/9
    for char in "<>&":  # outside strings JSON has none of them
        data = data.replace(char, f"\\u{ord(char):04x}")
    return page_template().replace(DATA_PLACEHOLDER, data)


def _write_together(texts: dict[Path, str]) -> None:
    """Write every file of ``texts`` to a temp file beside it, then rename them all: a failure
    while writing (a full disk) leaves every previous file in place (``UserError``)."""
    path = None
    try:
        with contextlib.ExitStack() as stack:
            for path, text in texts.items():
                f = stack.enter_context(atomic_write(path))
                f.write(text)
                f.flush()  # a write error shows here, before any file is renamed
    except UserError as err:  # a full disk, as atomic_write words it
        raise UserError(f"{err}; the leaderboard is as it was: run the command again then") from None
    except OSError as err:
        raise UserError(
            f"cannot write {path} ({err.strerror}); the leaderboard is as it was: free some space "
            "or fix the folder's permissions, then run the command again"
        ) from None


def render(root: str | Path, add: tuple[Path, dict] | None = None, store: dict[Path, dict] | None = None) -> list[Path]:
    """Regenerate ``README.md``, ``index.html``, ``paper_tables.md`` (and ``size_sweep.svg``)
    under ``root`` from its stored submissions, and the results table of the project's README (``headline``); with
    ``add`` (path, results), store that submission as well, and with ``store`` ({path:
    results}) those, in the same write. Nothing is replaced unless every file is written.
    Returns the paths written.

    Two writers at once would lose pages: callers hold the leaderboard's lock (the CLI does)."""
    from objsearch.leaderboard.headline import headline_tables, project_readme, with_headline

    root = Path(root)
    entries, texts = _stored(root), {}
    for path, results in ([add] if add is not None else []) + list((store or {}).items()):
        entries = {p: r for p, r in entries.items() if p.resolve() != Path(path).resolve()}
        entries[path] = results
        texts[path] = json.dumps(results) + "\n"  # as objsearch.fileio.write_json(..., indent=None) writes it
    submissions = [(path.stem, results) for path, results in sorted(entries.items(), key=lambda e: e[0])]
    tables = leaderboard_rows(submissions)
    full = [(name, results) for name, results in submissions if not results.get("partial")]
    texts[root / "README.md"] = render_markdown(tables, leaderboard_rows(submissions, partial=True))
    relations = relations_rows(full, lambda results: runs_label(training(results)[0]))
    texts[root / "index.html"] = render_html(tables, relations)
    texts[root / "paper_tables.md"] = render_paper_tables(full, relations)
    sweep = sweep_rows(full)
    if sweep:
        texts[root / SVG_FILE] = sweep_svg(sweep)
    readme = project_readme(root)
    if readme is not None:  # the project's README.md, when it holds the results table's markers
        texts[readme] = with_headline(readme.read_text(encoding="utf-8"), headline_tables(full), readme)
    _write_together(texts)
    return list(texts)
