"""The frontier agent's map geometry (``agents/baselines/frontier.py``): the map's grid (``CELL`` metres a
cell, ``SIZE`` cells a side, the start at (``RADIUS``, ``RADIUS``); headings' steps ``STEPS``),
depth frames as points on it (``project``), cheapest paths over it (``bfs``), and how much of the
view the target's voxels would fill from a pose (``view_scores``)."""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import shortest_path

CELL = 0.25  # metres: the pose graph's cell, so the agent's cells are the env's
RADIUS = 120  # cells each side of the start: maps span 60 m
SIZE = 2 * RADIUS + 1
VOXEL = 0.1  # metres: target memory
STEPS = np.array([[1, 0], [0, 1], [-1, 0], [0, -1]])  # (di, dj) of headings 0..3 (x forward, y left of the start)


def neighbours(k: int, shape) -> tuple[tuple[slice, slice], tuple[slice, slice]]:
    """Slices of a (h, w) grid: the cells whose neighbour along heading ``k`` is inside, and
    those neighbours, in the same order."""
    (di, dj), (h, w) = STEPS[k], shape
    cells = slice(max(-di, 0), h + min(-di, 0)), slice(max(-dj, 0), w + min(-dj, 0))
    beside = slice(max(di, 0), h + min(di, 0)), slice(max(dj, 0), w + min(dj, 0))
    return cells, beside


def turns(a, b):
    """Quarter turns between headings ``a`` and ``b`` (0, 1 or 2)."""
    d = (np.asarray(b) - np.asarray(a)) % 4
    return np.minimum(d, 4 - d)


def view_scores(cells: np.ndarray, voxels: np.ndarray, top: np.ndarray, camera: dict) -> np.ndarray:
    """How much of the image the target voxels would fill from each of ``cells`` (map
    indices) facing each heading: the sum of ``1 / depth**2`` over the voxels inside the
    camera's frustum and in line of sight, shape (C, 4). A voxel is out of sight when a cell
    on the way (other than the target's own) holds a point higher than the ray from the
    camera to it (``top``: the highest point seen in each cell)."""
    centre = cells * CELL  # (C, 2) metres
    v = (voxels + 0.5) * VOXEL  # (V, 3)
    rel = v[None, :, :2] - centre[:, None, :]  # (C, V, 2)
    up = v[None, :, 2] - camera["camera_height"]  # (1, V)
    tan_h = camera["cx"] / camera["fx"]
    tan_v = camera["cy"] / camera["fy"]
    own = np.zeros(top.shape, bool)
    own[tuple(np.rint(v[:, :2] / CELL).astype(int).T)] = True
    t = np.linspace(0.1, 0.9, 8)[None, None, :]
    # the cells a ray crosses depend on the voxel's column only: trace each column once
    columns, column_of = np.unique(voxels[:, :2], axis=0, return_inverse=True)
    across = (columns + 0.5) * VOXEL - centre[:, None, :]  # (C, U, 2): rel of each column
    si = np.rint((centre[:, None, None, :] + t[..., None] * across[:, :, None, :]) / CELL).astype(int)  # (C, U, T, 2)
    flat = si[..., 0] * top.shape[1] + si[..., 1]
    wall, mine = top.ravel()[flat][:, column_of.ravel()], own.ravel()[flat][:, column_of.ravel()]  # (C, V, T)
    ray = camera["camera_height"] + t * up[..., None]  # (1, V, T)
    hidden = (wall > ray + 0.05) & ~mine
    sight = ~hidden.any(-1)  # (C, V)
    out = np.zeros((len(cells), 4))
    for k, (di, dj) in enumerate(STEPS):
        fwd = rel[..., 0] * di + rel[..., 1] * dj
        left = -rel[..., 0] * dj + rel[..., 1] * di
        inside = (fwd > 0.1) & (np.abs(left) <= fwd * tan_h) & (np.abs(up) <= fwd * tan_v) & sight
        out[:, k] = np.where(inside, 1.0 / np.maximum(fwd, 0.2) ** 2, 0.0).sum(1)
    return out


