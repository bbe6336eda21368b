"""The distribution ships every package folder and its data."""

import tomllib
from importlib.metadata import entry_points
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_package_folder_is_listed_in_pyproject():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    found = set()
    for top, name in (("objsearch", "objsearch"), ("agents", "objsearch_agents")):
        for init in (ROOT / top).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / top).parts
            found.add(".".join((name, *rel)))
    assert found == listed, f"add to pyproject.toml [tool.setuptools] packages: {sorted(found - listed)}"


def test_agent_entry_points_resolve():
    for ep in entry_points(group="objsearch.agents"):
        cls = ep.load()
        assert callable(cls.reset) and callable(cls.act), ep.name
