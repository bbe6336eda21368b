"""Drawing a learned Goals Relational Graph, in either world, and checking that the grid
world's one recovers its goal chains.

    objsearch plot grg agents/checkpoints/gridworld/hrl_grg --out grg.png      # the paper's Figure 4
    objsearch plot grg agents/checkpoints/house-single/hrl_grg --out grg.png   # the paper's Figure 5

``plot_grg`` is the one path behind the command: it loads ``grg.npz`` (from a checkpoint or
run folder, or the file itself; digests checked), tells the world by the graph's nodes (16
goals: the grid world; one node per object category: the houses) unless told, draws it and
writes the PNG atomically. The grid-world drawing is here (``draw_graph``): goals on a
circle in id order (the two chains g0..g7 and g8..g15 side by side); an arrow i -> j for
each goal's strongest out-edges, darker and thicker for larger weights. The house drawing
is ``objsearch_agents.house.grg_figure``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import cv2
import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_write
from objsearch_agents.grg import GoalsRelationalGraph

WORLDS = ("gridworld", "house")
GRID_GOALS = 16
CHAINS = (tuple(range(0, 8)), tuple(range(8, 16)))
UNSEEN = (2, 5, 10, 13)


def chain_recovery(weights: np.ndarray, chains=CHAINS, top: int = 2) -> float:
    """Fraction of goals whose chain neighbour (predecessor or successor) is among their
    ``top`` strongest out-edges (self-edges and the back-up node ignored)."""
    goals = [g for chain in chains for g in chain]
    w = weights[np.ix_(goals, goals)].astype(float)
    np.fill_diagonal(w, -np.inf)
    index = {g: i for i, g in enumerate(goals)}
    hits = 0
    for chain in chains:
        for pos, goal in enumerate(chain):
            neighbours = {index[chain[p]] for p in (pos - 1, pos + 1) if 0 <= p < len(chain)}
            strongest = set(np.argsort(-w[index[goal]], kind="stable")[:top].tolist())
            hits += bool(neighbours & strongest)
    return hits / len(goals)


def draw_graph(weights: np.ndarray, edges_per_node: int = 2, size: int = 640) -> np.ndarray:
    """BGR image of the graph over the 16 goals (node i at angle i * 360 / 16)."""
    goals = 16
    img = np.full((size, size, 3), 255, np.uint8)
    centre, radius = size / 2, size * 0.38
    at = [
        (
            int(centre + radius * math.cos(2 * math.pi * i / goals - math.pi / 2)),
            int(centre + radius * math.sin(2 * math.pi * i / goals - math.pi / 2)),
        )
        for i in range(goals)
    ]
    w = weights[:goals, :goals].astype(float).copy()
    np.fill_diagonal(w, 0.0)
    for i in range(goals):
        for j in np.argsort(-w[i], kind="stable")[:edges_per_node]:
            if w[i, j] <= 0:
                continue
            shade = int(200 * (1 - w[i, j]))
            start, end = np.array(at[i], float), np.array(at[j], float)
            direction = (end - start) / max(np.linalg.norm(end - start), 1e-9)
            tip = end - direction * 22  # stop at the node's rim
            cv2.arrowedLine(
                img,
                tuple(int(v) for v in start + direction * 22),
                tuple(int(v) for v in tip),
                (shade, shade, shade),
                max(1, int(round(4 * w[i, j]))),
                cv2.LINE_AA,
                tipLength=0.08,
            )
    for i, (x, y) in enumerate(at):
        colour = (60, 150, 230) if i < 8 else (80, 180, 90)
        cv2.circle(img, (x, y), 20, colour, -1, cv2.LINE_AA)
        cv2.circle(img, (x, y), 20, (0, 0, 0), 3 if i in UNSEEN else 1, cv2.LINE_AA)
        label = f"g{i}"
        (tw, th), _ = cv2.getTextSize(label, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)
        cv2.putText(img, label, (x - tw // 2, y + th // 2), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(
        img,
        f"chain neighbour among the 2 strongest out-edges: {chain_recovery(weights):.0%} of goals",
        (10, size - 12),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    cv2.putText(
        img, "bold rim: goals never trained on", (10, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA
    )
    return img


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
