"""Observations pre-rendered at every pose of a house (the paper's protocol).

A cache lives in ``<cache dir>/<house_id>-<key>/`` with ``rgb.npy`` uint8 (P, H, W, 3),
``depth.npy`` uint16 (P, H, W) millimetres, ``semantic.npy`` uint8 (P, H, W) and ``meta.json``
(24 KB a pose at 64x64; 40-150 MB a house). ``.depth`` reads as float32 metres
(``MillimetreDepth``), bit-identical to ``quantize_depth`` of the rendered depth. The key hashes the house's spec, the render settings and the pose-graph
version, so a changed house or camera never reads a stale cache; a cache whose metadata
does not match is rebuilt. It is built in a temporary folder and renamed into place, so an
interrupted build leaves nothing half-written. The cache directory is ``$OBJSEARCH_CACHE``,
else ``~/.cache/objsearch``, or what the caller passes.

Integrity: ``meta.json`` records the size and sha256 of every layer file. ``open`` checks
them all (sizes, ``.npy`` headers, digests: about 0.1 s for 150 MB with a warm page cache)
and *rebuilds* a damaged cache, saying why on stderr, as it rebuilds a stale one; it is a
cache, so rebuilding is always right. ``objsearch cache verify`` checks caches without
opening them, ``objsearch cache clear`` removes them. Builds of one cache are serialised by
a lock file (``.<name>.lock``, there while it is held), so concurrent builders build it once; temp folders of killed
builds are removed when a build starts (``fileio.abandoned_temp_folders``).

Memory: a process opens each cache folder once (``open_layers``: every env of a batched
evaluation that plays the house shares it) and lets go of it when its last user does (the
env holds only the house in play). The env reads each step's frames from the files
(``CacheLayers.reader``, ``pread``): nothing is mapped, so memory does not grow with the
poses or houses visited (an env keeps the depth of its last 64 poses read: 1 MB); whole layers (``.rgb``, ``.depth``, ``.semantic``) are
memory-mapped on first use, for gathers over many poses (training, goal poses).

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
import weakref
from pathlib import Path
from typing import Callable, Protocol

import numpy as np

from objsearch.sim.cache_folder import check_folder, ensure_folder, fill_arrays, folder_bytes
from objsearch.sim.camera import AGENT_CAMERA, AGENT_CAMERA_NAME, RenderSettings, check_predictor_camera
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.renderer import HouseRenderer
from objsearch.sim.world import World

CACHE_VERSION = "cache-v2"  # v2: uint16 millimetre depth, file digests in meta.json
PREDICTED_VERSION = "predicted-cache-v2"
BATCH = 256
LAYERS = ("rgb", "depth", "semantic")
MAX_DEPTH_MM = np.iinfo(np.uint16).max  # 65.535 m: far beyond any house (zfar is 30 m by default)
_MM = np.float32(
    1000
)  # float32(mm) / 1000 in float32 is exactly quantize_depth's value for every uint16 (a test checks
# all 65,536), and 10x faster than a lookup table


def default_cache_dir() -> Path:
    """The cache folder: ``$OBJSEARCH_CACHE``, else ``~/.cache/objsearch``."""
    return Path(os.environ.get("OBJSEARCH_CACHE") or Path.home() / ".cache" / "objsearch")


def quantize_depth(depth: np.ndarray) -> np.ndarray:
    """Depth rounded to the millimetre (float32 metres): what both modes observe."""
    return (np.rint(depth * 1000.0) / 1000.0).astype(np.float32)


def depth_to_mm(depth: np.ndarray) -> np.ndarray:
    """float32 metres -> uint16 millimetres (how caches store depth)."""
    mm = np.rint(np.asarray(depth, np.float32) * np.float32(1000))
    if mm.size and not (mm.min() >= 0 and mm.max() <= MAX_DEPTH_MM):
        raise ValueError(f"depth {mm.min() / 1000}..{mm.max() / 1000} m is outside what a cache stores (0..65.535 m)")
    return mm.astype(np.uint16)


class MillimetreDepth(np.lib.mixins.NDArrayOperatorsMixin):
    """A cache's uint16 millimetre depth that reads as float32 metres: indexing converts only
    the frames taken (``depth[poses]``); ``np.asarray`` and arithmetic convert it all."""

    dtype = np.dtype(np.float32)

    def __init__(self, mm: np.ndarray):
        self.mm = mm

    shape = property(lambda self: self.mm.shape)
    ndim = property(lambda self: self.mm.ndim)

    def __len__(self) -> int:
        return len(self.mm)

    def __getitem__(self, index) -> np.ndarray:
        return np.divide(self.mm[index], _MM, dtype=np.float32)

    def __array__(self, dtype=None, copy=None):
        metres = np.divide(self.mm, _MM, dtype=np.float32)
        return metres if dtype is None else metres.astype(dtype)

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        inputs = [np.asarray(x) if isinstance(x, MillimetreDepth) else x for x in inputs]
        return getattr(ufunc, method)(*inputs, **kwargs)


def cache_key(world: World, settings: RenderSettings) -> str:
    """The 16 hex digits naming a house's cache: a hash of the cache and pose-graph versions, spec hash and camera."""
    text = json.dumps([CACHE_VERSION, NAVGRAPH_VERSION, world.spec_sha256, settings.key()])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _check_depth_range(settings: RenderSettings) -> None:
    from objsearch.errors import UserError

    if settings.zfar * 1000 > MAX_DEPTH_MM:
        raise UserError(
            f"zfar {settings.zfar} m: caches store depth as uint16 millimetres, up to 65.535 m; "
            "use a smaller zfar or mode='live'"
        )


