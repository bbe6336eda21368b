"""The size sweep: each prior agent's gain over ``frontier`` against house size, with the
objects where they belong and shuffled (``docs/large_houses.md``).

The sweep's suites (``house-size-N`` and ``house-size-N-shuffled``, N rooms, ``SWEEP_ROOMS``)
are ``house-gen-3`` houses of one size each, the same houses, starts and targets in both
placements. ``sweep_rows`` pairs every gt entry with ``frontier``'s on the same test episodes
(SR and SPL gain with the paired 95% bootstrap intervals over episodes and over houses: each
size has 8 houses, and the house interval is the one that says whether a gain holds on other
houses); ``render_sweep`` is its table for ``paper_tables.md`` and ``sweep_svg`` its plot
(``leaderboard/size_sweep.svg``, error bars over houses), both written by ``objsearch
leaderboard render``. ``sweep_owed_rows`` (``render_sweep_owed``): each size's functional gain
minus its shuffled gain, paired by episode and by house.
"""

from __future__ import annotations

import html
import math

from objsearch.eval.metrics import spl, success_rate
from objsearch.leaderboard.relations import (
    BOUNDS,
    REFERENCE,
    _ci,
    _gt,
    _interval_table,
    _name,
    _ordered,
    _split,
    owed_row,
    paired_gain,
)

#: The sweep's house sizes (rooms): ``objsearch.sim.large_suite.SWEEP``'s, which builds their suites (a
#: copy, so that the pages import no MuJoCo; a test keeps the two the same).
SWEEP_ROOMS = (4, 7, 10, 14)
PLACEMENTS = ("functional", "shuffled")
MEASURES = (("sr", "SR", success_rate), ("spl", "SPL", spl))
SVG_FILE = "size_sweep.svg"


def sweep_suite(rooms: int, placement: str) -> str:
    """The sweep's suite of ``rooms`` rooms in ``placement`` (``functional`` or ``shuffled``)."""
    return f"house-size-{rooms}" + ("" if placement == "functional" else f"-{placement}")


def sweep_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """Every gt entry of a sweep suite but ``REFERENCE`` and the bounds, with its SR and SPL and
    its gain over ``REFERENCE`` on the same episodes and seeds (paired 95% intervals over
    episodes, ``sr_gain_ci``, and over houses, ``sr_gain_house_ci``: None without houses), and
    ``REFERENCE``'s own SR and SPL there; by method, size, placement."""
    rows = []
    for rooms in SWEEP_ROOMS:
        for placement in PLACEMENTS:
            entries = _gt(submissions, sweep_suite(rooms, placement))
            if REFERENCE not in entries:
                continue
            ref = _split(entries[REFERENCE], split)
            for name in _ordered(n for n in entries if n not in (REFERENCE, *BOUNDS)):
                mine = _split(entries[name], split)
                gain = paired_gain(mine, ref)
                if gain is None:
                    continue
                row = {"name": name, "rooms": rooms, "placement": placement, "episodes": len(mine)}
                for key, _, measure in MEASURES:
                    row[key], row["reference_" + key] = measure(mine), measure(ref)
                    row[key + "_gain"], row[key + "_gain_ci"] = gain[key], gain[key + "_ci"]
                    row[key + "_gain_house_ci"] = gain[key + "_house_ci"]
                rows.append(row)
    order = _ordered({r["name"] for r in rows})
    return sorted(rows, key=lambda r: (order.index(r["name"]), r["rooms"]))


def render_sweep(rows: list[dict]) -> list[str]:
    """The markdown of ``sweep_rows``: one row per method and size, both placements side by side."""
    if not rows:
        return []
    lines = [
        "",
        f"## Gain over `{REFERENCE}` against house size",
        "",
        "The size sweep (`house-size-N`, N rooms, and `house-size-N-shuffled`: the same houses, starts and targets",
        "with every object anywhere in the house). Each cell: the agent's SR or SPL on test minus",
        f"`{REFERENCE}`'s on the same episodes, with the paired 95% bootstrap interval over episodes, and beside it",
        "the one over houses (a house and all its episodes drawn together: 8 houses a size, so the interval a",
        f"claim must hold on); `{REFERENCE}`'s own scores (functional · shuffled) in the first column. A prior that",
        "uses where things are gains on functional houses and not on shuffled ones. gt observations, seed 1.",
        f"The plot, with the intervals over houses: [`{SVG_FILE}`]({SVG_FILE}).",
        "",
        f"| Method | rooms | {REFERENCE} SR / SPL · shuffled | SR gain (95% CI over episodes) | over houses "
        "| SR gain shuffled (95% CI over episodes) | over houses | SPL gain (95% CI over episodes) | over houses "
        "| SPL gain shuffled (95% CI over episodes) | over houses |",
        "|---" * 11 + "|",
    ]
    cells = {(r["name"], r["rooms"], r["placement"]): r for r in rows}
    for name in _ordered({r["name"] for r in rows}):
        for rooms in SWEEP_ROOMS:
            got = [cells.get((name, rooms, p)) for p in PLACEMENTS]
            if not any(got):
                continue
            reference = " · ".join(
                "-" if r is None else f"{r['reference_sr']:.2f} / {r['reference_spl']:.2f}" for r in got
            )
            gains = ["- | -" if r is None else _gain(r, key) for key in ("sr", "spl") for r in got]
            lines.append(f"| {_name(name)} | {rooms} | {reference} | " + " | ".join(gains) + " |")
    return lines


