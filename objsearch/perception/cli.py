"""``objsearch perception dataset|train|eval``: frames, training and evaluation of the network
that predicts segmentation and depth from RGB (``docs/perception.md``)."""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys

from objsearch.cliargs import key_value, non_negative_int
from objsearch.cluster import add_executor_arguments, check_executor_arguments


def add_parser(subparsers) -> None:
    """Add ``objsearch perception`` (dataset, train, eval) to ``subparsers``."""
    parser = subparsers.add_parser(
        "perception", help="segmentation + depth network: dataset, train, eval", description=__doc__
    )
    commands = parser.add_subparsers(dest="perception_command", metavar="ACTION", required=True)

    data = commands.add_parser(
        "dataset", help="render training / validation / test frames of house-gen's (or house-large's) houses"
    )
    data.add_argument("--out", required=True, help="dataset folder (an interrupted build there resumes)")
    data.add_argument("--seed", type=non_negative_int, default=0, help="pose sampling seed (default: 0)")
    data.add_argument(
        "--suite",
        default="house-gen",
        help="the suite whose houses are rendered: house-gen (default, the shipped network's) or house-large "
        "(its 60 training, 5 val and 10 test houses with the large-house tier's small targets; no test-seen-shapes)",
    )
    data.add_argument(
        "--poses-per-house", type=non_negative_int, default=200, help="frames per training house (default: 200)"
    )
    data.add_argument(
        "--eval-poses-per-house", type=non_negative_int, default=200, help="frames per val / test house (default: 200)"
    )
    data.add_argument(
        "--train-houses",
        type=non_negative_int,
        help="training houses: house-gen's 40, then generated ones (default: 200; house-large: its 60)",
    )
    for split in ("val", "test", "test-seen-shapes"):
        data.add_argument(
            f"--{split}-houses", type=non_negative_int, help=f"use only the first N of the suite's {split} houses"
        )
    data.add_argument(
        "--size", type=non_negative_int, help="render width and height in pixels (default: 64, the agent camera's)"
    )
    data.add_argument(
        "--variety",
        type=float,
        default=0.0,
        help="strength 0..1 of the training frames' variety in object proportions and colours, walls, floors "
        "and light (objsearch/perception/variety.py; default 0: the houses as they are)",
    )
    data.add_argument(
        "--target-share",
        type=float,
        default=0.0,
        help="share 0..1 of each training house's frames chosen among poses that show one of the suite's "
        "targets (house-large: its small targets), as far as the house has them (default 0: uniform poses)",
    )
    data.add_argument("--quiet", action="store_true", help="no progress bar")
    add_executor_arguments(data, "--out")
    data.set_defaults(func=run_dataset)

    train = commands.add_parser("train", help="train the network (resumable)")
    train.add_argument("--data", required=True, help="dataset folder")
    train.add_argument("--out", required=True, help="run folder; a run there with the same config is resumed")
    train.add_argument("--steps", type=non_negative_int, help="optimizer steps (default: the config's 12000)")
    train.add_argument("--batch-size", type=non_negative_int, help="frames per step (default: 32)")
    train.add_argument("--seed", type=non_negative_int, help="run seed (default: 0)")
    train.add_argument("--device", help="auto (default: CUDA when present), cpu or cuda")
    train.add_argument("--threads", type=non_negative_int, help="torch CPU threads (default: all cores)")
    train.add_argument(
        "--set",
        action="append",
        type=key_value,
        default=[],
        dest="overrides",
        metavar="KEY=VALUE",
        help="override a TrainConfig field (model.FIELD for widths); repeatable",
    )
    train.add_argument("--fresh", action="store_true", help="start over even if --out holds a run")
    train.add_argument("--quiet", action="store_true", help="no progress bar")
    train.set_defaults(func=run_train)

    ev = commands.add_parser("eval", help="evaluate a checkpoint on held-out houses (default: the test split)")
    ev.add_argument(
        "--checkpoint", help="RUN/model.pt written by objsearch perception train (default: the shipped one)"
    )
    ev.add_argument("--data", required=True, help="dataset folder")
    ev.add_argument(
        "--split",
        default="test",
        help="test (default: unseen houses and object instances), test-seen-shapes (unseen houses, "
        "training object shapes), val or train",
    )
    ev.add_argument("--max-frames", type=non_negative_int, help="evaluate only the first N frames")
    ev.add_argument("--device", default="auto", help="auto (default), cpu or cuda")
    ev.add_argument(
        "--json",
        action="store_true",
        help="end with one line of JSON (miou, miou_targets, visibility_f1, depth_absrel, ...)",
    )
    ev.set_defaults(func=run_eval)