class CacheLayers:
    """The layer files of one cache folder, opened once per process (``open_layers``).

    Two ways in: ``frame(layer, pose)`` reads one pose's frame with ``pread`` (what the env
    does each step: nothing stays mapped, so the process's memory does not grow with the
    poses and houses it visits), and the attributes ``rgb``, ``depth``, ``semantic``: the
    whole layer, memory-mapped on first use (for gathers over many poses). The files
    close, and the maps go, when the last user drops the object (it is shared: no ``close``).
    """

    def __init__(self, directory: Path, meta: dict):
        self.directory = directory
        self.meta = meta
        self._maps: dict[str, np.ndarray] = {}
        self._depth: MillimetreDepth | None = None
        self._num_poses = int(meta["num_poses"])
        self._files: dict[str, tuple] = {}  # layer -> (fd, data offset, frame bytes, frame shape, dtype)
        self._close = weakref.finalize(self, _close_files, self._files)

    @property
    def num_poses(self) -> int:
        """Number of poses (frames) in the cache."""
        return self._num_poses

    def _layer(self, name: str) -> np.ndarray:
        if name not in self._maps:
            # a plain ndarray view of the memory map: indexing it is several times faster
            self._maps[name] = np.asarray(np.load(self.directory / f"{name}.npy", mmap_mode="r"))
        return self._maps[name]

    def _millimetres(self) -> MillimetreDepth:
        if self._depth is None:
            self._depth = MillimetreDepth(self._layer("depth"))
        return self._depth

    depth = property(_millimetres, doc="Depth of every pose, float32 metres (memory-mapped).")
    semantic = property(lambda self: self._layer("semantic"), doc="Category ids of every pose (memory-mapped).")

    def frame(self, name: str, pose: int) -> np.ndarray:
        """A new array holding layer ``name``'s frame of ``pose`` (``depth``: float32 metres),
        read from the file: the same values as ``getattr(self, name)[pose]``."""
        return self.reader(name)(pose)

    def reader(self, name: str, recent: int = 0) -> Callable[[int], np.ndarray]:
        """``frame(name, .)`` as a function bound to the layer's open file: what the env calls
        each step (one ``pread``, one new array; nothing looked up per call). It holds this
        object, so the file stays open while the function is kept.

        ``recent`` (depth only): keep the metres of the last ``recent`` poses read (FIFO) and
        give copies of them: converting millimetres costs several times a copy, and an agent
        often comes back to a pose it has just left (about half of a random walk's steps)."""
        if name not in self._files:
            self._files[name] = _open_layer(self.directory / f"{name}.npy")
        fd, offset, size, shape, dtype = self._files[name]
        num_poses, empty, preadv, divide, float32 = self._num_poses, np.empty, os.preadv, np.divide, np.float32
        layers = self  # the files close when the last holder of this object lets go (no cycle: not stored here)

        def read(pose: int) -> np.ndarray:
            if not 0 <= pose < num_poses:
                raise IndexError(f"pose {pose} is out of range for {num_poses} poses ({layers.directory})")
            out = empty(shape, dtype)
            if preadv(fd, (out,), offset + pose * size) != size:
                raise OSError(f"{layers.directory / name}.npy: short read (truncated?)")
            return out

        if name != "depth":
            return read

        def read_metres(pose: int) -> np.ndarray:
            if not 0 <= pose < num_poses:
                raise IndexError(f"pose {pose} is out of range for {num_poses} poses ({layers.directory})")
            out = empty(shape, dtype)
            if preadv(fd, (out,), offset + pose * size) != size:
                raise OSError(f"{layers.directory / name}.npy: short read (truncated?)")
            # the bits of np.divide(out, _MM, dtype=float32), whose casting loop is slower
            metres = out.astype(float32)
            divide(metres, _MM, out=metres)
            return metres

        if recent <= 0:
            return read_metres
        kept: dict[int, np.ndarray] = {}  # pose -> metres, oldest first

        def read_kept(pose: int) -> np.ndarray:
            frame = kept.get(pose)
            if frame is None:
                frame = kept[pose] = read_metres(pose)
                if len(kept) > recent:
                    del kept[next(iter(kept))]
            return frame.copy()

        return read_kept

    def frames(self, name: str, start: int, stop: int) -> np.ndarray:
        """A new array holding layer ``name``'s frames of poses ``start:stop`` (``depth``:
        float32 metres), read from the file: the same values as ``getattr(self, name)[start:stop]``."""
        if name not in self._files:
            self._files[name] = _open_layer(self.directory / f"{name}.npy")
        fd, offset, size, shape, dtype = self._files[name]
        stop = min(stop, self._num_poses)
        if not 0 <= start < stop:
            raise IndexError(f"poses {start}:{stop} are out of range for {self._num_poses} poses ({self.directory})")
        out = np.empty((stop - start, *shape), dtype)
        if os.preadv(fd, (out,), offset + start * size) != out.nbytes:
            raise OSError(f"{self.directory / name}.npy: short read (truncated?)")
        return np.divide(out, _MM, dtype=np.float32) if name == "depth" else out


