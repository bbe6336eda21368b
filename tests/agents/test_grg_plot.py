import cv2
import numpy as np

from objsearch_agents.grg import GoalsRelationalGraph
from objsearch_agents.grg_plot import CHAINS, chain_recovery, main


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
    assert main([str(tmp_path), "--out", str(tmp_path / "grg.png")]) == 0
    image = cv2.imread(str(tmp_path / "grg.png"))
    assert image.shape == (640, 640, 3) and (image < 250).any()
    assert "chain recovery 100%" in capsys.readouterr().out
    assert main([str(tmp_path / "missing"), "--out", str(tmp_path / "x.png")]) == 2