def run_dataset(args: argparse.Namespace) -> int:
    """``objsearch perception dataset``: render the frames of the dataset into ``--out``; returns 0."""
    from dataclasses import replace

    from objsearch.perception.dataset import SPLITS, build_dataset, default_houses
    from objsearch.sim.camera import AGENT_CAMERA

    check_executor_arguments(args)
    settings = AGENT_CAMERA if args.size is None else replace(AGENT_CAMERA, width=args.size, height=args.size)
    wanted = {s: getattr(args, f"{s.replace('-', '_')}_houses") for s in SPLITS}
    defaults = default_houses(args.suite)
    limits = {s: defaults.get(s, 0) if n is None else n for s, n in wanted.items()}
    manifest = build_dataset(
        args.out,
        settings=settings,
        seed=args.seed,
        poses_per_house=args.poses_per_house,
        eval_poses_per_house=args.eval_poses_per_house,
        houses=limits,
        progress=not args.quiet,
        executor=args.executor,
        address=args.address,
        workers=args.workers,
        variety=args.variety,
        suite=args.suite,
        target_share=args.target_share,
    )
    for split, entry in manifest["splits"].items():
        shown = f" ({entry['target_frames']} show a target)" if "target_frames" in entry else ""
        print(f"{split}: {entry['frames']} frames from {len(entry['houses'])} houses{shown}")
    print(f"wrote {args.out}/manifest.json")
    return 0


def run_train(args: argparse.Namespace) -> int:
    """``objsearch perception train``: train (or resume) into ``--out``; returns 0, or 130 if
    interrupted (143 by SIGTERM)."""
    from objsearch.interrupt import interrupted_line, stop_status
    from objsearch.perception.config import TrainConfig
    from objsearch.perception.train import train

    overrides = dict(args.overrides)
    for name, key in (
        ("steps", "steps"),
        ("batch_size", "batch_size"),
        ("seed", "seed"),
        ("device", "device"),
        ("threads", "threads"),
    ):
        if getattr(args, name) is not None:
            overrides[key] = str(getattr(args, name))
    config = TrainConfig(data=args.data).with_overrides(overrides)
    print(f"command: objsearch perception {shlex.join(sys.argv[2:]) if len(sys.argv) > 2 else 'train'}")
    finished = train(config, args.out, fresh=args.fresh, progress=not args.quiet)
    if finished:
        print(f"finished: {args.out}/model.pt")
        return 0
    status = stop_status()
    saved = f"checkpoint written to {args.out}; rerun the same command to resume"
    print(f"objsearch perception train: {interrupted_line(status, saved)}", file=sys.stderr)
    return status


class _TimedPredictor:
    """A predictor that adds up the seconds its ``predict`` calls take (the network's frames/s in ``eval``)."""

    def __init__(self, predictor):
        self.predictor, self.settings, self.seconds = predictor, predictor.settings, 0.0

    def predict(self, rgb):
        import time

        start = time.perf_counter()
        out = self.predictor.predict(rgb)
        self.seconds += time.perf_counter() - start
        return out


def _json_value(v, digits: int | None = 4):
    """JSON has no NaN: None; floats rounded to ``digits`` (None: as they are)."""
    if isinstance(v, float):
        return None if math.isnan(v) else (v if digits is None else round(v, digits))
    return v


