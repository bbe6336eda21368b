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
        *_house_rules(house),
    ]
    return "\n".join(lines).strip("\n")


def _house_rules(env) -> list[str]:
    """The rules of the house task, from the constants that define them."""
    from objsearch.house.categories import CATEGORY_IDS, CATEGORY_TABLE_VERSION
    from objsearch.house.occupancy import AGENT_HEIGHT, AGENT_RADIUS
    from objsearch.sim.goals import DEFAULT_RULE, GOAL_CAMERA, PROTOCOLS
    from objsearch.sim.navgraph import GRID, STOP
    from objsearch.sim.suites import OBJECTNAV_SUITES

    camera = env.settings.intrinsics()
    objectnav = PROTOCOLS["objectnav"]
    ids = ", ".join(f"{i} {name}" for name, i in sorted(CATEGORY_IDS.items(), key=lambda kv: kv[1]))
    return [
        "#### The rules of the house task",
        "",
        f"- **The agent** is a cylinder of radius {AGENT_RADIUS} m and height {AGENT_HEIGHT} m on a grid of "
        f"{GRID} m cells with 4 headings: a move goes one cell (ahead, back, left or right, without turning), "
        "a turn 90 degrees. A move that is blocked (a wall or an object within the agent's radius anywhere on "
        "the way) leaves the agent where it was and counts as a step; `collided` says so.",
        f"- **The camera** is {camera['width']} x {camera['height']} pixels, {camera['hfov']:g} x "
        f"{camera['vfov']:g} degrees (horizontal x vertical), {camera['camera_height']:g} m above the floor, "
        f"looking level; `depth` is planar (along the optical axis), clipped to {camera['znear']:g}-"
        f"{camera['zfar']:g} m. `task.camera` holds these parameters (`RenderSettings.intrinsics`): "
        "the pixel (u, v) at depth z is the point ((u + 0.5 - cx) z / fx, (cy - v - 0.5) z / fy, z) "
        "(right, up, forward).",
        f"- **Success** (the paper's protocol, `paper`: every shipped suite but {', '.join(OBJECTNAV_SUITES)}; "
        f"the rule `{DEFAULT_RULE.kind}`): the episode ends, "
        "successfully, when the agent stands on a goal pose of the target category. The goal poses are the "
        f"poses of the whole house whose view (through the goal camera, {GOAL_CAMERA.width} x "
        f"{GOAL_CAMERA.height}, {GOAL_CAMERA.fovy:g} degrees, {GOAL_CAMERA.camera_height:g} m high) shows the "
        f"most pixels of the category: every pose with at least the {DEFAULT_RULE.top_k}th largest area, ties "
        "included, over every object of the category. So the nearest chair may not hold a goal pose, and a "
        "painting mounted high or a coffee table is filled into the view from farther away than one step. "
        "There is no STOP action (`task.stop_action` is None): the episode ends by itself.",
        f"- **Success under ObjectNav** (the `objectnav` protocol: {', '.join(OBJECTNAV_SUITES)}, and suite files "
        "made with `objsearch suite make --protocol objectnav`; results record the protocol): the goal poses are "
        f"every pose whose goal-camera view shows at least {objectnav.goal_rule.min_pixels} pixels of the category "
        f"within {objectnav.goal_rule.max_distance:g} m (rule `{objectnav.goal_rule.kind}`; `task.goal_rule` holds "
        f"it), and the episode succeeds only when the agent calls STOP (action {STOP}, `task.stop_action`) on one. "
        "STOP anywhere else ends the episode as a failure; reaching a goal pose without STOP ends nothing.",
        f"- **The step limit** is the suite's `max_steps` (each suite file records its own; `house-single`: {env.max_steps}, "
        f"the paper's; ObjectNav suites: {objectnav.max_steps}, Habitat's); SPL counts every action, turns, blocked "
        "moves and the STOP included, against the minimal number of actions.",
        f"- **`target` and `semantic`** use the ids of the category table {CATEGORY_TABLE_VERSION} "
        "(`objsearch generate` writes it as `categories.json`); the structure classes are drawn and labelled "
        f"in every frame, the ceiling too: {ids}.",
        "",
    ]


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


if __name__ == "__main__":  # `python -m` of this module, a command until 2026-12-02: name its replacement
    raise SystemExit(f"python -m objsearch.eval.agent_io is now: {COMMAND} [--check]")
