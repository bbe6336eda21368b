"""Generating ``leaderboard/README.md``, ``leaderboard/index.html``,
``leaderboard/paper_tables.md`` (the paper's Tables 1-4 beside ours) and, once the size sweep
has entries, ``leaderboard/size_sweep.svg`` (``sweep``), and ``leaderboard/fidelity.svg`` (``fidelity``) once the fidelity suites have, from the stored submissions alone (``leaderboard/submissions/<suite>/<name>.json``).

Partial submissions (``"partial": true``: fewer splits or seeds than the suite's standard)
are never ranked: README.md lists them apart, after the ranked tables; index.html and
paper_tables.md show the full submissions only. The labels of a row are ``labels``'s,
paper_tables.md is ``paper_tables``'s, the project README's table ``headline``'s; every
file is written here, together (``render``)."""

from __future__ import annotations

import contextlib
import json
from importlib.resources import files
from pathlib import Path

from objsearch.errors import UserError
from objsearch.fileio import atomic_write
from objsearch.leaderboard.fidelity import SVG_FILE as FIDELITY_SVG
from objsearch.leaderboard.fidelity import fidelity_rows, fidelity_svg
from objsearch.leaderboard.headline import headline_tables, project_readme, with_headline
from objsearch.leaderboard.labels import (
    nonstandard_settings,
    observation_label,
    replayed_label,
    runs_label,
    steps_label,
    training,
)
from objsearch.leaderboard.labels import number_label as _num
from objsearch.leaderboard.markdown import markdown_text
from objsearch.leaderboard.paper import paper_rows
from objsearch.leaderboard.paper_tables import render_paper_tables
from objsearch.leaderboard.parsing import load_submission
from objsearch.leaderboard.relations import relations_rows
from objsearch.leaderboard.sweep import SVG_FILE, sweep_rows, sweep_svg

SUBMISSIONS = "submissions"


def _stored(root: str | Path, memo=None) -> dict[Path, dict]:
    """The stored entries by path (``memo``, a ``checked.Memo``: those it knows are read without
    the parsing limits they passed before)."""
    load = load_submission if memo is None else memo.load
    return {path: load(path) for path in sorted(Path(root, SUBMISSIONS).glob("*/*.json"))}


def stored_submissions(root: str | Path) -> list[tuple[str, dict]]:
    """(name, results) of every stored submission, sorted by suite then name."""
    return [(path.stem, results) for path, results in _stored(root).items()]


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
    while writing (a full disk) leaves every previous file in place (``UserError``), and a
    signal (SIGTERM, Ctrl-C) that comes during the renames waits until all are done
    (``signals_deferred``): every entry and page is stored, or none."""
    from objsearch.interrupt import signals_deferred

    path = None
    try:
        with contextlib.ExitStack() as stack:
            for path, text in texts.items():
                f = stack.enter_context(atomic_write(path))
                f.write(text)
                f.flush()  # a write error shows here, before any file is renamed
            with signals_deferred():
                stack.close()  # the renames
    except UserError as err:  # a full disk, as atomic_write words it
        raise UserError(f"{err}; the leaderboard is as it was: run the command again then") from None
    except OSError as err:
        raise UserError(
            f"cannot write {path} ({err.strerror}); the leaderboard is as it was: free some space "
            "or fix the folder's permissions, then run the command again"
        ) from None


def render(
    root: str | Path, add: tuple[Path, dict] | None = None, store: dict[Path, dict] | None = None, memo=None
) -> list[Path]:
    """Regenerate ``README.md``, ``index.html``, ``paper_tables.md`` (and ``size_sweep.svg``,
    ``fidelity.svg``)
    under ``root`` from its stored submissions, and the results table of the project's README (``headline``); with
    ``add`` (path, results), store that submission as well, and with ``store`` ({path:
    results}) those, in the same write. Nothing is replaced unless every file is written.
    Returns the paths written. ``memo``: the board's ``checked.Memo``, to read the entries it
    knows faster.

    Two writers at once would lose pages: callers hold the leaderboard's lock (the CLI does)."""
    root = Path(root)
    entries, texts = _stored(root, memo), {}
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
    fidelity = fidelity_rows(full)
    if fidelity:
        texts[root / FIDELITY_SVG] = fidelity_svg(fidelity)
    readme = project_readme(root)
    if readme is not None:  # the project's README.md, when it holds the results table's markers
        texts[readme] = with_headline(readme.read_text(encoding="utf-8"), headline_tables(full), readme)
    _write_together(texts)
    return list(texts)
