"""Datasets of rendered frames for the perception network: ``objsearch perception dataset``.

Frames are rendered at agent poses (pose-graph poses: 0.25 m cells, 4 headings) of a suite's
houses, which keep training and evaluation apart. Of the ``house-gen`` suite (the default, the
shipped network's):

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

Of the large-house tier's ``house-large`` (``suite="house-large"``: 9-14 room ``house-gen-3``
houses with its small targets, a cup, a remote, an alarm clock, ...): ``train`` its 60 training
houses, ``val`` its 5 validation houses and ``test`` its 10 test houses (held-out mesh variants);
no ``test-seen-shapes``.

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
from objsearch.perception.targets import small_target_categories, target_categories

DATASET_VERSION = "perception-data-v1"
SPLITS = ("train", "val", "test", "test-seen-shapes")
SUITE = "house-gen"
#: The suites whose houses a dataset can be rendered from (``suite``); only ``SUITE`` has generated
#: training houses beyond its own and a ``test-seen-shapes`` split.
SUITES = ("house-gen", "house-large")
MAX_DEPTH_MM = 65535
#: Seeds of the generated training houses beyond the suite's 40 (suites use seeds below 4000).
EXTRA_TRAIN_SEED = 10_000
#: Seeds of the ``test-seen-shapes`` houses (no suite and no other split uses them).
SEEN_SHAPES_SEED = 20_000
#: ``variety``: a training house's poses are rendered in this many groups, each from its own varied model.
VARIED_GROUPS = 4
VARIETY_STREAM = 7  # the variety's rng: default_rng([seed, house seed, VARIETY_STREAM])
#: ``target_share``: a training house's poses are chosen among this many times as many drawn
#: candidates, rendered first to see which show a target.
TARGET_CANDIDATES = 8
#: ``target_share``: a frame shows a target when at least this many of its pixels are one (the
#: large-house tier's goal rule counts 5).
TARGET_FRAME_PIXELS = 5
TARGET_STREAM = 11  # the choice's rng: default_rng([seed, house seed, TARGET_STREAM])
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


def check_suite(suite: str) -> None:
    """``UserError`` unless ``suite`` is one of ``SUITES``."""
    if suite not in SUITES:
        raise UserError(f"a perception dataset renders the houses of {' or '.join(SUITES)}, not {suite!r}")


def default_houses(suite: str = SUITE) -> dict[str, int]:
    """split -> houses of the default build of ``suite``: ``DEFAULT_HOUSES`` for ``SUITE``, every
    house of each split of the others (and no ``test-seen-shapes``)."""
    check_suite(suite)
    if suite == SUITE:
        return dict(DEFAULT_HOUSES)
    return {split: len(split_houses(split, suite=suite)) for split in SPLITS if split != "test-seen-shapes"}


def frame_targets(suite: str) -> list[int]:
    """The category ids a ``target_share`` build looks for in ``suite``'s frames: the large-house
    tier's small targets for ``house-large``, the house suites' targets for ``house-gen``."""
    check_suite(suite)
    return small_target_categories() if suite == "house-large" else target_categories()


def split_houses(split: str, count: int | None = None, suite: str = SUITE) -> dict[str, dict]:
    """house id -> HouseRef fields of the first ``count`` houses of ``split`` of ``suite``
    (default count: all the suite has).

    ``house-gen``'s ``train`` takes any count: past the suite's 40 training houses it generates
    houses from seeds ``EXTRA_TRAIN_SEED`` + i (about 0.2 s each); its other splits have 10
    each. Another suite's splits are its own houses, and it has no ``test-seen-shapes``.
    """
    from objsearch.sim.suites import load_suite_file

    if split not in SPLITS:
        raise UserError(f"unknown dataset split {split!r}; known: {', '.join(SPLITS)}")
    check_suite(suite)
    if split == "test-seen-shapes" and suite != SUITE:
        if not count:
            return {}
        raise UserError(f"{suite} has no test-seen-shapes split (only {SUITE} does); ask for 0 of its houses")
    generates = suite == SUITE and split == "train"
    suite = load_suite_file(suite)
    if split == "train":
        houses = sorted(suite["training_houses"].items())
    elif split == "test-seen-shapes":
        size = DEFAULT_HOUSES[split]  # generated on demand: no more than the split has
        houses = _generated(SEEN_SHAPES_SEED, size if count is None else min(count, size))
    else:
        prefix = {"val": "test_002", "test": "test_003"}[split]  # val seeds 2000.., test seeds 3000..
        houses = sorted((h, info) for h, info in suite["houses"].items() if h.startswith(prefix))
    count = len(houses) if count is None else count
    if count > len(houses) and not generates:
        raise UserError(
            f"the {split} split of {suite['suite']} has {len(houses)} houses, not {count}; "
            f"ask for at most {len(houses)}"
        )
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
    suite: str = SUITE,
    target_share: float = 0.0,
) -> dict:
    """Render the dataset into ``out`` (resuming: shards already there with the same meta are kept).

    Args:
        out: dataset folder.
        settings: ``RenderSettings`` (default: ``objsearch.sim.camera.AGENT_CAMERA``, 64 x 64).
        seed: pose sampling seed.
        poses_per_house: frames per training house.
        eval_poses_per_house: frames per validation and test house.
        houses: split -> number of houses; a split it does not name (or names with 0) is left
            out (default: ``default_houses(suite)``, every split).
        progress: show a progress bar.
        executor, address, workers: where the houses' shards are rendered, one task per
            house (``objsearch.cluster.map_houses``; on a Ray cluster ``out`` must be on a
            filesystem every node shares). The files are the same for any of them.
        variety: strength (0..1) of the appearance variety of training frames
            (``objsearch.perception.variety``; 0: none, the frames as the houses look). The
            validation and test frames never vary.
        suite: the suite whose houses are rendered (``SUITES``).
        target_share: the share (0..1) of each training house's frames chosen among poses whose
            frame shows one of the suite's targets (``frame_targets``; ``choose_pose_ids``), as
            far as the house has them; 0: uniform poses. Validation and test frames stay uniform.

    Returns:
        The manifest (also written to ``out/manifest.json`` once every shard is there).
    """
    from functools import partial

    from objsearch.cluster import map_houses
    from objsearch.sim.camera import AGENT_CAMERA
    from objsearch.sim.suites import load_suite_file

    check_suite(suite)
    settings = settings or AGENT_CAMERA
    out = Path(out)
    houses = default_houses(suite) if houses is None else houses
    unknown = sorted(set(houses) - set(SPLITS))
    if unknown:
        raise UserError(f"unknown dataset split(s) {', '.join(unknown)}; known: {', '.join(SPLITS)}")
    plan = []
    for split in SPLITS:
        count = poses_per_house if split == "train" else eval_poses_per_house
        chosen = split_houses(split, houses.get(split, 0), suite=suite)
        plan += [(split, house_id, info, count) for house_id, info in chosen.items()]
    if not 0.0 <= variety <= 1.0:
        raise UserError(f"variety must be between 0 and 1 (got {variety}); 0 renders the houses as they are")
    if not 0.0 <= target_share <= 1.0:
        raise UserError(f"target_share must be between 0 and 1 (got {target_share}); 0 draws poses uniformly")
    targets = tuple(frame_targets(suite)) if target_share else ()
    task = partial(
        render_shard,
        out=out.resolve(),
        settings=settings,
        seed=seed,
        variety=variety,
        target_share=target_share,
        targets=targets,
    )
    shards = map_houses(task, plan, executor, address, workers, desc=f"render {out.name}", progress=progress)
    manifest = {
        "version": DATASET_VERSION,
        "suite": suite,
        "suite_version": load_suite_file(suite)["version"],
        "categories": CATEGORY_TABLE_VERSION,
        "num_classes": NUM_CLASSES,
        "settings": settings.to_json(),
        "settings_key": settings.key(),
        "seed": seed,
        "splits": {},
    }
    if variety:  # recorded only when used, so a build without it keeps its bytes
        manifest["variety"] = variety
    if target_share:
        manifest["target_share"] = target_share
    for (split, house_id, info, _), shard in zip(plan, shards):
        entry = manifest["splits"].setdefault(split, {"houses": {}, "frames": 0, "class_pixels": [0] * NUM_CLASSES})
        entry["houses"][house_id] = {**info, "frames": shard["frames"], "shard": f"{split}/{house_id}.npz"}
        entry["frames"] += shard["frames"]
        entry["class_pixels"] = [a + b for a, b in zip(entry["class_pixels"], shard["class_pixels"])]
        if "target_frames" in shard:  # training shards of a target_share build
            entry["target_frames"] = entry.get("target_frames", 0) + shard["target_frames"]
    write_json(out / "manifest.json", manifest)
    return manifest


def shows_target(semantic: np.ndarray, targets) -> np.ndarray:
    """Per frame of (N, H, W) ``semantic``: whether at least ``TARGET_FRAME_PIXELS`` pixels are a
    category of ``targets``."""
    return np.isin(semantic, list(targets)).sum(axis=(1, 2)) >= TARGET_FRAME_PIXELS


def choose_pose_ids(world, settings, count: int, seed: int, house_seed: int, share: float, targets) -> np.ndarray:
    """``count`` distinct pose ids (sorted) of ``world``, ``round(share * count)`` of them (as far
    as there are) among those whose frame shows at least ``TARGET_FRAME_PIXELS`` pixels of a
    category of ``targets``: ``TARGET_CANDIDATES`` x ``count`` candidates are drawn as
    ``sample_pose_ids`` draws, rendered, and chosen from by ``default_rng([seed, house seed,
    TARGET_STREAM])``."""
    from objsearch.sim.renderer import HouseRenderer

    candidates = sample_pose_ids(world.graph.num_poses, count * TARGET_CANDIDATES, seed, house_seed)
    with HouseRenderer(world.model, settings) as renderer:
        semantic = renderer.render(world.graph.world_poses(candidates)).semantic
    shows = shows_target(semantic, targets)
    rng = np.random.default_rng([seed, house_seed, TARGET_STREAM])
    count = min(count, len(candidates))
    with_target = rng.permutation(candidates[shows])[: min(round(share * count), count)]
    rest = rng.permutation(np.setdiff1d(candidates, with_target))[: count - len(with_target)]
    return np.sort(np.concatenate([with_target, rest])).astype(np.int32)


def render_shard(
    item: tuple[str, str, dict, int],
    out: Path,
    settings,
    seed: int,
    variety: float = 0.0,
    target_share: float = 0.0,
    targets: tuple[int, ...] = (),
) -> dict:
    """The task of ``build_dataset``: the shard ``out/<split>/<house id>.npz`` of one house
    (``item``: split, house id, ``HouseRef`` fields, poses), kept if one with the same meta is
    there. Returns its number of frames and pixel count of every category id.

    With ``variety`` a training house's poses are rendered in ``VARIED_GROUPS`` consecutive
    groups, group k from the house's model varied with strength ``variety * (k + 1) /
    VARIED_GROUPS`` (``objsearch.perception.variety.vary_model``, drawn from
    ``default_rng([seed, house seed, VARIETY_STREAM])``). With ``target_share`` a training
    house's poses are ``choose_pose_ids``'s, the returned ``target_frames`` those that show one of
    ``targets``."""
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
    target_share = target_share if split == "train" else 0.0
    if target_share:
        meta["target_share"] = target_share
    shard = read_shard(path) if path.exists() else None
    if shard is None or shard["meta"] != meta:
        world = World.load(HouseRef(**info))
        if target_share:
            pose_ids = choose_pose_ids(world, settings, count, seed, info["seed"], target_share, targets)
        else:
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
    result = {"frames": int(len(pose_ids)), "class_pixels": counts.tolist()}
    if target_share:
        result["target_frames"] = int(shows_target(semantic, targets).sum())
    return result


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
