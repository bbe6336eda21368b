"""Finding agents by name: the entry-point group ``objsearch.agents``, ``module:Class`` or
``path/to/file.py:Class``.

Entry points are listed without importing anything; only the agent asked for is loaded.
A name registered twice (by two installed packages) is an error, never a silent overwrite.
A ``module:Class`` is also looked for in the folder the evaluation was started from (as
``python -m`` does), and a relative file path is taken from there; worker processes get
that folder (``folder``) so that they build the same agent.
"""

from __future__ import annotations

import difflib
import functools
import hashlib
import importlib
import importlib.util
import os
import sys
from importlib.metadata import entry_points
from pathlib import Path

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


def is_file_spec(spec: str) -> bool:
    """Whether ``spec`` names its agent by a file: ``path/to/file.py:Class``."""
    module, _, _ = spec.rpartition(":")
    return module.endswith(".py") or "/" in module or os.sep in module


def recorded_spec(spec: str, folder: str | None = None) -> str:
    """``spec`` as a results file records it: a file agent's path made absolute (relative
    paths are taken from ``folder``, default the current one), so that a replay from another
    folder (``objsearch leaderboard verify`` from the repository root) finds the same file;
    a name or ``module:Class`` as given."""
    if not is_file_spec(spec):
        return spec
    module, _, attr = spec.rpartition(":")
    return f"{Path(folder or os.getcwd(), module).resolve().as_posix()}:{attr}"


def _import_file(path: Path, what: str):
    """The Python file ``path`` loaded as a module (once per process; registered in
    ``sys.modules`` under a name made from its absolute path, so its classes pickle)."""
    path = path.resolve()
    if not path.is_file():
        raise UserError(
            f"{what}: no file {path}; give the path of the agent's .py file, relative to the current folder or absolute"
        )
    name = f"objsearch_agent_file_{path.stem}_{hashlib.sha1(str(path).encode()).hexdigest()[:8]}"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[name]
            raise
    return sys.modules[name]


def _import_target(target: str, what: str, folder: str | None = None):
    """The object ``module:attr`` (or ``file.py:attr``), modules also looked for in
    ``folder`` (default: the current one)."""
    folder = os.path.abspath(folder or os.getcwd())
    module_name, _, attr = target.rpartition(":")
    if is_file_spec(target):
        module = _import_file(Path(folder, module_name), what)
    else:
        if folder not in sys.path:
            sys.path.append(folder)  # after the installed packages: an installed agent wins
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as err:
            if err.name and module_name.startswith(err.name):
                raise UserError(
                    f"{what}: no module named {module_name!r}, neither installed nor in {folder}; "
                    "install its package, run from the folder that holds it, or give its file "
                    "(path/to/file.py:Class)"
                ) from None
            raise
    try:
        obj = module
        for part in attr.split("."):
            obj = getattr(obj, part)
    except AttributeError:
        raise UserError(f"{what}: module {module_name!r} has no attribute {attr!r}") from None
    return obj


def resolve_agent(spec: str, folder: str | None = None) -> type:
    """The agent class for ``spec``: a registered name, ``package.module:Class`` or
    ``path/to/file.py:Class`` (modules and relative paths also from ``folder``, default:
    the current folder)."""
    if ":" in spec:
        cls = _import_target(spec, f"agent {spec!r}", folder)
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


def is_privileged(spec: str) -> bool:
    """Whether ``spec`` (as a results file records its agent) is a registered agent, by its
    name or its registered ``module:Class``, whose class declares ``privileged = True``: it
    reads ground truth beyond its observations (the oracle's shortest path, the rooms that
    hold the target), so its results are shown marked and never ranked (``declares``)."""
    return declares(spec, "privileged")


def is_training_free(spec: str) -> bool:
    """Whether ``spec`` is a registered agent whose class declares ``training_free = True``: it
    learns nothing by training (no training runs, no seeds of training to vary; a prior counted
    from a suite's training houses is not training), so the board shows no training runs for
    it (``declares``)."""
    return declares(spec, "training_free")


