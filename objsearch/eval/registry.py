"""Finding agents by name: the entry-point group ``objsearch.agents`` or ``module:Class``.

Entry points are listed without importing anything; only the agent asked for is loaded.
A name registered twice (by two installed packages) is an error, never a silent overwrite.
"""

from __future__ import annotations

import difflib
import importlib
from importlib.metadata import entry_points

from objsearch.errors import UserError

GROUP = "objsearch.agents"


def registered_agents() -> dict[str, str]:
    """Map of agent name -> ``module:attr`` target of every installed agent."""
    found: dict[str, str] = {}
    for ep in entry_points(group=GROUP):
        if ep.name in found and found[ep.name] != ep.value:
            raise UserError(
                f"agent name {ep.name!r} is registered twice ({found[ep.name]} and {ep.value}); "
                "uninstall one of the packages that provide it"
            )
        found[ep.name] = ep.value
    return dict(sorted(found.items()))


def _import_target(target: str, what: str):
    module_name, _, attr = target.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as err:
        if err.name and module_name.startswith(err.name):
            raise UserError(f"{what}: no module named {module_name!r}; is its package installed?") from None
        raise
    try:
        obj = module
        for part in attr.split("."):
            obj = getattr(obj, part)
    except AttributeError:
        raise UserError(f"{what}: module {module_name!r} has no attribute {attr!r}") from None
    return obj


def resolve_agent(spec: str) -> type:
    """The agent class for ``spec``: a registered name or ``package.module:Class``."""
    if ":" in spec:
        cls = _import_target(spec, f"agent {spec!r}")
    else:
        agents = registered_agents()
        if spec not in agents:
            close = difflib.get_close_matches(spec, list(agents), n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise UserError(
                f"unknown agent {spec!r}; {hint}(objsearch-eval --list-agents shows the installed agents; "
                "or pass package.module:Class)"
            )
        cls = _import_target(agents[spec], f"agent {spec!r}")
    if not (callable(getattr(cls, "reset", None)) and callable(getattr(cls, "act", None))):
        raise UserError(f"agent {spec!r} ({cls!r}) has no reset(task) and act(observation) methods")
    return cls


def check_supports(spec: str, cls: type, suite: str) -> None:
    """Refuse, before any episode, an agent that declares worlds (``worlds()``) without the
    suite's world."""
    from objsearch.eval.suites import suite_world

    worlds = getattr(cls, "worlds", None)
    if not callable(worlds):
        return
    world = suite_world(suite)
    if world not in worlds():
        from objsearch.eval.suites import SUITES

        fits = [name for name in SUITES if suite_world(name) in worlds()]
        raise UserError(f"agent {spec!r} runs in the {' and '.join(worlds())} world(s), not in suite {suite!r} "
                        f"({world}); suites it supports: {', '.join(fits)}")


def make_agent(spec: str, checkpoint: str | None = None, suite: str | None = None):
    """Instantiate the agent ``spec`` for ``suite`` and load ``checkpoint`` into it if given.

    An agent class may declare ``worlds()`` (the suites' worlds it runs in: checked first)
    and ``for_suite(suite, checkpoint)`` (builds the agent for that suite, e.g. loading the
    checkpoint shipped for it); otherwise it is built with ``cls()`` and ``load(checkpoint)``."""
    cls = resolve_agent(spec)
    if suite is not None:
        check_supports(spec, cls, suite)
        factory = getattr(cls, "for_suite", None)
        if callable(factory):
            return factory(suite, checkpoint)
    agent = cls()
    if checkpoint is not None:
        if not callable(getattr(agent, "load", None)):
            raise UserError(f"agent {spec!r} takes no checkpoint (it has no load(path) method)")
        agent.load(checkpoint)
    return agent
