"""Datasets of rendered frames for the perception network: ``objsearch perception dataset``.

Frames are rendered at agent poses (pose-graph poses: 0.25 m cells, 4 headings) of the
``house-gen`` suite's houses, which keep training and evaluation apart:

* ``train``: the suite's 40 training houses, then as many more as asked for, generated
  from seeds ``EXTRA_TRAIN_SEED`` + 0, 1, ... that no suite uses (generator split
  ``train``: training object mesh variants only). The default 200 houses give the network
  five times the layouts, colours and object arrangements of the suite's 40: with 40
  houses it fitted them (training-house mIoU 0.53) far better than it generalised to
  unseen ones (0.23);
* ``val``: its 10 validation houses, ``test``: its 10 test houses (generator split
  ``test``: held-out mesh variants, so evaluation sees unseen object instances);
* ``test-seen-shapes``: 10 houses generated from seeds ``SEEN_SHAPES_SEED`` + 0, 1, ... with
  the generator split ``train``: unseen houses furnished with the training mesh variants.
  Beside ``test`` it splits a network's generalisation gap in two: new houses, and new
  object shapes (``docs/perception.md``, "Where the gap is").

Each house gets ``poses_per_house`` poses drawn without replacement by
``numpy.random.default_rng([seed, house seed])`` (independent of the order and number of
houses, so an interrupted build resumes and a smaller build is a prefix of a larger one).

On disk (``OUT/``)::

    manifest.json                  version, settings, seed, per split: houses, frames,
                                   pixel count of every category id
    train/train_001000.npz ...     one shard per house (np.savez_compressed):
                                   rgb uint8 (N, H, W, 3), depth_mm uint16 (N, H, W)
                                   (planar depth in millimetres, 30000 = nothing hit),
                                   semantic uint8 (N, H, W) category ids,
                                   pose_ids int32 (N,), meta (JSON text)

Sizes at 64 x 64: 24 KiB a frame raw (12 rgb + 8 depth + 4 semantic), about 2-3 KiB
compressed (flat-shaded synthetic images compress well). The default build (200 poses x
200 training houses, 200 x 10 val, 200 x 10 test and 200 x 10 test-seen-shapes) holds 46,000
frames (40,000 / 2,000 / 2,000 / 2,000), about 93 MB on disk and 1.4 GB in memory (depth as float32); see
``docs/perception.md`` for its build time.
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_write, write_json
from objsearch.house.categories import CATEGORY_TABLE_VERSION
from objsearch.perception.model import NUM_CLASSES

DATASET_VERSION = "perception-data-v1"
SPLITS = ("train", "val", "test", "test-seen-shapes")
SUITE = "house-gen"
MAX_DEPTH_MM = 65535
#: Seeds of the generated training houses beyond the suite's 40 (suites use seeds below 4000).
EXTRA_TRAIN_SEED = 10_000
#: Seeds of the ``test-seen-shapes`` houses (no suite and no other split uses them).
SEEN_SHAPES_SEED = 20_000
#: ``variety``: a training house's poses are rendered in this many groups, each from its own varied model.
VARIED_GROUPS = 4
VARIETY_STREAM = 7  # the variety's rng: default_rng([seed, house seed, VARIETY_STREAM])
#: Houses per split of the default build.
DEFAULT_HOUSES = {"train": 200, "val": 10, "test": 10, "test-seen-shapes": 10}


@dataclass
class FrameSet:
    """Frames of one split in memory.

    Attributes:
        rgb: uint8 (N, H, W, 3).
        depth: float32 (N, H, W) metres (millimetre resolution).
        semantic: uint8 (N, H, W) category ids.
        houses: house id of every frame (N,).
    """

    rgb: np.ndarray
    depth: np.ndarray
    semantic: np.ndarray
    houses: np.ndarray

    def __len__(self) -> int:
        return len(self.rgb)


def split_houses(split: str, count: int | None = None) -> dict[str, dict]:
    """house id -> HouseRef fields of the first ``count`` houses of ``split`` (default: the suite's).

    ``train`` takes any count: past the suite's 40 training houses it generates houses from
    seeds ``EXTRA_TRAIN_SEED`` + i (about 0.2 s each). The other splits have 10 each.
    """
    from objsearch.sim.suites import load_suite_file

    if split not in SPLITS:
        raise UserError(f"unknown dataset split {split!r}; known: {', '.join(SPLITS)}")
    suite = load_suite_file(SUITE)
    if split == "train":
        houses = sorted(suite["training_houses"].items())
    elif split == "test-seen-shapes":
        size = DEFAULT_HOUSES[split]  # generated on demand: no more than the split has
        houses = _generated(SEEN_SHAPES_SEED, size if count is None else min(count, size))
    else:
        prefix = {"val": "test_002", "test": "test_003"}[split]  # house-gen: val seeds 2000.., test seeds 3000..
        houses = sorted((h, info) for h, info in suite["houses"].items() if h.startswith(prefix))
    count = len(houses) if count is None else count
    if count > len(houses) and split != "train":
        raise UserError(f"the {split} split has {len(houses)} houses, not {count}; ask for at most {len(houses)}")
    if count > len(houses):
        houses += _generated(EXTRA_TRAIN_SEED, count - len(houses))
    return dict(houses[:count])


def _generated(first_seed: int, count: int) -> list[tuple[str, dict]]:
    """(house id, ``HouseRef`` fields) of ``count`` houses generated as training houses from seeds ``first_seed`` + i."""
    from objsearch.sim.suite_build import house_entry
    from objsearch.sim.world import HouseRef, World

    houses = []
    for seed in range(first_seed, first_seed + count):
        ref = HouseRef(seed=seed, split="train")
        world = World.load(ref)
        houses.append((world.house_id, house_entry(world, ref)))
    return houses


def sample_pose_ids(num_poses: int, count: int, seed: int, house_seed: int) -> np.ndarray:
    """``count`` distinct pose ids (sorted) of a house, drawn from its own Generator."""
    rng = np.random.default_rng([seed, house_seed])
    return np.sort(rng.choice(num_poses, size=min(count, num_poses), replace=False)).astype(np.int32)


def encode_depth(depth: np.ndarray) -> np.ndarray:
    """Metres -> uint16 millimetres (rounded, clipped at 65.535 m)."""
    return np.clip(np.rint(depth * 1000.0), 0, MAX_DEPTH_MM).astype(np.uint16)


def decode_depth(depth_mm: np.ndarray) -> np.ndarray:
    """uint16 millimetres -> float32 metres."""
    return depth_mm.astype(np.float32) / np.float32(1000.0)


def write_shard(path: Path, rgb, depth, semantic, pose_ids, meta: dict) -> None:
    """One house's frames as a compressed ``.npz``, written atomically."""
    buffer = io.BytesIO()
    np.savez_compressed(
        buffer,
        rgb=rgb,
        depth_mm=encode_depth(depth),
        semantic=semantic,
        pose_ids=np.asarray(pose_ids, np.int32),
        meta=np.array(json.dumps(meta, sort_keys=True)),
    )
    with atomic_write(path, "wb") as f:
        f.write(buffer.getvalue())


def read_shard(path: Path) -> dict:
    """A shard's arrays (``depth`` in float32 metres) and ``meta`` dict."""
    try:
        with np.load(path) as data:
            out = {k: data[k] for k in ("rgb", "semantic", "pose_ids")}
            out["depth"] = decode_depth(data["depth_mm"])
            out["meta"] = json.loads(str(data["meta"]))
    except (OSError, ValueError, KeyError) as err:
        raise UserError(
            f"cannot read dataset shard {path}: {err}; delete it and rerun objsearch perception dataset"
        ) from None
    return out


def build_dataset(
    out: str | Path,
    *,
    settings=None,
    seed: int = 0,
    poses_per_house: int = 200,
    eval_poses_per_house: int = 200,
    houses: dict[str, int] | None = None,
    progress: bool = True,
    executor: str = "local",
    address: str | None = None,
    workers: int | None = None,
    variety: float = 0.0,
) -> dict:
    """Render the dataset into ``out`` (resuming: shards already there with the same meta are kept).

    Args:
        out: dataset folder.
        settings: ``RenderSettings`` (default: ``objsearch.sim.camera.AGENT_CAMERA``, 64 x 64).
        seed: pose sampling seed.
        poses_per_house: frames per training house.
        eval_poses_per_house: frames per validation and test house.
        houses: split -> number of houses; a split it does not name (or names with 0) is left
            out (default: ``DEFAULT_HOUSES``, every split).
        progress: show a progress bar.
        executor, address, workers: where the houses' shards are rendered, one task per
            house (``objsearch.cluster.map_houses``; on a Ray cluster ``out`` must be on a
            filesystem every node shares). The files are the same for any of them.
        variety: strength (0..1) of the appearance variety of training frames
            (``objsearch.perception.variety``; 0: none, the frames as the houses look). The
            validation and test frames never vary.

    Returns:
        The manifest (also written to ``out/manifest.json`` once every shard is there).
    """
    from functools import partial

    from objsearch.cluster import map_houses
    from objsearch.sim.camera import AGENT_CAMERA
    from objsearch.sim.suites import load_suite_file

    settings = settings or AGENT_CAMERA
    out = Path(out)
    houses = DEFAULT_HOUSES if houses is None else houses
    unknown = sorted(set(houses) - set(SPLITS))
    if unknown:
        raise UserError(f"unknown dataset split(s) {', '.join(unknown)}; known: {', '.join(SPLITS)}")
    plan = []
    for split in SPLITS:
        count = poses_per_house if split == "train" else eval_poses_per_house
        chosen = split_houses(split, houses.get(split, 0))
        plan += [(split, house_id, info, count) for house_id, info in chosen.items()]
    if not 0.0 <= variety <= 1.0:
        raise UserError(f"variety must be between 0 and 1 (got {variety}); 0 renders the houses as they are")
    task = partial(render_shard, out=out.resolve(), settings=settings, seed=seed, variety=variety)
    shards = map_houses(task, plan, executor, address, workers, desc=f"render {out.name}", progress=progress)
    manifest = {
        "version": DATASET_VERSION,
        "suite": SUITE,
        "suite_version": load_suite_file(SUITE)["version"],
        "categories": CATEGORY_TABLE_VERSION,
        "num_classes": NUM_CLASSES,
        "settings": settings.to_json(),
        "settings_key": settings.key(),
        "seed": seed,
        "splits": {},
    }
    if variety:  # recorded only when used, so a build without it keeps its bytes
        manifest["variety"] = variety
    for (split, house_id, info, _), shard in zip(plan, shards):
        entry = manifest["splits"].setdefault(split, {"houses": {}, "frames": 0, "class_pixels": [0] * NUM_CLASSES})
        entry["houses"][house_id] = {**info, "frames": shard["frames"], "shard": f"{split}/{house_id}.npz"}
        entry["frames"] += shard["frames"]
        entry["class_pixels"] = [a + b for a, b in zip(entry["class_pixels"], shard["class_pixels"])]
    write_json(out / "manifest.json", manifest)
    return manifest


def render_shard(item: tuple[str, str, dict, int], out: Path, settings, seed: int, variety: float = 0.0) -> dict:
    """The task of ``build_dataset``: the shard ``out/<split>/<house id>.npz`` of one house
    (``item``: split, house id, ``HouseRef`` fields, poses), kept if one with the same meta is
    there. Returns its number of frames and pixel count of every category id.

    With ``variety`` a training house's poses are rendered in ``VARIED_GROUPS`` consecutive
    groups, group k from the house's model varied with strength ``variety * (k + 1) /
    VARIED_GROUPS`` (``objsearch.perception.variety.vary_model``, drawn from
    ``default_rng([seed, house seed, VARIETY_STREAM])``)."""
    from objsearch.perception.variety import vary_model
    from objsearch.sim.renderer import HouseRenderer
    from objsearch.sim.world import HouseRef, World

    split, house_id, info, count = item
    path = out / split / f"{house_id}.npz"
    meta = {
        "version": DATASET_VERSION,
        "house": house_id,
        "spec_sha256": info["spec_sha256"],
        "settings_key": settings.key(),
        "seed": seed,
        "requested": count,
    }
    variety = variety if split == "train" else 0.0
    if variety:
        meta["variety"] = variety
    shard = read_shard(path) if path.exists() else None
    if shard is None or shard["meta"] != meta:
        world = World.load(HouseRef(**info))
        pose_ids = sample_pose_ids(world.graph.num_poses, count, seed, info["seed"])
        poses = world.graph.world_poses(pose_ids)
        rng = np.random.default_rng([seed, info["seed"], VARIETY_STREAM])
        groups = np.array_split(np.arange(len(pose_ids)), VARIED_GROUPS if variety else 1)
        parts = []
        for k, group in enumerate(groups):
            model = vary_model(world.model, rng, variety * (k + 1) / len(groups)) if variety else world.model
            with HouseRenderer(model, settings) as renderer:
                parts.append(renderer.render(poses[group]))
        rgb, depth, semantic = (np.concatenate([getattr(f, a) for f in parts]) for a in ("rgb", "depth", "semantic"))
        write_shard(path, rgb, depth, semantic, pose_ids, meta)
    else:
        semantic, pose_ids = shard["semantic"], shard["pose_ids"]
    counts = np.bincount(semantic.ravel(), minlength=NUM_CLASSES)
    return {"frames": int(len(pose_ids)), "class_pixels": counts.tolist()}


def read_manifest(data_dir: str | Path) -> dict:
    """The dataset's ``manifest.json``; ``UserError`` if it cannot be read or has another version."""
    path = Path(data_dir) / "manifest.json"
    try:
        manifest = json.loads(path.read_text())
    except (OSError, ValueError) as err:
        raise UserError(
            f"cannot read {path} ({err}); build the dataset with objsearch perception dataset --out {data_dir}"
        ) from None
    if manifest.get("version") != DATASET_VERSION:
        raise UserError(
            f"{path} is version {manifest.get('version')!r}, expected {DATASET_VERSION!r}; rebuild the dataset"
        )
    return manifest


def load_split(data_dir: str | Path, split: str, max_frames: int | None = None) -> FrameSet:
    """All frames of ``split`` (or the first ``max_frames``) in memory."""
    manifest = read_manifest(data_dir)
    if split not in manifest["splits"]:
        raise UserError(f"dataset {data_dir} has no {split!r} split; it has: {', '.join(manifest['splits'])}")
    parts = {"rgb": [], "depth": [], "semantic": [], "houses": []}
    have = 0
    for house_id, entry in manifest["splits"][split]["houses"].items():
        if max_frames is not None and have >= max_frames:
            break
        shard = read_shard(Path(data_dir) / entry["shard"])
        for key in ("rgb", "depth", "semantic"):
            parts[key].append(shard[key])
        parts["houses"].append(np.full(len(shard["rgb"]), house_id))
        have += len(shard["rgb"])
    arrays = {k: np.concatenate(v)[:max_frames] for k, v in parts.items()}
    return FrameSet(**arrays)
