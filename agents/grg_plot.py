"""Drawing a learned Goals Relational Graph, in either world, and checking that the grid
world's one recovers its goal chains.

    objsearch plot grg agents/checkpoints/gridworld/hrl_grg --out grg.png      # the paper's Figure 4
    objsearch plot grg agents/checkpoints/house-single/hrl_grg --out grg.png   # the paper's Figure 5

``plot_grg`` is the one path behind the command: it loads ``grg.npz`` (from a checkpoint or
run folder, or the file itself; digests checked), tells the world by the graph's nodes (16
goals: the grid world; one node per object category: the houses) unless told, draws it and
writes the PNG atomically. Each world draws its own figure: ``gridworld.grg_figure`` (the
goals' chains) and ``house.grg_figure`` (the strongest edges between object categories).
"""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_write
from objsearch_agents.core.grg import GoalsRelationalGraph

WORLDS = ("gridworld", "house")


def load_grg(run: str | os.PathLike) -> tuple[GoalsRelationalGraph, Path]:
    """The graph of ``run`` (a folder with ``grg.npz``, or the file) and its file's path."""
    path = Path(run)
    path = path / "grg.npz" if path.is_dir() else path
    if not path.exists():
        raise UserError(
            f"no GRG at {path}: give a checkpoint or run folder with a grg.npz (e.g. "
            "agents/checkpoints/gridworld/hrl_grg) or a grg.npz file"
        )
    return GoalsRelationalGraph.load(path), path


def world_of(graph: GoalsRelationalGraph, path: Path) -> str:
    """``gridworld`` or ``house``, by the nodes the graph can see (16 goals, or the object categories)."""
    from objsearch_agents.gridworld.grg_figure import GRID_GOALS
    from objsearch_agents.house.tables import NUM_OBJECTS

    if graph.observable == GRID_GOALS:
        return "gridworld"
    if graph.observable == NUM_OBJECTS:
        return "house"
    raise UserError(
        f"{path}: a GRG over {graph.observable} observable nodes is neither the grid world's "
        f"({GRID_GOALS} goals) nor the houses' ({NUM_OBJECTS} object categories)"
    )


def write_png(image: np.ndarray, out: str | os.PathLike) -> None:
    """Write the BGR ``image`` to ``out`` as PNG atomically."""
    if not str(out).lower().endswith(".png"):
        raise UserError(f"--out {out}: the figure is a PNG; give a file name ending in .png")
    ok, png = cv2.imencode(".png", image)
    with atomic_write(out, "wb") as f:
        f.write(png.tobytes())


def plot_grg(
    run: str | os.PathLike, out: str | os.PathLike = "grg.png", world: str | None = None, edges: int | None = None
) -> list[str]:
    """Draw the GRG of ``run`` to the PNG ``out``; return the lines to print.

    Args:
        run: a checkpoint or run folder with ``grg.npz``, or a ``grg.npz`` file.
        out: the PNG to write.
        world: ``gridworld`` or ``house``; None: told by the graph.
        edges: houses: at most this many edges (default 24). The grid-world figure draws
            every goal's two strongest out-edges and takes no ``edges``.
    """
    graph, path = load_grg(run)
    found = world_of(graph, path)
    if world is not None and world != found:
        raise UserError(f"{path} holds a {found} GRG, not a {world} one; leave out --world to draw it as {found}")
    weights = graph.edge_weights()
    if found == "gridworld":
        if edges is not None:
            raise UserError(
                "--edges applies to house GRGs; the grid-world figure draws each goal's 2 strongest out-edges"
            )
        from objsearch_agents.gridworld.grg_figure import chain_recovery, draw_graph

        write_png(draw_graph(weights), out)
        return [f"wrote {out}; chain recovery {chain_recovery(weights):.0%}"]
    from objsearch_agents.house.grg_figure import draw, strongest_edges

    if edges is not None and edges < 1:
        raise UserError(f"--edges {edges}: draw at least one edge")
    strongest = strongest_edges(weights, limit=24 if edges is None else edges)
    write_png(draw(strongest), out)
    return [*(f"{a:>16} -> {b:<16} {w:.2f}" for a, b, w in strongest), f"wrote {out}"]


if __name__ == "__main__":  # `python -m` of this module, a command until 2026-12-02: name its replacement
    raise SystemExit("python -m objsearch_agents.grg_plot is now: objsearch plot grg RUN [--out FILE]")
