"""The house world as the methods see it (its adapter, ``HOUSE``): nodes, the networks'
inputs built from ``ObservationTables`` rows (``hist``: (N, 4) pose ids, oldest first), the
high levels' Q-values and losses.

Nodes (sub-goals, GRG): object categories ``0..NUM_OBJECTS-1`` (category id minus
``FIRST_OBJECT_ID``) and ``RANDOM`` = NUM_OBJECTS, the back-up sub-goal. Training (tables of
every pose of a house) and evaluation (tables of the 4 frames the agent was given) build
their inputs here, so what is trained is what is evaluated. The losses are ``core.double_dqn``'s
Double DQN on these inputs.
"""

from __future__ import annotations

import numpy as np
import torch

from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch_agents.core import double_dqn
from objsearch_agents.core.grg import GoalsRelationalGraph
from objsearch_agents.core.nets import as_tensor, seeded_init
from objsearch_agents.house.episodes import object_node
from objsearch_agents.house.nets import NUM_ACTIONS, CandidateQ, CategoryQ
from objsearch_agents.house.tables import DEPTH_SCALE, NUM_CATEGORIES, NUM_OBJECTS, REACH_RULE, ObservationTables

RANDOM = NUM_OBJECTS
NUM_NODES = NUM_OBJECTS + 1


def node_category(nodes: np.ndarray) -> np.ndarray:
    """Category id of each node (-1 for ``RANDOM``: an all-zero mask)."""
    nodes = np.asarray(nodes)
    return np.where(nodes < RANDOM, nodes + FIRST_OBJECT_ID, -1)


def depth_input(tables: ObservationTables, hist: np.ndarray) -> np.ndarray:
    return tables.depth[hist] / np.float32(DEPTH_SCALE)


