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
import shutil
import tempfile
from pathlib import Path
from typing import Protocol

import numpy as np
from tqdm import tqdm

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
        try:
            meta = json.loads((directory / "meta.json").read_text())
            if meta == expected:
                return cls(directory, meta)
        except (OSError, ValueError):
            pass
        _build(world, settings, directory, expected, progress)
        return cls(directory, expected)


def _build(world: World, settings: RenderSettings, directory: Path, meta: dict, progress: bool) -> None:
    directory.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=directory.parent, prefix=f".{directory.name}.", suffix=".tmp"))
    try:
        poses = world.graph.world_poses()
        n, h, w = len(poses), settings.height, settings.width
        rgb = np.lib.format.open_memmap(tmp / "rgb.npy", mode="w+", dtype=np.uint8, shape=(n, h, w, 3))
        depth = np.lib.format.open_memmap(tmp / "depth.npy", mode="w+", dtype=np.float32, shape=(n, h, w))
        semantic = np.lib.format.open_memmap(tmp / "semantic.npy", mode="w+", dtype=np.uint8, shape=(n, h, w))
        with HouseRenderer(world.model, settings) as renderer, tqdm(
            total=n, desc=f"cache {world.house_id}", unit="pose", disable=not progress or None
        ) as bar:
            for start in range(0, n, BATCH):
                frames = renderer.render(poses[start : start + BATCH])
                stop = start + len(frames.rgb)
                rgb[start:stop] = frames.rgb
                depth[start:stop] = quantize_depth(frames.depth)
                semantic[start:stop] = frames.semantic
                bar.update(stop - start)
        for array in (rgb, depth, semantic):
            array.flush()
        del rgb, depth, semantic
        (tmp / "meta.json").write_text(json.dumps(meta, indent=1) + "\n")
        if directory.exists():
            shutil.rmtree(directory)
        os.replace(tmp, directory)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


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
        try:
            if json.loads((directory / "meta.json").read_text()) == expected:
                return cls(directory, expected)
        except (OSError, ValueError):
            pass
        tmp = Path(tempfile.mkdtemp(dir=directory.parent, prefix=f".{directory.name}.", suffix=".tmp"))
        try:
            n, h, w = gt.semantic.shape
            depth = np.lib.format.open_memmap(tmp / "depth.npy", mode="w+", dtype=np.float32, shape=(n, h, w))
            semantic = np.lib.format.open_memmap(tmp / "semantic.npy", mode="w+", dtype=np.uint8, shape=(n, h, w))
            with tqdm(total=n, desc=f"predict {world.house_id}", unit="pose", disable=not progress or None) as bar:
                for start in range(0, n, BATCH):
                    sem, dep = predictor.predict(gt.rgb[start : start + BATCH])
                    semantic[start : start + len(sem)] = sem
                    depth[start : start + len(sem)] = quantize_depth(dep)
                    bar.update(len(sem))
            for array in (depth, semantic):
                array.flush()
            del depth, semantic
            (tmp / "meta.json").write_text(json.dumps(expected, indent=1) + "\n")
            if directory.exists():
                shutil.rmtree(directory)
            os.replace(tmp, directory)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        return cls(directory, expected)