def sweep_owed_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """Every gt entry on both placements of a sweep size but ``REFERENCE`` and the bounds: its
    gain over ``REFERENCE`` on functional houses minus its gain on the same episodes shuffled
    (``relations.owed_row``: what the gain owes to where things are), by method and size
    (``suite``: the shuffled suite)."""
    rows = []
    for rooms in SWEEP_ROOMS:
        base, moved = (_gt(submissions, sweep_suite(rooms, placement)) for placement in PLACEMENTS)
        if REFERENCE not in base or REFERENCE not in moved:
            continue
        for name in _ordered(n for n in base if n in moved and n not in (REFERENCE, *BOUNDS)):
            row = owed_row(base, moved, name, split)
            if row is not None:
                rows.append({"suite": sweep_suite(rooms, "shuffled"), "rooms": rooms, **row})
    order = _ordered({r["name"] for r in rows})
    return sorted(rows, key=lambda r: (order.index(r["name"]), r["rooms"]))


def render_sweep_owed(rows: list[dict]) -> list[str]:
    """The markdown of ``sweep_owed_rows``."""
    text = (
        f"Each agent's gain over `{REFERENCE}` on `house-size-N` minus its gain on `house-size-N-shuffled`, per test",
        "episode (the same houses, starts and targets), with the paired 95% intervals over episodes and over houses:",
        "above zero, the gain needs the objects where they belong. gt observations, seed 1.",
    )
    heading = f"Gain over `{REFERENCE}` against house size: what it owes to where things are"
    return _interval_table(heading, text, "shuffled suite", "owed", rows)


def _gain(row: dict, key: str) -> str:
    """Two cells: the gain with its interval over episodes, then its interval over houses."""
    return f"{row[key + '_gain']:+.2f} ({_ci(row[key + '_gain_ci'])}) | {_ci(row[key + '_gain_house_ci'])}"


def _bars(rows: list[dict]) -> tuple[str, str]:
    """Which interval the plot's error bars show: ``_gain_house_ci`` (over houses) where every
    row has one, else ``_gain_ci`` (over episodes); and its words for the titles."""
    if all(r[key + "_gain_house_ci"] is not None for r in rows for key, _, _ in MEASURES):
        return "_gain_house_ci", "95% CI over houses"
    return "_gain_ci", "95% CI over episodes"


# The plot's frame (px) and the colours of its methods, in order.
WIDTH, HEIGHT, MARGIN, GAP = 360, 260, 48, 24
COLOURS = ("#1b6ca8", "#d1495b", "#2e933c", "#8e5ea2", "#edae49")


