"""The "Actions and observations" section of ``docs/add_your_agent.md``, rendered from the
suites' envs (their spaces, action names and docstrings) so that it cannot drift from them.

    objsearch data rebuild agent-io-doc           # rewrite the section of the doc
    objsearch data rebuild agent-io-doc --check   # exit 1 if the doc's section is stale

(``objsearch/data_cli.py`` holds the subcommand; ``rebuild_doc`` here does the work. The doc
is the repository's ``docs/``, so it runs from a checkout.)
"""

from __future__ import annotations

import inspect
import re
import sys
from pathlib import Path

COMMAND = "objsearch data rebuild agent-io-doc"
BEGIN = f"<!-- generated: {COMMAND} -->"
END = "<!-- end generated -->"
DOC = Path(__file__).resolve().parents[2] / "docs" / "add_your_agent.md"


def _markdown(text: str) -> str:
    """reST inline literals (````x````) as markdown ones, lines joined into one paragraph."""
    return re.sub(r"``(.+?)``", r"`\1`", " ".join(line.strip() for line in text.splitlines() if line.strip()))


def docstring_section(cls: type, title: str) -> str:
    """The ``## title`` section of ``cls``'s docstring (the Gymnasium env docstring layout)."""
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", inspect.cleandoc(cls.__doc__), re.S | re.M)
    if match is None:
        raise RuntimeError(f"{cls.__name__}'s docstring has no '## {title}' section")
    return _markdown(match.group(1))


def _predicted_sentence() -> str:
    """What ``observation="predicted"`` changes, from the house suites' module docstring."""
    from objsearch.eval.suites import house

    text = _markdown(house.__doc__)
    match = re.search(r'With `observation="predicted"`[^.]*\.', text)
    if match is None:
        raise RuntimeError('objsearch.eval.suites.house\'s docstring no longer says what observation="predicted" does')
    return match.group(0)


def _world(title: str, suite: str, env, action_names, observation: str, actions: str) -> list[str]:
    lines = [
        f"### {title}",
        "",
        f"As suite `{suite}` makes the env (`{type(env).__module__}.{type(env).__name__}`):",
        "",
        "| observation key | space |",
        "|---|---|",
    ]
    lines += [f"| `{key}` | `{space}` |" for key, space in env.observation_space.spaces.items()]
    lines += ["", observation, "", f"| action (`{env.action_space}`) | meaning |", "|---|---|"]
    lines += [f"| {i} | {action_names[i]} |" for i in range(env.action_space.n)]
    lines += ["", actions, ""]
    return lines


def render() -> str:
    """The generated section (without its markers)."""
    from objsearch.eval.suites import make_suite
    from objsearch.gridworld.batched import ACTION_NAMES
    from objsearch.gridworld.env import GridWorldEnv
    from objsearch.sim.env import HouseEnv
    from objsearch.sim.navgraph import ACTIONS

    grid = make_suite("gridworld").make_env()
    house = make_suite("house-single").make_env()
    lines = [
        "## Actions and observations",
        "",
        "`reset(task)` gets the episode's `AgentTask`, `act(observation)` the env's observation, and",
        "returns an action of `task.action_space`. (This section is generated from the envs; do not edit it.)",
        "",
    ]
    lines += _world(
        "Grid world (`gridworld`)",
        "gridworld",
        grid,
        ACTION_NAMES,
        docstring_section(GridWorldEnv, "Observation Space") + ' The suite plays `observation="all_goals"`.',
        docstring_section(GridWorldEnv, "Action Space"),
    )
    lines += _world(
        "Houses (`house-single`, `house-multi`, `house-gen`, suite files)",
        "house-single",
        house,
        ACTIONS,
        docstring_section(HouseEnv, "Observation Space"),
        docstring_section(HouseEnv, "Action Space"),
    )
    lines += [
        "#### Ground-truth and predicted observations",
        "",
        f"`--observation gt` (the default): `semantic` and `depth` are rendered ground truth. "
        f"`--observation predicted`: the same keys and spaces. {_predicted_sentence()}",
        "",
    ]
    return "\n".join(lines).strip("\n")


def doc_section(text: str) -> str:
    """The generated part of the doc ``text`` (between the markers)."""
    if BEGIN not in text or END not in text:
        raise RuntimeError(f"{DOC} lacks the markers {BEGIN} ... {END}")
    return text.split(BEGIN, 1)[1].split(END, 1)[0].strip("\n")


def rebuild_doc(check: bool = False) -> int:
    """Rewrite the generated section of ``DOC`` from the envs; with ``check``, only compare:
    1 (and a message on stderr) if it is stale, else 0."""
    from objsearch.fileio import atomic_write

    text = DOC.read_text()
    fresh = render()
    if check:
        if doc_section(text) != fresh:
            print(f"{DOC}: the generated section is stale; run {COMMAND}", file=sys.stderr)
            return 1
        print(f"{DOC}: the generated section is current", file=sys.stderr)
        return 0
    before, rest = text.split(BEGIN, 1)
    after = rest.split(END, 1)[1]
    with atomic_write(DOC) as f:
        f.write(f"{before}{BEGIN}\n{fresh}\n{END}{after}")
    print(f"{DOC} updated", file=sys.stderr)
    return 0


if __name__ == "__main__":  # the old entry point, gone: say where it went
    raise SystemExit(f"python -m objsearch.eval.agent_io is now: {COMMAND} [--check]")
