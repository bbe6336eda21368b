from importlib.metadata import EntryPoint

import pytest

from objsearch.errors import UserError
from objsearch.eval import registry
from objsearch.eval.registry import make_agent, registered_agents, resolve_agent
from objsearch_agents.baselines.oracle import OracleAgent
from objsearch_agents.baselines.random_agent import RandomAgent


def test_builtin_agents_are_registered():
    agents = registered_agents()
    assert agents["random"] == "objsearch_agents.baselines.random_agent:RandomAgent"
    assert agents["oracle"] == "objsearch_agents.baselines.oracle:OracleAgent"


def test_resolve_by_name_and_by_path():
    assert resolve_agent("oracle") is OracleAgent
    assert resolve_agent("objsearch_agents.baselines.random_agent:RandomAgent") is RandomAgent


def test_unknown_agent_suggests_the_close_name():
    with pytest.raises(UserError, match=r"unknown agent 'orcale'; did you mean 'oracle'\?.*--list-agents"):
        resolve_agent("orcale")


def test_bad_module_path_is_a_clear_error():
    with pytest.raises(UserError, match="no module named 'nopkg.mod'"):
        resolve_agent("nopkg.mod:Agent")
    with pytest.raises(UserError, match="has no attribute 'Nope'"):
        resolve_agent("objsearch_agents.baselines.oracle:Nope")


def test_class_without_the_protocol_is_rejected():
    with pytest.raises(UserError, match="reset"):
        resolve_agent("objsearch.errors:UserError")


def test_checkpoint_for_agent_without_load_is_rejected():
    with pytest.raises(UserError, match="no load"):
        make_agent("random", checkpoint="x.pt")


def test_duplicate_names_are_an_error(monkeypatch):
    eps = [
        EntryPoint("twin", "a.mod:A", registry.GROUP),
        EntryPoint("twin", "b.mod:B", registry.GROUP),
    ]
    monkeypatch.setattr(registry, "entry_points", lambda group: eps)
    with pytest.raises(UserError, match="registered twice"):
        registered_agents()


def test_lookup_is_lazy(monkeypatch):
    # listing agents imports none of them
    import sys

    monkeypatch.delitem(sys.modules, "objsearch_agents.baselines.oracle", raising=False)
    registered_agents()
    assert "objsearch_agents.baselines.oracle" not in sys.modules