def project(depth: np.ndarray, pose: np.ndarray, camera: dict) -> dict:
    """Every pixel of N frames (``depth`` (N, H, W), planar metres) seen from ``pose`` (N, 3)
    as map coordinates: ``x``, ``y`` in cells (fractional, the map's origin at index 0),
    ``height`` above the floor and ``range`` along the column's horizontal ray (metres), and
    ``valid`` (something was hit)."""
    n, h, w = depth.shape
    u = (np.arange(w) + 0.5 - camera["cx"]) / camera["fx"]  # right per metre of depth
    v = (camera["cy"] - np.arange(h) - 0.5) / camera["fy"]  # up per metre of depth
    z = depth.astype(np.float64)
    left = -u[None, None, :] * z
    yaw = pose[:, 2][:, None, None]
    c, s = np.cos(yaw), np.sin(yaw)
    return {
        "x": (pose[:, 0][:, None, None] + c * z - s * left) / CELL + RADIUS,
        "y": (pose[:, 1][:, None, None] + s * z + c * left) / CELL + RADIUS,
        "height": camera["camera_height"] + v[None, :, None] * z,
        "range": z * np.sqrt(1 + u**2)[None, None, :],
        "valid": z < camera["zfar"] * 0.999,
    }


def unique_voxels(voxels: np.ndarray) -> np.ndarray:
    """``np.unique(voxels, axis=0)`` for int32 (V, 3) voxels, through one int64 key per voxel
    (the same sorted rows, several times faster)."""
    shifted = voxels.astype(np.int64) + (1 << 20)
    if len(voxels) and (shifted.min() < 0 or shifted.max() >= 1 << 21):
        return np.unique(voxels, axis=0)
    keys = np.unique((shifted[:, 0] << 42) | (shifted[:, 1] << 21) | shifted[:, 2])
    mask = (1 << 21) - 1
    return (np.stack([keys >> 42, (keys >> 21) & mask, keys & mask], 1) - (1 << 20)).astype(np.int32)


def voxel_keys(x: np.ndarray, y: np.ndarray, height: np.ndarray) -> np.ndarray:
    """One int64 key per point of map coordinates ``x``, ``y`` (cells) and ``height`` (metres): its
    ``VOXEL`` voxel, packed as ``unique_voxels`` packs them."""
    vox = np.floor(np.stack([x * (CELL / VOXEL), y * (CELL / VOXEL), height / VOXEL], 1)).astype(np.int64) + (1 << 20)
    return (vox[:, 0] << 42) | (vox[:, 1] << 21) | vox[:, 2]


def column_angles(camera: dict) -> np.ndarray:
    """Each image column's ray, radians to the left of the heading."""
    u = (np.arange(camera["width"]) + 0.5 - camera["cx"]) / camera["fx"]
    return -np.arctan(u)


def bfs(free: np.ndarray, edge: np.ndarray, start, cost: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cost of a cheapest path from ``start`` to every cell over free cells and open edges
    (``cost``: of entering each cell; -1: unreached), and each cell's predecessor on it (flat
    index; -9999 at the start and where unreached)."""
    h, w = free.shape
    index = np.arange(h * w).reshape(h, w)
    rows, cols = [], []
    weights = cost.ravel()
    for k in range(4):
        src, dst = neighbours(k, free.shape)
        ok = free[src] & edge[k][src] & free[dst]
        rows.append(index[src][ok])
        cols.append(index[dst][ok])
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    graph = csr_matrix((weights[cols], (rows, cols)), shape=(h * w, h * w))
    dist, pred = shortest_path(graph, method="D", indices=start[0] * w + start[1], return_predecessors=True)
    dist = np.where(np.isinf(dist), -1.0, dist).reshape(h, w)
    return dist, pred.reshape(h, w)
