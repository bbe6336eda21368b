"""Generator versions are packages, registered in one place, that never reach a newer version.

Every module under ``objsearch/house/`` is parsed (not imported), as ``tests/test_layers.py``
does; every import counts, also those inside functions and under ``TYPE_CHECKING``. A module
reaches what it imports, what those import, and so on (importing ``a.b.c`` runs ``a.b``'s
``__init__`` too). A version reaches no newer version (what it reaches is frozen with it); a
newer one may build on the stages of an older, frozen one that it names in ``BUILDS_ON``
(``house-gen-3`` runs ``house-gen-2``'s with its own limits), and on no other; the house
modules import each other without a circle; each version exports the ``Generator`` that the
registry names it by.
"""

import ast
from pathlib import Path

import pytest

from objsearch.house.generators import GENERATORS, Generator, get_generator

ROOT = Path(__file__).resolve().parents[2]
HOUSE = ROOT / "objsearch" / "house"
VERSIONS = sorted(
    p.name for p in HOUSE.iterdir() if p.is_dir() and (p / "__init__.py").exists() and p.name[:3] == "gen"
)


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(p): p for p in HOUSE.rglob("*.py")}


def imports_of(module: str) -> set[str]:
    """The house modules ``module`` imports directly (a name imported from a package that is a
    module counts as that module; a package's ``__init__`` counts for every module under it, but
    for the modules inside that package)."""
    tree = ast.parse(MODULES[module].read_text())
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        else:
            continue
        for name in names:
            parts = name.split(".")
            found |= {".".join(parts[:k]) for k in range(1, len(parts) + 1)} & MODULES.keys()
    # a module's own packages are already being imported when it runs
    own = {".".join(module.split(".")[:k]) for k in range(1, module.count(".") + 2)}
    return found - own


GRAPH = {m: imports_of(m) for m in MODULES}


def reached(start: str) -> set[str]:
    seen, todo = set(), [start]
    while todo:
        for m in GRAPH[todo.pop()]:
            if m not in seen:
                seen.add(m)
                todo.append(m)
    return seen


#: The older versions a version builds on (their stages, frozen with them).
BUILDS_ON = {"gen3": ("gen2",), "gen4": ("gen2", "gen3")}


def test_there_are_generator_packages():
    assert VERSIONS == ["gen1", "gen2", "gen3", "gen4"], VERSIONS


@pytest.mark.parametrize("version", VERSIONS)
def test_a_generator_package_reaches_no_other(version):
    own = f"objsearch.house.{version}"
    allowed = BUILDS_ON.get(version, ())
    assert all(int(v[3:]) < int(version[3:]) for v in allowed), "a version builds only on older ones"
    others = [f"objsearch.house.{v}" for v in VERSIONS if v != version and v not in allowed]
    for module in sorted(m for m in MODULES if m == own or m.startswith(own + ".")):
        bad = sorted(m for m in reached(module) if any(m == o or m.startswith(o + ".") for o in others))
        assert not bad, f"{module} reaches {bad}: a generator version imports only the shared house modules"


def test_shared_house_modules_import_no_generator_package():
    """Shared modules read versions through the registry (``generators.get_generator``) only;
    ``rooms`` (single rooms, a mode of ``house-gen-2`` that belongs in ``gen2``) is the exception."""
    shared = [m for m in MODULES if not any(m.startswith(f"objsearch.house.{v}") for v in VERSIONS)]
    for module in sorted(shared):
        direct = sorted(m for m in GRAPH[module] if any(m.startswith(f"objsearch.house.{v}") for v in VERSIONS))
        if module != "objsearch.house.rooms":
            assert not direct, f"{module} imports {direct}; use objsearch.house.generators.get_generator"


def test_house_modules_import_no_circle():
    for module in sorted(MODULES):
        assert module not in reached(module), f"{module} reaches itself through {sorted(GRAPH[module])}"


@pytest.mark.parametrize("name", list(GENERATORS))
def test_registry_names_each_version_by_its_record(name):
    record = get_generator(name)
    assert isinstance(record, Generator) and record.name == name
    assert GENERATORS[name] in {f"objsearch.house.{v}" for v in VERSIONS}
    assert record.attempts > 0


def test_shuffle_keys_are_never_shared():
    keys = [get_generator(name).shuffle_key for name in GENERATORS]
    assert len(set(keys)) == len(keys), keys
