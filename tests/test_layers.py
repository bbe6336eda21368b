"""The layers of objsearch (DEVELOPERS.md): a lower layer never imports a higher one, and
objsearch never imports the agents (``objsearch_agents``).

Every module under ``objsearch/`` is parsed (not imported); every ``import`` in it counts,
also those inside functions. Layers, low to high: ``gridworld`` and ``house``, ``sim``,
``perception``, ``eval``, ``leaderboard``. The top-level helpers (``errors``, ``fileio``,
...) import no layer; the top-level glue (``GLUE``: ``cli.py`` and the subcommand modules
that drive several layers) may import any layer, and reaches the agents only inside a
function, when its command runs.

No two modules of objsearch and the agents import each other, directly or round a circle
(every import counts here too), no module is longer than ``MAX_LINES`` lines, and the agents'
grid-world and house packages (``agents/gridworld``, ``agents/house``) never import each other.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "objsearch"
LAYERS = {"gridworld": 0, "house": 0, "sim": 1, "perception": 2, "eval": 3, "leaderboard": 4}
GLUE = {"cli.py", "train.py", "data_cli.py", "plot_cli.py", "api.py"}
AGENTS = "objsearch_agents"


def imported_modules(tree: ast.AST, module_level_only: bool = False) -> list[tuple[int, str]]:
    """(line, absolute module name) of every import in ``tree`` (objsearch has no relative imports)."""
    nodes = tree.body if module_level_only else ast.walk(tree)
    found = []
    for node in nodes:
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            assert node.level == 0, f"line {node.lineno}: relative import"
            found += [(node.lineno, f"{node.module}.{alias.name}") for alias in node.names]
    return found


def layer_of(module: str) -> int | None:
    """The layer of ``objsearch.LAYER...`` (None: not a layer, e.g. objsearch.errors)."""
    parts = module.split(".")
    return LAYERS.get(parts[1]) if len(parts) > 1 and parts[0] == "objsearch" else None


MODULES = sorted(p.relative_to(ROOT) for p in ROOT.rglob("*.py"))


@pytest.mark.parametrize("rel", MODULES, ids=str)
def test_no_module_imports_a_higher_layer_or_the_agents(rel):
    tree = ast.parse((ROOT / rel).read_text(), filename=str(rel))
    if len(rel.parts) == 1 and rel.name in GLUE:
        bad = [(line, m) for line, m in imported_modules(tree, module_level_only=True) if m.split(".")[0] == AGENTS]
        assert not bad, f"objsearch/{rel} imports the agents at module level (import them inside the command): {bad}"
        return
    own = LAYERS.get(rel.parts[0], -1) if len(rel.parts) > 1 else -1  # -1: a top-level helper
    for line, module in imported_modules(tree):
        assert module.split(".")[0] != AGENTS, (
            f"objsearch/{rel}:{line} imports {module}: objsearch never imports the agents"
        )
        layer = layer_of(module)
        assert layer is None or layer <= own, (
            f"objsearch/{rel}:{line} imports {module}, a higher layer than its own; move the code that needs both "
            "to the lower of the layers that can see both (or to the top-level glue)"
        )


def test_every_layer_is_known():
    folders = {p.name for p in ROOT.iterdir() if (p / "__init__.py").exists()}
    assert folders == set(LAYERS), f"give the new package folder a layer in LAYERS: {sorted(folders ^ set(LAYERS))}"


# -- no import circles, no long modules (issue 44) ----------------------------------------------
PACKAGES = {"objsearch": ROOT, "objsearch_agents": ROOT.parent / "agents"}  # import name -> folder
MAX_LINES = 450  # DESIGN.md: a module does one job; a file over ~400 lines is usually two modules
NOT_MODULES = (ROOT / "leaderboard" / "templates",)  # the page template is data, not a module


def package_modules() -> dict[str, Path]:
    """Every module of objsearch and the agents (``objsearch_agents``), by its import name."""
    out = {}
    for package, folder in PACKAGES.items():
        for path in sorted(folder.rglob("*.py")):
            parts = path.relative_to(folder).with_suffix("").parts
            out[".".join((package, *parts[: -1 if parts[-1] == "__init__" else None]))] = path
    return out


def import_graph() -> dict[str, dict[str, int]]:
    """module -> {module of objsearch or the agents it imports: line}, every import counted (those
    inside functions too: a circle of lazy imports is still two modules that need each other)."""
    modules = package_modules()
    graph = {}
    for name, path in modules.items():
        edges: dict[str, int] = {}
        for line, imported in imported_modules(ast.parse(path.read_text(), filename=str(path))):
            while imported and imported not in modules:  # `from a.b import c`: module a.b.c, else a.b
                imported = imported.rpartition(".")[0]
            if imported and imported != name:
                edges.setdefault(imported, line)
        graph[name] = edges
    return graph


def find_circle(graph: dict[str, dict[str, int]]) -> list[str] | None:
    """One circle of ``graph`` (its modules, the first again at the end), or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return path[path.index(nxt) :] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def test_no_import_circle():
    graph = import_graph()
    circle = find_circle(graph)
    if circle:
        steps = " -> ".join(f"{a} (line {graph[a][b]})" for a, b in zip(circle, circle[1:]))
        raise AssertionError(
            f"import circle: {steps} -> {circle[0]}; move what the modules share into a module that both "
            "import, or the code that needs both into the one that is imported"
        )


def test_the_circle_finder_finds_circles_and_only_circles():
    assert find_circle({"a": {"b": 1}, "b": {"c": 2}, "c": {}}) is None
    assert find_circle({"a": {"b": 1}, "b": {"c": 2}, "c": {"a": 3}}) == ["a", "b", "c", "a"]
    assert find_circle({"a": {"b": 1}, "b": {"b": 2}}) == ["b", "b"]
    tree = ast.parse(
        "import objsearch.sim.world\nfrom objsearch.sim import suite_record\ndef f():\n    import objsearch\n"
    )
    assert [m for _, m in imported_modules(tree)] == ["objsearch.sim.world", "objsearch.sim.suite_record", "objsearch"]


@pytest.mark.parametrize("path", sorted(package_modules().values()), ids=lambda p: str(p.relative_to(ROOT.parent)))
def test_no_module_is_longer_than_the_limit(path):
    if any(folder in path.parents for folder in NOT_MODULES):
        return
    lines = len(path.read_text().splitlines())
    assert lines <= MAX_LINES, (
        f"{path.relative_to(ROOT.parent)} has {lines} lines, more than {MAX_LINES}: split it by job "
        "(shared/DESIGN.md: a module does one job); keep the old import path working where other code uses it"
    )


# -- the agents' two worlds (issue 44) ----------------------------------------------------------
WORLDS = ("gridworld", "house")  # folders of agents/: neither imports the other


@pytest.mark.parametrize("world", WORLDS)
def test_the_agents_worlds_never_import_each_other(world):
    other = next(w for w in WORLDS if w != world)
    graph = import_graph()
    own, banned = f"{AGENTS}.{world}", f"{AGENTS}.{other}"
    bad = [
        f"{module} (line {line}) imports {imported}"
        for module, edges in graph.items()
        if module == own or module.startswith(own + ".")
        for imported, line in edges.items()
        if imported == banned or imported.startswith(banned + ".")
    ]
    assert not bad, (
        f"agents/{world}/ imports agents/{other}/: {bad}; what both worlds use goes into agents/core/ or "
        "agents/methods/, what pairs them into agents/learned.py"
    )
