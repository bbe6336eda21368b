"""Observations pre-rendered at every pose of a house (the paper's protocol).

A cache lives in ``<cache dir>/<house_id>-<key>/``: ``frames.npy``, one record a pose
(``record_dtype``: rgb uint8 (H, W, 3), semantic uint8 (H, W), depth float32 (H, W) metres
rounded to the millimetre, side by side), and ``meta.json`` (32 KB a pose at 64x64; 50-200
MB a house). One record a pose, so that one read gives a step all its observations; depth
as the float32 the env gives, so that nothing is converted per step (cache-v2 stored uint16
millimetres in a file a layer: a quarter smaller, and a step cost three reads and a
division; ``benchmarks/RESULTS.md``). The key hashes the house's spec, the render settings
and the pose-graph version, so a changed house or camera never reads a stale cache; a cache
whose metadata does not match is rebuilt. It is built in a temporary folder and renamed
into place, so an interrupted build leaves nothing half-written. A cache-v2 folder of the
same house and camera is converted instead of rendered again (the same bits: its
millimetres divided as v2 read them), then removed (``cache_folder.retire_folder``: only its own
files are deleted, what else it holds is moved into the new cache). The cache directory is
``$OBJSEARCH_CACHE``, else ``~/.cache/objsearch``, or what the caller passes.

Integrity: ``meta.json`` records the size and sha256 of the data file. ``open`` checks it
(size, ``.npy`` header, digest: about 0.1 s for 150 MB with a warm page cache) and
*rebuilds* a damaged cache, saying why on stderr, as it rebuilds a stale one; it is a
cache, so rebuilding is always right. ``objsearch cache verify`` checks caches without
opening them, ``objsearch cache clear`` removes them. Builds of one cache are serialised by
a lock file (``.<name>.lock``, there while it is held), so concurrent builders build it
once; temp folders of killed builds are removed when a build starts
(``fileio.abandoned_temp_folders``).

Memory: a process opens each cache folder once (``open_layers``: every env of a batched
evaluation that plays the house shares it) and lets go of it when its last user does (the
env holds only the house in play). The env reads each step's record from the file
(``CacheLayers.reader``, one ``pread``): nothing is mapped, so memory does not grow with the
poses or houses visited; whole layers (``.rgb``, ``.depth``, ``.semantic``) are views of the
file memory-mapped on first use, for gathers over many poses (training, goal poses).

Depth is rounded to the millimetre in both modes (``quantize_depth``), so live and cached
observations are identical.

``PredictedCache`` is the same for a network's predictions (the env's ``observation=
"predicted"``): records of semantic and depth predicted from the cached RGB of every pose
by any ``Predictor`` (``objsearch.perception.inference.Predictor`` is one), in
``<cache dir>/<house_id>-<key>-pred-<predictor key>/``.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import weakref
from pathlib import Path
from typing import Callable, Protocol, Sequence

import numpy as np

from objsearch.sim.cache_folder import cache_meta, check_folder, ensure_folder, fill_arrays, folder_bytes, retire_folder
from objsearch.sim.camera import AGENT_CAMERA, AGENT_CAMERA_NAME, RenderSettings, check_predictor_camera
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.renderer import HouseRenderer
from objsearch.sim.world import World

CACHE_VERSION = "cache-v3"  # v3: one record a pose in frames.npy, float32 depth; v2: a file a layer, uint16 mm
PREDICTED_VERSION = "predicted-cache-v3"
PREVIOUS_CACHE_VERSION, PREVIOUS_PREDICTED_VERSION = "cache-v2", "predicted-cache-v2"  # converted, not rendered again
BATCH = 256
FRAMES = "frames"  # a cache's one data file, frames.npy
RECORD_ORDER = ("rgb", "semantic", "depth")  # a pose's record in a house's cache (record_dtype)
PREDICTED_ORDER = ("semantic", "depth")  # ... and in a predicted cache
_MM = np.float32(1000)  # cache-v2's millimetres / _MM in float32: exactly quantize_depth's metres (a test checks all)


def default_cache_dir() -> Path:
    """The cache folder: ``$OBJSEARCH_CACHE``, else ``~/.cache/objsearch``."""
    return Path(os.environ.get("OBJSEARCH_CACHE") or Path.home() / ".cache" / "objsearch")


def quantize_depth(depth: np.ndarray) -> np.ndarray:
    """Depth rounded to the millimetre (float32 metres): what both modes observe."""
    return (np.rint(depth * 1000.0) / 1000.0).astype(np.float32)


def millimetres_to_metres(mm: np.ndarray) -> np.ndarray:
    """cache-v2's uint16 millimetres as the float32 metres it read them as (and
    ``quantize_depth`` gives): what a converted cache stores."""
    return np.divide(mm, _MM, dtype=np.float32)


def cache_key(world: World, settings: RenderSettings, version: str = CACHE_VERSION) -> str:
    """The 16 hex digits naming a house's cache: a hash of the cache and pose-graph versions, spec hash and camera."""
    text = json.dumps([version, NAVGRAPH_VERSION, world.spec_sha256, settings.key()])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class CacheLayers:
    """The frames of one cache folder, opened once per process (``open_layers``).

    A cache holds one file, ``frames.npy``: one record a pose with every layer of that pose
    side by side (``record_dtype``), so one read gives a step its observations. Two ways in:
    ``reader(names)`` reads a pose's record with one ``pread`` (what the env does each step:
    nothing stays mapped, so the process's memory does not grow with the poses and houses
    it visits), and the attributes ``rgb``, ``depth``, ``semantic``: the whole layer, a view
    of the memory-mapped file made on first use (for gathers over many poses). The file
    closes, and the map goes, when the last user drops the object (it is shared: no ``close``).
    """

    def __init__(self, directory: Path, meta: dict):
        self.directory = directory
        self.meta = meta
        self._map: np.ndarray | None = None
        self._num_poses = int(meta["num_poses"])
        self._files: dict[str, tuple] = {}  # FRAMES -> (fd, data offset, record dtype)
        self._close = weakref.finalize(self, _close_files, self._files)

    @property
    def num_poses(self) -> int:
        """Number of poses (frames) in the cache."""
        return self._num_poses

    def _layer(self, name: str) -> np.ndarray:
        if self._map is None:
            # a plain ndarray view of the memory map: indexing it is several times faster
            self._map = np.asarray(np.load(self.directory / f"{FRAMES}.npy", mmap_mode="r"))
        if name not in (self._map.dtype.names or ()):
            raise AttributeError(f"{self.directory} holds no {name!r} layer (it has {self._map.dtype.names})")
        return self._map[name]

    depth = property(lambda self: self._layer("depth"), doc="Depth of every pose, float32 metres (memory-mapped).")
    semantic = property(lambda self: self._layer("semantic"), doc="Category ids of every pose (memory-mapped).")

    def _file(self) -> tuple[int, int, np.dtype]:
        if FRAMES not in self._files:
            self._files[FRAMES] = _open_frames(self.directory / f"{FRAMES}.npy")
        return self._files[FRAMES]

    def frame(self, name: str, pose: int) -> np.ndarray:
        """A new array holding layer ``name``'s frame of ``pose`` (``depth``: float32 metres),
        read from the file: the same values as ``getattr(self, name)[pose]``."""
        return self.reader((name,))(pose)[0]

    def reader(self, names: Sequence[str]) -> Callable[[int], tuple]:
        """A function of a pose giving the frames of layers ``names`` (in that order), bound
        to the open file: what the env calls each step (one ``pread`` of the bytes of the
        pose's record that hold them into a new buffer, the frames views of it; nothing
        looked up per call). It holds this object, so the file stays open while it is kept."""
        fd, offset, record = self._file()
        missing = [n for n in names if n not in record.names]
        if missing or not names:
            raise ValueError(f"{self.directory} holds layers {record.names}, not {missing or 'none'}")
        first = min(record.fields[n][1] for n in names)
        span = np.dtype(
            {
                "names": list(names),
                "formats": [record.fields[n][0] for n in names],
                "offsets": [record.fields[n][1] - first for n in names],
                "itemsize": max(record.fields[n][1] + record.fields[n][0].itemsize for n in names) - first,
            }
        )
        size, start, stride = span.itemsize, offset + first, record.itemsize
        num_poses, empty, preadv, names = self._num_poses, np.empty, os.preadv, tuple(names)
        layers = self  # the file closes when the last holder of this object lets go (no cycle: not stored here)

        def read(pose: int) -> tuple:
            if not 0 <= pose < num_poses:
                raise IndexError(f"pose {pose} is out of range for {num_poses} poses ({layers.directory})")
            out = empty((), span)
            if preadv(fd, (out,), start + pose * stride) != size:
                raise OSError(f"{layers.directory / FRAMES}.npy: short read (truncated?)")
            return tuple([out[name] for name in names])

        return read

    def frames(self, name: str, start: int, stop: int) -> np.ndarray:
        """A new array holding layer ``name``'s frames of poses ``start:stop`` (``depth``:
        float32 metres), read from the file: the same values as ``getattr(self, name)[start:stop]``."""
        fd, offset, record = self._file()
        stop = min(stop, self._num_poses)
        if not 0 <= start < stop:
            raise IndexError(f"poses {start}:{stop} are out of range for {self._num_poses} poses ({self.directory})")
        out = np.empty(stop - start, record)
        if os.preadv(fd, (out,), offset + start * record.itemsize) != out.nbytes:
            raise OSError(f"{self.directory / FRAMES}.npy: short read (truncated?)")
        return np.ascontiguousarray(out[name])


