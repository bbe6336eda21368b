"""Observations pre-rendered at every pose of a house, memory-mapped (the paper's protocol).

A cache lives in ``<cache dir>/<house_id>-<key>/`` with ``rgb.npy`` uint8 (P, H, W, 3),
``depth.npy`` float32 (P, H, W) metres, ``semantic.npy`` uint8 (P, H, W) and ``meta.json``
(32 KB a pose at 64x64; 50-200 MB a house). The key hashes the house's spec, the render settings and the pose-graph
version, so a changed house or camera never reads a stale cache; a cache whose metadata
does not match is rebuilt. It is built in a temporary folder and renamed into place, so an
interrupted build leaves nothing half-written. The cache directory is ``$OBJSEARCH_CACHE``,
else ``~/.cache/objsearch``, or what the caller passes.

Depth is rounded to the millimetre in both modes (``quantize_depth``), so live and cached
observations are identical.

``PredictedCache`` is the same for a network's predictions (the env's ``observation=
"predicted"``): ``semantic.npy`` and ``depth.npy`` predicted from the cached RGB of every
pose by any ``Predictor`` (``objsearch.perception.inference.Predictor`` is one), in
``<cache dir>/<house_id>-<key>-pred-<predictor key>/``.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Protocol

import numpy as np
from tqdm import tqdm

from objsearch.fileio import atomic_directory
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.renderer import HouseRenderer, RenderSettings
from objsearch.sim.world import World

CACHE_VERSION = "cache-v1"
PREDICTED_VERSION = "predicted-cache-v1"
BATCH = 256
LAYERS = ("rgb", "depth", "semantic")


def default_cache_dir() -> Path:
    return Path(os.environ.get("OBJSEARCH_CACHE") or Path.home() / ".cache" / "objsearch")


def quantize_depth(depth: np.ndarray) -> np.ndarray:
    """Depth rounded to the millimetre (float32 metres): what both modes observe."""
    return (np.rint(depth * 1000.0) / 1000.0).astype(np.float32)


def cache_key(world: World, settings: RenderSettings) -> str:
    text = json.dumps([CACHE_VERSION, NAVGRAPH_VERSION, world.spec_sha256, settings.key()])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class HouseCache:
    """The memory-mapped observations of every pose of one house."""

    def __init__(self, directory: Path, meta: dict):
        self.directory = directory
        self.meta = meta
        # plain ndarray views of the memory maps: indexing them is several times faster
        self.rgb = np.asarray(np.load(directory / "rgb.npy", mmap_mode="r"))
        self.depth = np.asarray(np.load(directory / "depth.npy", mmap_mode="r"))
        self.semantic = np.asarray(np.load(directory / "semantic.npy", mmap_mode="r"))

    @property
    def num_poses(self) -> int:
        return len(self.semantic)

    @classmethod
    def open(
        cls,
        world: World,
        settings: RenderSettings,
        cache_dir: str | Path | None = None,
        progress: bool = True,
    ) -> "HouseCache":
        """Open the house's cache, building (or rebuilding) it if missing or stale."""
        root = Path(cache_dir) if cache_dir is not None else default_cache_dir()
        key = cache_key(world, settings)
        directory = root / f"{world.house_id}-{key}"
        expected = {
            "version": CACHE_VERSION,
            "key": key,
            "house_id": world.house_id,
            "spec_sha256": world.spec_sha256,
            "navgraph": NAVGRAPH_VERSION,
            "settings": settings.to_dict(),
            "num_poses": world.graph.num_poses,
        }
        poses = world.graph.world_poses()
        n, h, w = len(poses), settings.height, settings.width

        def render(tmp: Path) -> None:
            layers = {"rgb": (np.uint8, (n, h, w, 3)), "depth": (np.float32, (n, h, w)), "semantic": (np.uint8, (n, h, w))}
            with HouseRenderer(world.model, settings) as renderer:
                batches = ((start, renderer.render(poses[start : start + BATCH])) for start in range(0, n, BATCH))
                _fill_arrays(
                    tmp,
                    layers,
                    ((start, {"rgb": f.rgb, "depth": quantize_depth(f.depth), "semantic": f.semantic}) for start, f in batches),
                    f"cache {world.house_id}",
                    progress,
                )

        _ensure_folder(directory, expected, render)
        return cls(directory, expected)


def _ensure_folder(directory: Path, meta: dict, fill) -> None:
    """Keep ``directory`` if its ``meta.json`` equals ``meta``; otherwise rebuild it: ``fill``
    writes the arrays into a temp folder that is then renamed into place."""
    try:
        if json.loads((directory / "meta.json").read_text()) == meta:
            return
    except (OSError, ValueError):
        pass
    with atomic_directory(directory) as tmp:
        fill(tmp)
        (tmp / "meta.json").write_text(json.dumps(meta, indent=1) + "\n")


def _fill_arrays(folder: Path, layers: dict, batches, desc: str, progress: bool) -> None:
    """Create ``<name>.npy`` memory maps of ``layers`` ({name: (dtype, shape)}) in ``folder``
    and fill them from ``batches`` of (first pose, {name: values})."""
    arrays = {name: np.lib.format.open_memmap(folder / f"{name}.npy", mode="w+", dtype=dtype, shape=shape)
              for name, (dtype, shape) in layers.items()}
    total = len(next(iter(arrays.values())))
    with tqdm(total=total, desc=desc, unit="pose", disable=not progress or None) as bar:
        for start, values in batches:
            for name, value in values.items():
                arrays[name][start : start + len(value)] = value
            bar.update(len(value))
    for array in arrays.values():
        array.flush()


class Predictor(Protocol):
    """Segmentation and depth from RGB (what ``PredictedCache`` needs of a network)."""

    key: str
    """Identity of the network and its weights (part of the cache key)."""

    def predict(self, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """uint8 (N, H, W, 3) -> (semantic uint8 (N, H, W), depth float32 (N, H, W) metres)."""
        ...


class PredictedCache:
    """A predictor's semantic and depth at every pose of one house, memory-mapped.

    Built from the house's ``HouseCache`` RGB (rendered first if needed); depth is rounded
    to the millimetre like the ground truth's.
    """

    def __init__(self, directory: Path, meta: dict):
        self.directory = directory
        self.meta = meta
        self.depth = np.asarray(np.load(directory / "depth.npy", mmap_mode="r"))
        self.semantic = np.asarray(np.load(directory / "semantic.npy", mmap_mode="r"))

    @classmethod
    def open(cls, world: World, settings: RenderSettings, predictor: Predictor, cache_dir: str | Path | None = None,
             progress: bool = True) -> "PredictedCache":
        """Open the predictions of ``predictor`` for the house, computing them if missing or stale."""
        gt = HouseCache.open(world, settings, cache_dir, progress)
        directory = gt.directory.parent / f"{gt.directory.name}-pred-{predictor.key}"
        expected = {"version": PREDICTED_VERSION, "observations": gt.meta["key"], "predictor": predictor.key,
                    "house_id": world.house_id, "settings": settings.to_dict(), "num_poses": gt.num_poses}
        n, h, w = gt.semantic.shape

        def predict(tmp: Path) -> None:
            def batches():
                for start in range(0, n, BATCH):
                    semantic, depth = predictor.predict(gt.rgb[start : start + BATCH])
                    yield start, {"semantic": semantic, "depth": quantize_depth(depth)}

            layers = {"depth": (np.float32, (n, h, w)), "semantic": (np.uint8, (n, h, w))}
            _fill_arrays(tmp, layers, batches(), f"predict {world.house_id}", progress)

        _ensure_folder(directory, expected, predict)
        return cls(directory, expected)
