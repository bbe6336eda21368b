"""The layers of objsearch (DEVELOPERS.md): a lower layer never imports a higher one, and
objsearch never imports the agents (``objsearch_agents``).

Every module under ``objsearch/`` is parsed (not imported); every ``import`` in it counts,
also those inside functions. Layers, low to high: ``gridworld`` and ``house``, ``sim``,
``perception``, ``eval``, ``leaderboard``. The top-level helpers (``errors``, ``fileio``,
...) import no layer; the top-level glue (``GLUE``: ``cli.py`` and the subcommand modules
that drive several layers) may import any layer, and reaches the agents only inside a
function, when its command runs.
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