def record_dtype(names: Sequence[str], height: int, width: int) -> np.dtype:
    """One pose's record in ``frames.npy``: the layers ``names`` side by side in ``RECORD_ORDER``,
    rgb uint8 (H, W, 3), semantic uint8 (H, W), depth float32 (H, W) metres (after 4 bytes a
    pixel of uint8 layers, so it is aligned)."""
    shapes = {
        "rgb": (np.uint8, (height, width, 3)),
        "semantic": (np.uint8, (height, width)),
        "depth": (np.float32, (height, width)),
    }
    return np.dtype([(name, *shapes[name]) for name in RECORD_ORDER if name in names])


def _open_frames(path: Path) -> tuple[int, int, np.dtype]:
    """(fd, offset of the data, record dtype) of a cache's ``frames.npy``."""
    mapped = np.load(path, mmap_mode="r")  # numpy reads the header; the map goes at once, untouched
    offset, dtype = mapped.offset, mapped.dtype
    del mapped
    if dtype.names is None:
        raise ValueError(f"{path} holds no records of layers, as caches are written; rebuild it")
    return os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0)), offset, dtype


def _close_files(files: dict) -> None:
    for fd, *_ in files.values():
        os.close(fd)
    files.clear()


_OPEN: weakref.WeakValueDictionary = weakref.WeakValueDictionary()  # cache folder -> its CacheLayers in use


