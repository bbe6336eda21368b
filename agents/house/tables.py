"""The paper's small observations of every pose of a house, computed once, as tables.

HRL-GRG's House3D agents see 10x10 maps and the last 4 frames (paper appendix B.2): the
fraction of each block that shows a category (``TargetMaskDepth``'s mask channel, for any
category) and the block's mean depth. ``ObservationTables`` holds them for every pose of
one or more houses, so that a batched step of N training episodes is a few array gathers:

* ``depth``: float32 (P, 10, 10) metres;
* ``mask_rows`` float32 (R, 10, 10) and ``slot`` int32 (P, C): the 10x10 map of category
  c at pose p is ``mask_rows[slot[p, c]]`` (row 0 is all zeros: c not in view), so only
  the categories a pose shows take memory;
* ``pixels`` int32 (P, C): the category's pixels in the full frame (64x64), and ``near``
  int32 (P, C): those closer than ``REACH_DISTANCE`` metres;
* ``next_pose`` int32 (P, 6): the pose graph.

Pose ids are global over the houses of a table (``offsets[h]`` + the house's pose id).
Evaluation agents build the same tables from the frames they are given
(``ObservationTables.from_frames``), so training and evaluation observe exactly the same
numbers. Tables of a house are stored beside its observation cache (``tables-v1.npz`` in
the cache folder) and rebuilt when missing.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import cv2
import numpy as np

from objsearch.fileio import atomic_write
from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch.sim.env import NUM_CATEGORY_IDS
from objsearch.sim.goals import GoalRule

TABLES_VERSION = "house-tables-v1"
SIZE = 10  # the paper's 10 x 10 maps
HISTORY = 4  # frames an agent sees
NUM_CATEGORIES = NUM_CATEGORY_IDS
NUM_OBJECTS = NUM_CATEGORIES - FIRST_OBJECT_ID  # GRG nodes 0..NUM_OBJECTS-1 are object categories
#: "Reached" rule for sub-goals, judged from the agent's own observation (ObjectNav's: enough
#: pixels of the category closer than a metre). Final targets are judged by the env.
REACH_RULE = GoalRule(kind="near_visible", min_pixels=20, max_distance=1.0)
REACH_DISTANCE = REACH_RULE.max_distance
#: A category is "visible" (a candidate sub-goal) when it covers this many pixels of the
#: 64x64 frame (0.5%: about one 10x10 block's worth of pixels).
VISIBLE_PIXELS = 20
DEPTH_SCALE = 10.0  # metres; network inputs are depth / DEPTH_SCALE


def frame_features(semantic: np.ndarray, depth: np.ndarray):
    """One frame -> (depth 10x10, {category: mask 10x10}, pixels (C,), near (C,)).

    The 10x10 maps are ``cv2.resize(..., INTER_AREA)`` of the full-size category mask and
    depth, exactly as ``objsearch.sim.wrappers.TargetMaskDepth`` computes them."""
    shape = (SIZE, SIZE)
    semantic = np.asarray(semantic)
    depth = np.asarray(depth, dtype=np.float32)
    pixels = np.bincount(semantic.ravel(), minlength=NUM_CATEGORIES)[:NUM_CATEGORIES].astype(np.int32)
    near = np.bincount(semantic[depth <= REACH_DISTANCE].ravel(), minlength=NUM_CATEGORIES)[:NUM_CATEGORIES].astype(
        np.int32
    )
    masks = {
        int(c): cv2.resize((semantic == c).astype(np.float32), shape, interpolation=cv2.INTER_AREA)
        for c in np.flatnonzero(pixels)
    }
    return cv2.resize(depth, shape, interpolation=cv2.INTER_AREA), masks, pixels, near


@dataclass(frozen=True, eq=False)
class ObservationTables:
    """Per-pose observation tables of one or more houses (see the module docstring)."""

    depth: np.ndarray
    mask_rows: np.ndarray
    slot: np.ndarray
    pixels: np.ndarray
    near: np.ndarray
    next_pose: np.ndarray
    offsets: np.ndarray  # int64 (H + 1,): house h owns global poses offsets[h]..offsets[h+1]-1

    @property
    def num_poses(self) -> int:
        return len(self.depth)

    @classmethod
    def from_frames(
        cls, semantic: np.ndarray, depth: np.ndarray, next_pose: np.ndarray | None = None
    ) -> "ObservationTables":
        """Tables of frames (``semantic`` uint8 (P, H, W), ``depth`` float32 (P, H, W)), one
        pose each; ``next_pose`` the pose graph (None: a frame history, no moves)."""
        n = len(semantic)
        depth10 = np.zeros((n, SIZE, SIZE), np.float32)
        slot = np.zeros((n, NUM_CATEGORIES), np.int32)
        pixels = np.zeros((n, NUM_CATEGORIES), np.int32)
        near = np.zeros((n, NUM_CATEGORIES), np.int32)
        rows = [np.zeros((SIZE, SIZE), np.float32)]
        for p in range(n):
            depth10[p], masks, pixels[p], near[p] = frame_features(semantic[p], depth[p])
            for c, mask in masks.items():
                slot[p, c] = len(rows)
                rows.append(mask)
        if next_pose is None:
            next_pose = np.tile(np.arange(n, dtype=np.int32)[:, None], (1, 6))
        return cls(
            depth10, np.stack(rows), slot, pixels, near, np.asarray(next_pose, np.int32)[:, :6], np.array([0, n])
        )

    @classmethod
    def concat(cls, tables: list["ObservationTables"]) -> "ObservationTables":
        """One table over several houses (global pose ids)."""
        pose_off = np.cumsum([0] + [t.num_poses for t in tables])
        row_off = np.cumsum([0] + [len(t.mask_rows) for t in tables])
        slot = np.concatenate([np.where(t.slot > 0, t.slot + r, 0) for t, r in zip(tables, row_off)]).astype(np.int32)
        next_pose = np.concatenate([t.next_pose + o for t, o in zip(tables, pose_off)]).astype(np.int32)
        return cls(
            np.concatenate([t.depth for t in tables]),
            np.concatenate([t.mask_rows for t in tables]),
            slot,
            np.concatenate([t.pixels for t in tables]),
            np.concatenate([t.near for t in tables]),
            next_pose,
            pose_off,
        )

    # -- what the networks see ------------------------------------------------------------
    def masks(self, poses: np.ndarray, categories: np.ndarray) -> np.ndarray:
        """float32 (N, K, 10, 10): category ``categories[i]`` at the K poses ``poses[i]``
        (a category id < 0 gives zeros)."""
        cat = np.asarray(categories)[:, None]
        rows = np.where(cat >= 0, self.slot[poses, np.maximum(cat, 0)], 0)
        return self.mask_rows[rows]

    def all_masks(self, poses: np.ndarray) -> np.ndarray:
        """float32 (N, K, C, 10, 10): every category at the K poses of each row."""
        return self.mask_rows[self.slot[poses]]

    @cached_property
    def _present(self) -> tuple[np.ndarray, np.ndarray]:
        width = max(1, int((self.slot > 0).sum(axis=1).max()))
        cats = np.argsort(self.slot == 0, axis=1, kind="stable")[:, :width].astype(np.int64)
        return cats, np.take_along_axis(self.slot, cats, axis=1)

    def present_masks(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The categories in view, compactly: (categories int64 (N, K, M), masks float32
        (N, K, M, 10, 10)) for the K poses of each row, M the most categories any pose
        shows (padding: zero masks). Summing ``w[categories] * masks`` over M equals the
        per-pixel linear map over every category's mask (``all_masks``)."""
        cats, rows = self._present
        return cats[poses], self.mask_rows[rows[poses]]

    def visible(self, poses: np.ndarray) -> np.ndarray:
        """bool (N, C): categories that cover ``VISIBLE_PIXELS`` in any of the K frames."""
        return (self.pixels[poses] >= VISIBLE_PIXELS).any(axis=1)

    def reached(self, poses: np.ndarray, categories: np.ndarray) -> np.ndarray:
        """bool (N,): ``REACH_RULE`` holds for ``categories[i]`` at pose ``poses[i]``."""
        return self.near[poses, np.maximum(categories, 0)] >= REACH_RULE.min_pixels

    # -- files ------------------------------------------------------------------------------
    def save(self, path: str | Path) -> None:
        with atomic_write(path, "wb") as f:
            np.savez(f, version=np.array(TABLES_VERSION), **{k: getattr(self, k) for k in FIELDS})

    @classmethod
    def load(cls, path: str | Path) -> "ObservationTables | None":
        """The tables in ``path``, or None if it is missing, unreadable or of another version."""
        try:
            with np.load(path, allow_pickle=False) as data:
                if str(data["version"]) != TABLES_VERSION:
                    return None
                return cls(**{k: data[k] for k in FIELDS})
        except (OSError, ValueError, KeyError):
            return None


FIELDS = ("depth", "mask_rows", "slot", "pixels", "near", "next_pose", "offsets")


def house_tables(labels, next_pose: np.ndarray) -> ObservationTables:
    """The tables of one house from its cached ``labels`` (a ``HouseCache`` or
    ``PredictedCache``: ``semantic``, ``depth``, ``directory``), stored beside them."""
    path = Path(labels.directory) / "tables-v1.npz"
    tables = ObservationTables.load(path)
    if tables is None or tables.num_poses != len(labels.semantic):
        tables = ObservationTables.from_frames(labels.semantic, labels.depth, next_pose)
        tables.save(path)
    return tables