@functools.cache
def declares(spec: str, flag: str) -> bool:
    """Whether ``spec`` (as a results file records its agent: a registered name or its
    registered ``module:Class``) is a registered agent whose class sets ``flag`` to True.

    The one place that decides what an agent declares. Only registered agents are imported
    (installed code, as ``objsearch-eval --agent NAME`` runs it); a file agent or an
    unregistered module is never imported here, so rendering a leaderboard runs no code that a
    submission names, and such an agent declares nothing (``docs/failure_modes.md``: what
    verify does not prove)."""
    agents = registered_agents()
    target = agents.get(spec) or (spec if spec in agents.values() else None)
    if target is None:
        return False
    try:
        cls = _import_target(target, f"agent {spec!r}")
    except (ImportError, UserError):  # a broken installed package: it cannot be replayed either
        return False
    return getattr(cls, flag, False) is True


def agent_label(spec: str) -> str:
    """The agent of a results file as the leaderboard shows it: a registered name or
    ``module:Class`` as recorded, a file agent as its file's name and class (``my_agent.py:Agent``)."""
    if not is_file_spec(spec):
        return spec
    module, _, attr = spec.rpartition(":")
    return f"{Path(module).name}:{attr}"


def check_supports(spec: str, cls: type, suite: str) -> None:
    """Refuse, before any episode, an agent that declares worlds (``worlds()``) without the
    suite's world, or protocols (``protocols()``) without the suite's protocol."""
    from objsearch.eval.suites import suite_world

    protocols = getattr(cls, "protocols", None)
    if callable(protocols):
        check_protocol(spec, protocols(), suite)
    worlds = getattr(cls, "worlds", None)
    if not callable(worlds):
        return
    world = suite_world(suite)
    if world not in worlds():
        from objsearch.eval.suites import SUITES

        fits = [name for name in SUITES if suite_world(name) in worlds()]
        raise UserError(
            f"agent {spec!r} runs in the {' and '.join(worlds())} world(s), not in suite {suite!r} "
            f"({world}); suites it supports: {', '.join(fits)}"
        )


def check_protocol(spec: str, protocols, suite: str) -> None:
    """Refuse an agent whose ``protocols()`` lack the suite's protocol: one without a STOP
    action on a suite whose success needs STOP (``objectnav``)."""
    from objsearch.eval.suites import suite_protocol
    from objsearch.sim.suites import OBJECTNAV_SUITES

    protocol = suite_protocol(suite)
    if protocol in protocols:
        return
    if suite in OBJECTNAV_SUITES:
        twin = f" ({OBJECTNAV_SUITES[suite]} has the same episodes)"
    else:
        twin = (
            f" (objsearch suite make --protocol paper makes one of {suite}'s houses)" if suite.endswith(".json") else ""
        )
    raise UserError(
        f"agent {spec!r} plays the {' and '.join(protocols)} protocol, not the {protocol} protocol of suite {suite!r}: "
        f"learned agents have no STOP action, and {protocol} counts success only when the agent calls STOP at the "
        f"goal; use a suite of the paper protocol{twin}"
    )


def make_agent(spec: str, checkpoint: str | None = None, suite: str | None = None, folder: str | None = None):
    """Instantiate the agent ``spec`` for ``suite`` and load ``checkpoint`` into it if given
    (``folder``: where modules and relative paths of ``spec`` are also looked for; default:
    the current folder).

    An agent class may declare ``worlds()`` (the suites' worlds it runs in) and
    ``protocols()`` (the protocols it plays: ``paper``, ``objectnav``), both checked first,
    and ``for_suite(suite, checkpoint)`` (builds the agent for that suite, e.g. loading the
    checkpoint shipped for it); otherwise it is built with ``cls()`` and ``load(checkpoint)``."""
    from objsearch.eval.agent import build_agent

    cls = resolve_agent(spec, folder)
    if suite is not None:
        check_supports(spec, cls, suite)
    return build_agent(cls, spec, checkpoint, suite)
