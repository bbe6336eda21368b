import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from objsearch.cli import main
from objsearch_agents.core.grg import GoalsRelationalGraph
from objsearch_agents.gridworld.grg_figure import CHAINS, chain_recovery


def chain_graph() -> GoalsRelationalGraph:
    """A graph counted from options in which chain neighbours are seen at once and other
    goals never: the structure the grid world's generator plants."""
    graph = GoalsRelationalGraph(17, observable=16)
    for chain in CHAINS:
        for pos, goal in enumerate(chain):
            first_seen = np.zeros(16, dtype=int)
            for p in (pos - 1, pos + 1):
                if 0 <= p < len(chain):
                    first_seen[chain[p]] = 1
            for _ in range(5):
                graph.record_option(goal, first_seen)
    return graph


def test_chain_recovery_of_a_chain_graph_and_of_random_weights():
    assert chain_recovery(chain_graph().edge_weights()) == 1.0
    random = np.random.default_rng(0).random((17, 17))
    assert chain_recovery(random) < 0.5


def test_plot_writes_a_png(tmp_path, capsys):
    chain_graph().save(tmp_path / "grg.npz")
    assert main(["plot", "grg", str(tmp_path), "--out", str(tmp_path / "grg.png")]) == 0
    image = cv2.imread(str(tmp_path / "grg.png"))
    assert image.shape == (640, 640, 3) and (image < 250).any()
    assert "chain recovery 100%" in capsys.readouterr().out


def test_plot_of_the_shipped_house_checkpoint_is_figure_5(tmp_path, capsys):
    """One command for both worlds: a house GRG is told by its nodes and drawn with its edge list."""
    out = tmp_path / "house.png"
    checkpoint = Path(__file__).resolve().parents[2] / "agents" / "checkpoints" / "house-single" / "hrl_grg"
    assert main(["plot", "grg", str(checkpoint), "--out", str(out), "--edges", "6"]) == 0
    image = cv2.imread(str(out))
    assert image.shape == (720, 720, 3) and (image < 250).any()
    lines = capsys.readouterr().out.splitlines()
    assert lines[-1] == f"wrote {out}" and 1 <= len(lines) - 1 <= 6 and " -> " in lines[0]


@pytest.mark.parametrize(
    "args, needle",
    [
        (["{tmp}/missing"], "no GRG at {tmp}/missing"),
        (["{tmp}/bad.npz"], "cannot read GRG file {tmp}/bad.npz"),
        (["{tmp}", "--world", "house"], "holds a gridworld GRG, not a house one"),
        (["{tmp}", "--edges", "3"], "--edges applies to house GRGs"),
        (["{tmp}", "--out", "{tmp}/grg.jpg"], "--out {tmp}/grg.jpg: the figure is a PNG"),
    ],
)
def test_plot_refuses_bad_input_naming_it(tmp_path, capsys, args, needle):
    chain_graph().save(tmp_path / "grg.npz")
    (tmp_path / "bad.npz").write_bytes(b"not an npz")
    args = [a.format(tmp=tmp_path) for a in args]
    out = [] if "--out" in args else ["--out", str(tmp_path / "x.png")]
    assert main(["plot", "grg", *args, *out]) == 2
    assert needle.format(tmp=tmp_path) in capsys.readouterr().err
    assert not list(tmp_path.glob("x.png")) and not list(tmp_path.glob("*.jpg"))


def test_shipped_hrl_grg_graph_recovers_the_goal_chains():
    """The learned graph of the shipped checkpoint links most goals to a chain neighbour
    (the structure the map generator plants, which the paper's Figure 4 shows)."""
    from objsearch.eval.registry import make_agent

    agent = make_agent("hrl_grg")
    assert agent.loaded_from and agent.loaded_from.endswith("checkpoints/gridworld/hrl_grg/policy.pt")
    assert chain_recovery(agent.policy.grg.edge_weights()) >= 0.75


LEARNED = ("dqn", "hdqn", "hrl_grg", "hrl_grg_no_relation", "hrl_grg_no_termination", "hrl_grg_no_high_level")


@pytest.mark.parametrize("name", LEARNED)
def test_learned_agents_load_their_shipped_checkpoint(name):
    """`objsearch-eval --agent NAME` evaluates the shipped weights, which carry the command that made them."""
    from objsearch.eval.registry import make_agent

    agent = make_agent(name)
    assert agent.loaded_from, f"no shipped checkpoint in agents/checkpoints/gridworld/{name}/"
    folder = Path(agent.loaded_from).parent
    assert folder.name == name and (folder / "command.txt").read_text().startswith(f"objsearch train --agent {name} ")
    assert (folder / "README.md").is_file() and (folder / "log.csv").is_file()


def test_an_agent_without_a_shipped_checkpoint_starts_untrained(monkeypatch):
    from objsearch_agents.dqn import DQNAgent

    monkeypatch.setattr(DQNAgent, "checkpoint_name", "not-shipped")
    assert DQNAgent().loaded_from is None


def test_house_figure_labels_cross_no_node_and_no_other_label():
    """The labels run outwards along their nodes' rays: with the 24 longest category names none
    covers a node or another label, and all stay inside the picture (the paper's Figure 5)."""
    from objsearch.house.categories import CATEGORY_NAMES, FIRST_OBJECT_ID
    from objsearch_agents.house.grg_figure import FONT, FONT_SCALE, NODE_R, label_box, node_angles

    objects = [n for i, n in CATEGORY_NAMES.items() if i >= FIRST_OBJECT_ID]
    size, names = 720, sorted(objects, key=lambda n: -cv2.getTextSize(n, FONT, FONT_SCALE, 1)[0][0])[:24]
    centre, radius = size / 2, size * 0.30
    angles = node_angles(len(names))
    nodes = [(int(centre + radius * math.cos(a)), int(centre + radius * math.sin(a))) for a in angles]
    masks = []
    for name, (x, y), angle in zip(names, nodes, angles):
        box = label_box(name, x, y, angle)
        assert box.min() >= 0 and box.max() < size, f"{name}'s label leaves the picture"
        mask = np.zeros((size, size), np.uint8)
        cv2.fillPoly(mask, [np.round(box).astype(np.int32)], 1)
        for other in nodes:
            ring = np.zeros_like(mask)
            cv2.circle(ring, other, NODE_R, 1, -1)
            assert not (mask & ring).any(), f"{name}'s label covers a node"
        masks.append(mask)
    assert np.sum(masks, axis=0).max() == 1, "two labels overlap"