def open_layers(cls, directory: Path, meta: dict):
    """The ``cls`` of ``directory`` already in use in this process if it was made for the
    same ``meta`` (the same files), else a new one: every env of a batched evaluation that
    plays a house reads it through one set of files and maps."""
    layers = _OPEN.get(directory)
    if type(layers) is not cls or layers.meta != meta:
        layers = _OPEN[directory] = cls(directory, meta)
    return layers


def open_cache_folders() -> list[Path]:
    """The cache folders this process has open (``CacheLayers`` not yet released)."""
    return list(_OPEN.keys())


class HouseCache(CacheLayers):
    """The observations of every pose of one house (``CacheLayers``: read frame by frame,
    or memory-mapped)."""

    rgb = property(lambda self: self._layer("rgb"), doc="RGB of every pose (memory-mapped).")

    @classmethod
    def open(
        cls,
        world: World,
        settings: RenderSettings,
        cache_dir: str | Path | None = None,
        progress: bool = True,
    ) -> "HouseCache":
        """Open the house's cache, building (or rebuilding) it if missing, stale or damaged
        (from an intact cache of the previous version where there is one: no rendering)."""
        root = Path(cache_dir) if cache_dir is not None else default_cache_dir()

        def expected(version: str) -> dict:
            key = cache_key(world, settings, version)
            return {
                "version": version,
                "key": key,
                "house_id": world.house_id,
                "spec_sha256": world.spec_sha256,
                "navgraph": NAVGRAPH_VERSION,
                "settings": settings.to_json(),
                "num_poses": world.graph.num_poses,
            }

        new, old = expected(CACHE_VERSION), expected(PREVIOUS_CACHE_VERSION)
        directory = root / f"{world.house_id}-{new['key']}"
        poses = world.graph.world_poses()
        n, h, w = len(poses), settings.height, settings.width
        layers = {FRAMES: (record_dtype(RECORD_ORDER, h, w), (n,))}

        def rendered():
            with HouseRenderer(world.model, settings) as renderer:
                for start in range(0, n, BATCH):
                    f = renderer.render(poses[start : start + BATCH])
                    yield start, {"rgb": f.rgb, "depth": quantize_depth(f.depth), "semantic": f.semantic}

        previous = _Previous(root / f"{world.house_id}-{old['key']}", old, RECORD_ORDER, h, w)
        meta = ensure_folder(
            directory,
            new,
            layers,
            lambda tmp: fill_arrays(
                tmp,
                layers,
                previous.batches() if previous.intact() else rendered(),
                f"cache {world.house_id}",
                progress,
            ),
            f"cache {world.house_id}",
        )
        previous.remove(directory)
        return open_layers(cls, directory, meta)