def sweep_svg(rows: list[dict]) -> str:
    """``sweep_rows`` as an SVG: a panel for SR gain and one for SPL gain against rooms, a line a
    method (solid: functional, dashed: shuffled) with its 95% intervals over houses as bars
    (over episodes where a record names no house; the titles say which)."""
    names = _ordered({r["name"] for r in rows})
    bar, bar_words = _bars(rows)
    lows = [min(r[k + bar][0] for r in rows) for k, _, _ in MEASURES]
    highs = [max(r[k + bar][1] for r in rows) for k, _, _ in MEASURES]
    low, high = min(-0.05, *lows), max(0.05, *highs)
    low, high = math.floor(low * 10) / 10, math.ceil(high * 10) / 10
    span_x = SWEEP_ROOMS[-1] - SWEEP_ROOMS[0]
    total_w = 2 * (WIDTH + MARGIN) + GAP + MARGIN // 2  # room for the last tick's label
    legend_h = 18 * (len(names) + 2)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{total_w}" height="{HEIGHT + 2 * MARGIN + legend_h}" '
        'font-family="sans-serif" font-size="12">',
        f'<rect width="{total_w}" height="{HEIGHT + 2 * MARGIN + legend_h}" fill="white"/>',
    ]
    for panel, (key, label, _) in enumerate(MEASURES):
        left = MARGIN + panel * (WIDTH + MARGIN + GAP)

        def x(rooms: float) -> float:
            return left + (rooms - SWEEP_ROOMS[0]) / span_x * WIDTH

        def y(value: float) -> float:
            return MARGIN + (high - value) / (high - low) * HEIGHT

        out.append(
            f'<text x="{left + WIDTH / 2}" y="{MARGIN - 16}" text-anchor="middle" font-weight="bold">'
            f"{label} gain over {REFERENCE} ({bar_words})</text>"
        )
        out.append(f'<rect x="{left}" y="{MARGIN}" width="{WIDTH}" height="{HEIGHT}" fill="none" stroke="#888"/>')
        for tick in _ticks(low, high):
            out.append(
                f'<line x1="{left}" x2="{left + WIDTH}" y1="{y(tick):.1f}" y2="{y(tick):.1f}" '
                f'stroke="{"#444" if tick == 0 else "#ddd"}"/>'
            )
            out.append(f'<text x="{left - 6}" y="{y(tick) + 4:.1f}" text-anchor="end">{_tick_label(tick)}</text>')
        for rooms in SWEEP_ROOMS:
            out.append(f'<text x="{x(rooms):.1f}" y="{MARGIN + HEIGHT + 16}" text-anchor="middle">{rooms}</text>')
        out.append(f'<text x="{left + WIDTH / 2}" y="{MARGIN + HEIGHT + 34}" text-anchor="middle">rooms</text>')
        for m, name in enumerate(names):
            colour = COLOURS[m % len(COLOURS)]
            for p, placement in enumerate(PLACEMENTS):
                mine = sorted(
                    (r for r in rows if r["name"] == name and r["placement"] == placement), key=lambda r: r["rooms"]
                )
                shift = (p - 0.5) * 0.12 * span_x / len(SWEEP_ROOMS)  # the two placements side by side
                points = " ".join(f"{x(r['rooms'] + shift):.1f},{y(r[key + '_gain']):.1f}" for r in mine)
                dash = "" if placement == "functional" else ' stroke-dasharray="5,4"'
                out.append(f'<polyline points="{points}" fill="none" stroke="{colour}" stroke-width="2"{dash}/>')
                for r in mine:
                    cx, (ci_low, ci_high) = x(r["rooms"] + shift), r[key + bar]
                    out.append(
                        f'<line x1="{cx:.1f}" x2="{cx:.1f}" y1="{y(ci_low):.1f}" y2="{y(ci_high):.1f}" '
                        f'stroke="{colour}"/>'
                    )
                    fill = colour if placement == "functional" else "white"
                    out.append(
                        f'<circle cx="{cx:.1f}" cy="{y(r[key + "_gain"]):.1f}" r="3.5" fill="{fill}" '
                        f'stroke="{colour}"/>'
                    )
    out += legend(
        names, "solid, filled: functional; dashed, open: shuffled (objects anywhere). gt observations, test episodes."
    )
    out.append("</svg>")
    return "\n".join(out) + "\n"


def legend(names: list[str], note: str) -> list[str]:
    """The SVG elements of a plot's legend below its panels: a coloured line and the name of
    each method (in ``COLOURS``' order), then ``note``."""
    top = HEIGHT + 2 * MARGIN
    out = []
    for m, name in enumerate(names):
        colour = COLOURS[m % len(COLOURS)]
        out.append(
            f'<line x1="{MARGIN}" x2="{MARGIN + 24}" y1="{top + 18 * m:.0f}" y2="{top + 18 * m:.0f}" '
            f'stroke="{colour}" stroke-width="3"/>'
        )
        out.append(f'<text x="{MARGIN + 32}" y="{top + 18 * m + 4:.0f}">{html.escape(name)}</text>')
    out.append(f'<text x="{MARGIN}" y="{top + 18 * len(names) + 4:.0f}">{note}</text>')
    return out


def _ticks(low: float, high: float) -> list[float]:
    count = round((high - low) * 10)
    return [round(low + i / 10, 1) for i in range(count + 1)]


def _tick_label(value: float) -> str:
    """``+0.1``, ``0``, ``-0.2``."""
    return "0" if value == 0 else f"{value:+.1f}"