def run_eval(args: argparse.Namespace) -> int:
    """``objsearch perception eval``: print a checkpoint's segmentation, visibility and depth
    metrics on a split, beside the quality targets (and as JSON)."""
    import torch

    from objsearch.house.categories import CATEGORY_NAMES
    from objsearch.perception.dataset import load_split, read_manifest
    from objsearch.perception.inference import BATCH, Predictor, evaluate
    from objsearch.perception.metrics import (
        NEAR_DISTANCE,
        QUALITY_TARGETS,
        format_table,
        format_targets,
        target_metrics,
        target_status,
        visibility_scores,
    )
    from objsearch.perception.targets import small_target_categories, target_categories
    from objsearch.sim.camera import RenderSettings, check_camera

    manifest = read_manifest(args.data)
    predictor = Predictor.from_checkpoint(args.checkpoint, device=args.device)
    dataset_camera = RenderSettings.from_json(manifest["settings"], source=f"{args.data}/manifest.json")
    check_camera(
        predictor.settings,
        dataset_camera,
        source=f"perception checkpoint {predictor.checkpoint}",
        expected_name=f"the camera of dataset {args.data}",
        fix="pass a --data rendered with the checkpoint's camera (objsearch perception dataset --size), "
        "or the --checkpoint trained on this dataset",
    )
    frames = load_split(args.data, args.split, args.max_frames)
    timed = _TimedPredictor(predictor)
    result = evaluate(timed, frames, progress=not args.json)
    targets = target_categories()
    result.update(target_metrics(result, targets))
    small = small_target_categories()
    small_present = sum(c in result["iou"] for c in small)
    if small_present:
        result.update({k.replace("_targets", "_small_targets"): v for k, v in target_metrics(result, small).items()})
    result["predict_frames_per_s"] = len(frames) / timed.seconds if timed.seconds else float("nan")
    present = sum(c in result["iou"] for c in targets)
    print(
        f"{args.split}: {len(frames)} frames from {len(set(frames.houses.tolist()))} houses, checkpoint {predictor.key}"
    )
    print(format_table(result, targets))
    print(
        f"over the {present} target categories of the house suites present: mIoU {result['miou_targets']:.3f}   "
        f"visibility F1 {result['visibility_f1_targets']:.3f}   10x10 map IoU {result['mask10_iou_targets']:.3f}"
    )
    print(
        f"the ObjectNav STOP test (>= {result['visible_pixels']} pixels within {NEAR_DISTANCE:g} m by depth) on the "
        f"predictions, target categories: precision {result['stop_precision_targets']:.3f} (frames where the "
        f"ground truth passes it too), recall {result['stop_recall_targets']:.3f}"
    )
    if small_present:
        print(
            f"over the {small_present} small targets of the large-house tier present: mIoU "
            f"{result['miou_small_targets']:.3f}   STOP test precision {result['stop_precision_small_targets']:.3f}, "
            f"recall {result['stop_recall_small_targets']:.3f}"
        )
    print(
        f"network: {result['predict_frames_per_s']:.1f} frames/s (batches of {BATCH}, {predictor.device}, "
        f"{torch.get_num_threads()} torch threads; benchmarks/bench_perception.py measures it properly); "
        "target >= 150 frames/s batched on 2 CPU cores"
    )
    print(
        "quality targets:" if args.split == "test" else f"quality targets (set for the test split, not {args.split}):"
    )
    labels = {
        "miou_targets": f"mIoU, the suites' {present} target categories",
        "miou": f"mIoU, all {len(result['counted'])} object categories",
        "visibility_f1": f"visibility F1 (>= {result['visible_pixels']} pixels), all objects",
        "depth_absrel": "depth AbsRel",
    }
    print(format_targets(result, labels))
    if args.json:
        per_category_visibility, per_category_near = (
            {
                CATEGORY_NAMES.get(c, str(c)): {
                    **counts,
                    **{k: _json_value(v) for k, v in visibility_scores(counts).items()},
                }
                for c, counts in result[key].items()
            }
            for key in ("visibility", "near")
        )
        summary = {
            k: _json_value(v, None)
            for k, v in result.items()
            if k not in ("iou", "gt_pixels", "counted", "confused_with", "visibility", "near", "mask10_iou")
        }
        summary.update(
            split=args.split,
            frames=len(frames),
            checkpoint_key=predictor.key,
            torch_threads=torch.get_num_threads(),
            counted=[CATEGORY_NAMES[c] for c in result["counted"]],
            targets=[CATEGORY_NAMES[c] for c in targets],
            small_targets=[CATEGORY_NAMES[c] for c in small if c in result["iou"]],
            per_category={CATEGORY_NAMES[c]: round(v, 4) for c, v in result["iou"].items()},
            visibility_per_category=per_category_visibility,
            near_per_category=per_category_near,
            mask10_per_category={CATEGORY_NAMES[c]: _json_value(v) for c, v in result["mask10_iou"].items()},
            confused_with={
                CATEGORY_NAMES[c]: [CATEGORY_NAMES.get(o, "?"), round(share, 4)]
                for c, (o, share) in result["confused_with"].items()
            },
            quality_targets={
                k: {"target": f"{op} {t}", "status": target_status(result.get(k, float("nan")), (op, t))}
                for k, (op, t) in QUALITY_TARGETS.items()
            },
        )
        print(json.dumps(summary, sort_keys=True))
    return 0