class _Previous:
    """A cache folder of the previous version (cache-v2: ``<layer>.npy`` a layer, depth in
    uint16 millimetres) for the same house, camera and predictor: a new cache is filled from
    it when it is intact, instead of rendering or predicting again (the same bits: depth as
    v2 read it, ``millimetres_to_metres``), and it is removed once the new one is in place
    (this version cannot read it)."""

    def __init__(self, directory: Path, expected: dict, names: Sequence[str], height: int, width: int):
        self.directory, self.expected, self.used = directory, expected, False
        n = int(expected["num_poses"])
        v2 = {"rgb": (np.uint8, (n, height, width, 3)), "depth": (np.uint16, (n, height, width))}
        self.layers = {name: v2.get(name, (np.uint8, (n, height, width))) for name in names}

    def intact(self) -> bool:
        """Whether the folder is there and intact (its files' sizes, headers and digests)."""
        return self.directory.is_dir() and check_folder(self.directory, self.expected, self.layers) is None

    def batches(self):
        """(first pose, {layer: frames}) of the whole folder, as a new cache is filled."""
        self.used = True
        arrays = {name: np.load(self.directory / f"{name}.npy", mmap_mode="r") for name in self.layers}
        print(f"{self.directory.name}: converting {self.expected['version']} (no rendering)", file=sys.stderr)
        for start in range(0, int(self.expected["num_poses"]), BATCH):
            batch = {name: np.asarray(a[start : start + BATCH]) for name, a in arrays.items()}
            yield start, {**batch, "depth": millimetres_to_metres(batch["depth"])}

    def remove(self, converted: Path) -> None:
        """Remove the folder once it was converted into ``converted`` (nothing when it was
        not): what else it holds (e.g. the learned agents' tables: made from the same bits,
        so still right) is moved there first, and only its own files are deleted
        (``cache_folder.retire_folder``)."""
        if self.used:
            said = retire_folder(self.directory, converted, ["meta.json", *(f"{name}.npy" for name in self.layers)])
            print(f"{said} (converted to {CACHE_VERSION})", file=sys.stderr)