def _open_layer(path: Path) -> tuple[int, int, int, tuple, np.dtype]:
    """(fd, offset of the data, bytes of a frame, shape of a frame, dtype) of an ``.npy`` layer file."""
    mapped = np.load(path, mmap_mode="r")  # numpy reads the header; the map goes at once, untouched
    offset, shape, dtype, c_order = mapped.offset, mapped.shape, mapped.dtype, mapped.flags.c_contiguous
    del mapped
    if not c_order:
        raise ValueError(f"{path} is not stored in C order, as caches are written; rebuild it")
    size = int(np.prod(shape[1:])) * dtype.itemsize
    return os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0)), offset, size, tuple(shape[1:]), dtype


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
        """Open the house's cache, building (or rebuilding) it if missing, stale or damaged."""
        _check_depth_range(settings)
        root = Path(cache_dir) if cache_dir is not None else default_cache_dir()
        key = cache_key(world, settings)
        directory = root / f"{world.house_id}-{key}"
        expected = {
            "version": CACHE_VERSION,
            "key": key,
            "house_id": world.house_id,
            "spec_sha256": world.spec_sha256,
            "navgraph": NAVGRAPH_VERSION,
            "settings": settings.to_json(),
            "num_poses": world.graph.num_poses,
        }
        poses = world.graph.world_poses()
        n, h, w = len(poses), settings.height, settings.width
        layers = {"rgb": (np.uint8, (n, h, w, 3)), "depth": (np.uint16, (n, h, w)), "semantic": (np.uint8, (n, h, w))}

        def render(tmp: Path) -> None:
            with HouseRenderer(world.model, settings) as renderer:
                batches = ((start, renderer.render(poses[start : start + BATCH])) for start in range(0, n, BATCH))
                fill_arrays(
                    tmp,
                    layers,
                    (
                        (start, {"rgb": f.rgb, "depth": depth_to_mm(quantize_depth(f.depth)), "semantic": f.semantic})
                        for start, f in batches
                    ),
                    f"cache {world.house_id}",
                    progress,
                )

        meta = ensure_folder(directory, expected, layers, render, f"cache {world.house_id}")
        return open_layers(cls, directory, meta)


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
        directory = gt.directory.parent / f"{gt.directory.name}-pred-{predictor.key}"
        expected = {
            "version": PREDICTED_VERSION,
            "observations": gt.meta["key"],
            "predictor": predictor.key,
            "house_id": world.house_id,
            "settings": settings.to_json(),
            "num_poses": gt.num_poses,
        }
        n, h, w = gt.num_poses, settings.height, settings.width
        layers = {"depth": (np.uint16, (n, h, w)), "semantic": (np.uint8, (n, h, w))}

        def predict(tmp: Path) -> None:
            def batches():
                for start in range(0, n, BATCH):
                    semantic, depth = predictor.predict(gt.frames("rgb", start, start + BATCH))  # not mapped: read once
                    yield start, {"semantic": semantic, "depth": depth_to_mm(quantize_depth(depth))}

            fill_arrays(tmp, layers, batches(), f"predict {world.house_id}", progress)

        meta = ensure_folder(directory, expected, layers, predict, f"predicted cache {world.house_id}")
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
    layers = {"depth": (np.uint16, (n, h, w)), "semantic": (np.uint8, (n, h, w))}
    return layers if kind == "predicted" else {"rgb": (np.uint8, (n, h, w, 3)), **layers}


def cache_folders(root: Path, digests: bool = False) -> list[dict]:
    """Every cache in ``root``: {path, house, kind ("obs" or "predicted"), bytes, problem};
    ``problem`` None: of this version and intact (file sizes and .npy headers; with ``digests``, sha256s)."""
    out = []
    for path in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")) if root.is_dir() else []:
        try:
            meta = json.loads((path / "meta.json").read_text())
            version, house = meta.get("version"), meta.get("house_id", "?")
        except (OSError, ValueError, AttributeError):
            version, house = None, path.name.split("-")[0]
        kind = "predicted" if "-pred-" in path.name else "obs"
        size = folder_bytes(path)
        if version != (PREDICTED_VERSION if kind == "predicted" else CACHE_VERSION):
            problem = "no meta.json" if version is None else f"old version {version}"
        else:
            problem = check_folder(path, layers=_layers_of(meta, kind), digests=digests)
        out.append({"path": path, "house": house, "kind": kind, "bytes": size, "problem": problem})
    return out
