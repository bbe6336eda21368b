"""docs/add_your_agent.md's "Actions and observations" is the one the envs render
(``objsearch data rebuild agent-io-doc [--check]`` rewrites or checks it)."""

from objsearch.cli import main
from objsearch.eval import agent_io


def test_the_docs_section_is_what_the_envs_render():
    assert agent_io.doc_section(agent_io.DOC.read_text()) == agent_io.render(), (
        f"docs/add_your_agent.md is stale: run {agent_io.COMMAND}"
    )


def test_the_section_names_every_action_and_observation_key():
    text = agent_io.render()
    for name in ("| 3 | right |", "| 5 | move_right |", "`image`", "`semantic`", "`depth`", "`target`", "predicted"):
        assert name in text, name


def test_check_fails_on_a_stale_doc(tmp_path, monkeypatch, capsys):
    stale = tmp_path / "doc.md"
    stale.write_text(agent_io.DOC.read_text().replace("| 0 | up |", "| 0 | north |"))
    monkeypatch.setattr(agent_io, "DOC", stale)
    assert main(["data", "rebuild", "agent-io-doc", "--check"]) == 1
    assert f"stale; run {agent_io.COMMAND}" in capsys.readouterr().err
    assert main(["data", "rebuild", "agent-io-doc"]) == 0 and main(["data", "rebuild", "agent-io-doc", "--check"]) == 0
    assert stale.read_text() == agent_io.DOC.read_text().replace("| 0 | north |", "| 0 | up |")