class Predictor(Protocol):
    """Segmentation and depth from RGB (what ``PredictedCache`` needs of a network)."""

    key: str
    """Identity of the network and its weights (part of the cache key)."""

    # A predictor may also have ``settings`` (the ``RenderSettings`` of its training frames):
    # the env and the harness then check it against their camera (``sim.camera.check_predictor_camera``).

    def predict(self, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """uint8 (N, H, W, 3) -> (semantic uint8 (N, H, W), depth float32 (N, H, W) metres)."""
        ...


class PredictedCache(CacheLayers):
    """A predictor's semantic and depth at every pose of one house (``CacheLayers``: read
    frame by frame, or memory-mapped).

    Built from the house's ``HouseCache`` RGB (rendered first if needed); depth is rounded
    to the millimetre like the ground truth's (stored as uint16 millimetres).
    """

    @classmethod
    def open(
        cls,
        world: World,
        settings: RenderSettings,
        predictor: Predictor,
        cache_dir: str | Path | None = None,
        progress: bool = True,
    ) -> "PredictedCache":
        """Open the predictions of ``predictor`` for the house, computing them if missing, stale or damaged.

        A predictor with ``settings`` must have been trained on ``settings``' frames
        (``CameraMismatchError`` otherwise), whoever calls.
        """
        check_predictor_camera(
            predictor,
            settings,
            AGENT_CAMERA_NAME
            if settings == AGENT_CAMERA
            else f"the camera of these observations (cache key {settings.key()})",
        )
        gt = HouseCache.open(world, settings, cache_dir, progress)

        def expected(version: str, observations: str) -> dict:
            return {
                "version": version,
                "observations": observations,
                "predictor": predictor.key,
                "house_id": world.house_id,
                "settings": settings.to_json(),
                "num_poses": gt.num_poses,
            }

        directory = gt.directory.parent / f"{gt.directory.name}-pred-{predictor.key}"
        n, h, w = gt.num_poses, settings.height, settings.width
        layers = {FRAMES: (record_dtype(PREDICTED_ORDER, h, w), (n,))}

        def predicted():
            for start in range(0, n, BATCH):
                semantic, depth = predictor.predict(gt.frames("rgb", start, start + BATCH))  # not mapped: read once
                yield start, {"semantic": semantic, "depth": quantize_depth(depth)}

        old_key = cache_key(world, settings, PREVIOUS_CACHE_VERSION)
        previous = _Previous(
            gt.directory.parent / f"{world.house_id}-{old_key}-pred-{predictor.key}",
            expected(PREVIOUS_PREDICTED_VERSION, old_key),
            PREDICTED_ORDER,
            h,
            w,
        )
        meta = ensure_folder(
            directory,
            expected(PREDICTED_VERSION, gt.meta["key"]),
            layers,
            lambda tmp: fill_arrays(
                tmp,
                layers,
                previous.batches() if previous.intact() else predicted(),
                f"predict {world.house_id}",
                progress,
            ),
            f"predicted cache {world.house_id}",
        )
        previous.remove(directory)
        return open_layers(cls, directory, meta)


# -- managing a cache folder (objsearch cache list / verify / clear) --------------------
def _layers_of(meta: dict, kind: str) -> dict | None:
    """The layers ({name: (dtype, shape)}) a cache of ``kind`` with metadata ``meta`` holds, as
    ``HouseCache.open`` and ``PredictedCache.open`` write them (None when ``meta`` does not say):
    so that ``cache list`` checks each file's ``.npy`` header byte for byte."""
    try:
        n, h, w = int(meta["num_poses"]), int(meta["settings"]["height"]), int(meta["settings"]["width"])
    except (KeyError, TypeError, ValueError):
        return None
    return {FRAMES: (record_dtype(PREDICTED_ORDER if kind == "predicted" else RECORD_ORDER, h, w), (n,))}


def cache_folders(root: Path, digests: bool = False) -> list[dict]:
    """Every cache objsearch made in ``root`` (``cache_meta``: any other folder is none of them):
    {path, house, kind ("obs" or "predicted"), bytes, problem, link (a symlink to a cache)};
    ``problem`` None: of this version and intact (file sizes and .npy headers; with ``digests``, sha256s)."""
    out = []
    for path in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")) if root.is_dir() else []:
        meta = cache_meta(path)
        if meta is None:
            continue
        kind = "predicted" if meta["version"].startswith("predicted-") else "obs"
        if meta["version"] != (PREDICTED_VERSION if kind == "predicted" else CACHE_VERSION):
            problem = f"old version {meta['version']}"
        else:
            problem = check_folder(path, layers=_layers_of(meta, kind), digests=digests)
        size, link = folder_bytes(path), path.is_symlink()
        out.append(
            {"path": path, "house": meta["house_id"], "kind": kind, "bytes": size, "problem": problem, "link": link}
        )
    return out