def low_input(tables: ObservationTables, hist: np.ndarray, categories: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(mask (N, 4, 10, 10), depth (N, 4, 10, 10)): the actor-critic's input."""
    return tables.masks(hist, categories), depth_input(tables, hist)


def category_input(tables: ObservationTables, hist: np.ndarray, targets: np.ndarray) -> tuple[torch.Tensor, ...]:
    """``CategoryQ``'s input: the categories in view and their masks, depth, the target's one-hot."""
    onehot = np.eye(NUM_CATEGORIES, dtype=np.float32)[targets]
    cats, masks = tables.present_masks(hist)
    return torch.from_numpy(cats), as_tensor(masks), as_tensor(depth_input(tables, hist)), as_tensor(onehot)


def candidates(tables: ObservationTables, hist: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """bool (N, NUM_NODES): object categories visible in the 4 frames, less those already
    reached at the current pose (except the target), plus ``RANDOM``."""
    vis = tables.visible(hist)[:, FIRST_OBJECT_ID:]
    reached = tables.near[hist[:, -1], FIRST_OBJECT_ID:] >= REACH_RULE.min_pixels
    reached[np.arange(len(targets)), object_node(targets)] = False
    return np.concatenate([vis & ~reached, np.ones((len(hist), 1), bool)], axis=1)


def candidate_inputs(
    tables: ObservationTables, hist: np.ndarray, env_ix: np.ndarray, node_ix: np.ndarray, weights: np.ndarray
) -> tuple[torch.Tensor, torch.Tensor]:
    """``CandidateQ``'s input for (env, node) pairs: the node's mask times its weight
    (``RANDOM``: ones times its weight), and depth."""
    cats = node_category(node_ix)
    mask = tables.masks(hist[env_ix], cats)
    mask[cats < 0] = 1.0
    mask *= weights[env_ix, node_ix][:, None, None, None].astype(np.float32)
    return as_tensor(mask), as_tensor(depth_input(tables, hist[env_ix]))


def candidate_score(tables: ObservationTables, hist: np.ndarray, weights: np.ndarray):
    """``score(net, rows, nodes)``: ``CandidateQ`` of (row, node) pairs (``core.double_dqn``)."""
    return lambda net, rows, nodes: net(*candidate_inputs(tables, hist, rows, nodes, weights))


def candidate_argmax(net, tables: ObservationTables, hist: np.ndarray, cand: np.ndarray, weights: np.ndarray):
    """argmax over each row's candidates of ``CandidateQ`` (``weights``: (N, NUM_NODES), each
    candidate's mask factor), one forward pass for all (env, candidate) pairs."""
    return double_dqn.candidate_argmax(net, candidate_score(tables, hist, weights), cand)


def visible_nodes(tables: ObservationTables, hist: np.ndarray) -> np.ndarray:
    """bool (N, NUM_NODES): object nodes visible in any of the 4 frames (``RANDOM`` never)."""
    vis = tables.visible(hist)[:, FIRST_OBJECT_ID:]
    return np.concatenate([vis, np.zeros((len(hist), 1), bool)], axis=1)


def sample_actions(logits: torch.Tensor, rng) -> np.ndarray:
    """One action per row from softmax(logits), drawn with ``rng`` (inverse CDF)."""
    p = torch.softmax(logits, dim=1).double().numpy()
    cdf = np.cumsum(p, axis=1)
    u = rng.random(len(p))[:, None] * cdf[:, -1:]
    return np.minimum((cdf < u).sum(axis=1), p.shape[1] - 1)


class HouseWorld:
    """The house world's side of a method's strategy (``objsearch_agents.methods``): its
    networks, the Q-values its high levels choose by, and their losses. ``obs`` is
    ``(tables, hist)``; a loss's ``tables`` are the training houses' tables."""

    num_nodes = NUM_NODES
    random_node = RANDOM
    node_category = staticmethod(node_category)

    def action_q_net(self, seed: int):
        """DQN's Q over the primitive actions: every category's mask, depth, the target's one-hot."""
        return seeded_init(CategoryQ, seed, NUM_CATEGORIES, NUM_ACTIONS)

    def node_q_net(self, seed: int):
        """h-DQN's high level: the same inputs, one Q per node."""
        return seeded_init(CategoryQ, seed, NUM_CATEGORIES, NUM_NODES)

    def candidate_q_net(self, seed: int):
        """HRL-GRG's high level: one Q per candidate, on its weighted mask and the depth."""
        return seeded_init(CandidateQ, seed)

    def graph(self, config) -> GoalsRelationalGraph:
        return GoalsRelationalGraph(NUM_NODES, config.option_steps, config.grg_gamma, observable=NUM_OBJECTS)

    def action_q(self, net, obs, targets: np.ndarray) -> np.ndarray:
        tables, hist = obs
        return net(*category_input(tables, hist, targets)).numpy()

    def node_q(self, net, obs, targets: np.ndarray) -> np.ndarray:
        tables, hist = obs
        return net(*category_input(tables, hist, targets)).numpy()

    def candidate_argmax(self, net, obs, cand: np.ndarray, weights: np.ndarray) -> np.ndarray:
        tables, hist = obs
        return candidate_argmax(net, tables, hist, cand, weights)

    def visible_nodes(self, obs) -> np.ndarray:
        return visible_nodes(*obs)

    def loss_plan_values(self, plan_values: np.ndarray, batch: dict) -> np.ndarray:
        """(B, NUM_NODES): each transition's plan values to its target."""
        return plan_values[object_node(batch["target"])]

    def action_q_loss(self, learner, batch: dict, tables) -> torch.Tensor:
        """Double DQN on the action Q."""
        return category_q_loss(learner, batch, tables)

    def node_q_loss(self, learner, batch: dict, tables) -> torch.Tensor:
        """Double DQN on the node Q; the next value maximises over the next state's candidates."""
        return category_q_loss(learner, batch, tables, candidates)

    def candidate_q_loss(self, learner, batch: dict, tables, weights: np.ndarray) -> torch.Tensor:
        """Double DQN on the candidate Q (``weights``: (B, NUM_NODES), each candidate's mask factor)."""
        nxt = batch["next_hist"]
        return double_dqn.candidate_double_dqn_loss(
            learner,
            candidate_score(tables, batch["hist"], weights),
            candidate_score(tables, nxt, weights),
            batch["action"],
            candidates(tables, nxt, batch["target"]),
            batch,
        )


def category_q_loss(learner, batch: dict, tables, allowed=None) -> torch.Tensor:
    """Double DQN on ``CategoryQ``; ``allowed(tables, hist, targets)`` (bool (N, outputs)), if
    given, restricts the next state's argmax (h-DQN's candidates)."""
    hist, nxt, targets = batch["hist"], batch["next_hist"], batch["target"]
    return double_dqn.double_dqn_loss(
        learner,
        category_input(tables, hist, targets),
        batch["action"],
        category_input(tables, nxt, targets),
        batch,
        None if allowed is None else allowed(tables, nxt, targets),
    )


HOUSE = HouseWorld()
