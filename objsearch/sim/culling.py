"""Which geoms of a house a camera pose can possibly see (conservative portal culling).

On a software rasteriser (Mesa llvmpipe) the cost of a frame is mostly a fixed cost per
drawn geom, so drawing only what can be seen is the largest single speed-up of the
renderer. A generated house is rooms (``floor_r<k>`` boxes) closed by full-height walls,
connected only through door openings (the ``door_d<k>`` lintel boxes span them). From a
camera in room R a geom can be visible only if it lies in R, or in a room reached through
a chain of door openings each seen (in plan view) within the camera's horizontal field
of view narrowed by the openings before it (classic portal culling); and its plan-view
bounding box must overlap that angular window.

Everything is conservative (bounding boxes, no vertical test, a small angular margin): a
culled geom cannot cover a pixel, so images are identical with and without culling
(``tests/sim/test_renderer.py`` checks this). Poses outside every room, and fields of view
of 150 degrees or more, fall back to drawing everything.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

MARGIN = 1e-3  # radians added to every angular window
EPS = 1e-6


def _name(model: mujoco.MjModel, g: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or ""


def _overlap(a: np.ndarray, boxes: np.ndarray, pad: float = 0.0) -> np.ndarray:
    """Positive-area overlap of plan box a (x0, y0, x1, y1) with each of boxes (K, 4)."""
    return (np.minimum(a[2], boxes[:, 2] + pad) - np.maximum(a[0], boxes[:, 0] - pad) > EPS) & (
        np.minimum(a[3], boxes[:, 3] + pad) - np.maximum(a[1], boxes[:, 1] - pad) > EPS
    )


class PortalCuller:
    """Per-pose visible-geom masks for a compiled house model.

    Args:
        model: The house.
        half_fov: Half the horizontal field of view, radians.
    """

    def __init__(self, model: mujoco.MjModel, half_fov: float):
        data = mujoco.MjData(model)
        mujoco.mj_kinematics(model, data)
        self.half_fov = half_fov
        self.enabled = half_fov < math.radians(75)
        # Plan-view bounding boxes of every geom (world frame) from the local AABBs.
        centre = data.geom_xpos + np.einsum("gij,gj->gi", data.geom_xmat.reshape(-1, 3, 3), model.geom_aabb[:, :3])
        half = np.einsum("gij,gj->gi", np.abs(data.geom_xmat.reshape(-1, 3, 3)), model.geom_aabb[:, 3:])
        self.boxes = np.concatenate([centre[:, :2] - half[:, :2], centre[:, :2] + half[:, :2]], axis=1)

        names = [_name(model, g) for g in range(model.ngeom)]
        room_ids, room_boxes, doors = [], [], []
        for g, name in enumerate(names):
            if name.startswith("floor_r") and name[7:].isdigit():
                room_ids.append(g)
                room_boxes.append(self.boxes[g])
            elif name.startswith("door_d") and name[6:].isdigit():
                doors.append(g)
        self.rooms = np.array(room_boxes).reshape(-1, 4)
        if len(self.rooms) == 0:
            self.enabled = False
            return
        # Doors: the two rooms each opening joins, and the opening's plan box corners.
        self.door_rooms = [np.flatnonzero(_overlap(self.boxes[g], self.rooms)).tolist() for g in doors]
        self.room_doors = [[] for _ in range(len(self.rooms))]
        for d, rooms in enumerate(self.door_rooms):
            for r in rooms:
                self.room_doors[r].append(d)
        self.door_corners = np.stack([self._corners(self.boxes[g]) for g in doors]) if doors else np.zeros((0, 4, 2))
        # Geoms per room; geoms in no room (the exterior wall skins) are never visible from inside.
        self.geom_rooms = np.stack([_overlap(self.boxes[g], self.rooms) for g in range(model.ngeom)])  # (G, R) bool
        self.corners = np.stack([self._corners(b) for b in self.boxes])  # (G, 4, 2)

    @staticmethod
    def _corners(b: np.ndarray) -> np.ndarray:
        return np.array([[b[0], b[1]], [b[2], b[1]], [b[2], b[3]], [b[0], b[3]]])

    def _windows(self, corners: np.ndarray, p: np.ndarray, yaw: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Angular extent (lo, hi), relative to yaw, of plan boxes given by corners (K, 4, 2)."""
        v = corners - p
        centre = v.mean(axis=1)
        ac = np.arctan2(centre[:, 1], centre[:, 0])
        rel = np.arctan2(v[..., 1], v[..., 0]) - ac[:, None]
        rel = (rel + np.pi) % (2 * np.pi) - np.pi
        d = (ac - yaw + np.pi) % (2 * np.pi) - np.pi
        inside = (
            (corners[:, 0, 0] - EPS <= p[0])
            & (p[0] <= corners[:, 2, 0] + EPS)
            & (corners[:, 0, 1] - EPS <= p[1])
            & (p[1] <= corners[:, 2, 1] + EPS)
        )
        return d + rel.min(axis=1) - MARGIN, d + rel.max(axis=1) + MARGIN, inside

    @staticmethod
    def _overlaps(lo: np.ndarray, hi: np.ndarray, inside: np.ndarray, a: float, b: float) -> np.ndarray:
        """Whether each angular interval (lo, hi), or a 2 pi twin of it, meets window (a, b)."""
        ok = inside.copy()
        for shift in (-2 * np.pi, 0.0, 2 * np.pi):
            ok |= (lo + shift <= b) & (hi + shift >= a)
        return ok

    def visible(self, x: float, y: float, yaw: float) -> np.ndarray | None:
        """Bool mask (ngeom,) of geoms that may be seen from pose (x, y, yaw); None = all."""
        if not self.enabled:
            return None
        p = np.array([x, y])
        r = self.rooms
        start = np.flatnonzero(
            (r[:, 0] - EPS <= x) & (x <= r[:, 2] + EPS) & (r[:, 1] - EPS <= y) & (y <= r[:, 3] + EPS)
        )
        if len(start) == 0:
            return None
        # Portal traversal (scalar Python: a handful of doors): room -> angular window.
        full = (-self.half_fov - MARGIN, self.half_fov + MARGIN)
        windows = {int(k): full for k in start}
        if len(self.door_corners):
            dlo, dhi, dins = (v.tolist() for v in self._windows(self.door_corners, p, yaw))
            queue = list(windows)
            while queue:
                room = queue.pop()
                a, b = windows[room]
                for d in self.room_doors[room]:
                    if dins[d]:
                        lo, hi = a, b
                    else:
                        lo, hi = math.inf, -math.inf
                        for shift in (-2 * math.pi, 0.0, 2 * math.pi):
                            l, h = max(dlo[d] + shift, a), min(dhi[d] + shift, b)
                            if l <= h:
                                lo, hi = min(lo, l), max(hi, h)
                        if lo > hi:
                            continue
                    for nxt in self.door_rooms[d]:
                        old = windows.get(nxt)
                        new = (lo, hi) if old is None else (min(old[0], lo), max(old[1], hi))
                        if old is None or new[0] < old[0] - EPS or new[1] > old[1] + EPS:
                            windows[nxt] = new
                            queue.append(nxt)
        # A geom is drawn if its plan box meets the window of a room it belongs to.
        glo, ghi, gins = self._windows(self.corners, p, yaw)
        mask = np.zeros(len(self.boxes), dtype=bool)
        for room, (a, b) in windows.items():
            mask |= self.geom_rooms[:, room] & self._overlaps(glo, ghi, gins, a, b)
        return mask
