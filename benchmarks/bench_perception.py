"""Perception network inference throughput on the CPU: frames per second at several batch sizes.

    python benchmarks/bench_perception.py [--threads 1] [--size 64] [--batches 1,16,64] [--set KEY=VALUE] [--baseline] [--json]

The default ``SegDepthNet`` (``objsearch.perception.model.ModelConfig()``, or with ``--set``
fields of it, e.g. ``--set separable=true --set decoder=48``), random
weights (speed does not depend on them), uint8 RGB in, what ``Predictor.predict`` returns
out (argmax category ids and depth in metres, as numpy arrays): the cost of filling a
predicted observation cache, or of predicted observations in live mode. Each figure is
the median of ``--repeats`` timed runs of at least ``--seconds`` after a warm-up.

``reference`` is the inference path before issue 15 (full-resolution logits from
``forward``, then the argmax), measured in the same run: the same ids and depth, bit for bit
(``tests/perception/test_perception_model.py``), so the ratio is the speed-up alone.
``--baseline`` also times ``Predictor.predict`` of the default network (``ModelConfig()``) in
the same run, interleaved: the speed-up of a ``--set`` variant over it.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np
import torch

from objsearch.cliargs import key_value
from objsearch.perception.inference import BATCH, Predictor
from objsearch.perception.model import ModelConfig, SegDepthNet, count_parameters, depth_from_log, rgb_to_tensor
from objsearch.perception.train import init_weights
from objsearch.sim.camera import RenderSettings


@torch.no_grad()
def reference_predict(predictor: Predictor, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``Predictor.predict`` as it was before issue 15: the argmax of full-resolution logits, in
    batches of ``BATCH`` frames as there."""
    out = []
    for start in range(0, len(rgb), BATCH):
        logits, log_depth = predictor.model(rgb_to_tensor(rgb[start : start + BATCH]))
        depth = depth_from_log(log_depth, predictor.settings.znear, predictor.settings.zfar)
        out.append((logits.argmax(dim=1).to(torch.uint8).numpy(), depth.numpy()))
    return np.concatenate([o[0] for o in out]), np.concatenate([o[1] for o in out])


def frames_per_second(predict, rgb: np.ndarray, seconds: float) -> float:
    predict(rgb)  # warm-up
    n, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        predict(rgb)
        n += len(rgb)
    return n / (time.perf_counter() - t0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (default: 1)")
    parser.add_argument("--size", type=int, default=64, help="frame width and height (default: 64)")
    parser.add_argument("--batches", default="1,16,64", help="batch sizes (default: 1,16,64)")
    parser.add_argument("--seconds", type=float, default=3.0, help="minimum time per timed run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per batch size; the median is reported")
    parser.add_argument(
        "--set",
        action="append",
        type=key_value,
        default=[],
        metavar="KEY=VALUE",
        help="a ModelConfig field; repeatable",
    )
    parser.add_argument(
        "--baseline", action="store_true", help="also time the default network in the same run, interleaved"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    config = ModelConfig().with_overrides(dict(args.set))
    model = SegDepthNet(config)
    init_weights(model, torch.Generator().manual_seed(0))
    predictor = Predictor(model, RenderSettings(width=args.size, height=args.size), key="bench", device="cpu")
    rng = np.random.default_rng(0)
    paths = {"predict": predictor.predict, "reference": lambda rgb: reference_predict(predictor, rgb)}
    if args.baseline:
        default = SegDepthNet(ModelConfig())
        init_weights(default, torch.Generator().manual_seed(0))
        settings = RenderSettings(width=args.size, height=args.size)
        paths["default"] = Predictor(default, settings, key="bench-default", device="cpu").predict
    results = {path: {} for path in paths}
    for batch in (int(b) for b in args.batches.split(",")):
        rgb = rng.integers(0, 256, (batch, args.size, args.size, 3), dtype=np.uint8)
        for _ in range(args.repeats):  # interleaved, so that a busy stretch of the host hits both paths
            for path, predict in paths.items():
                results[path].setdefault(batch, []).append(frames_per_second(predict, rgb, args.seconds))
    results = {path: {b: statistics.median(v) for b, v in r.items()} for path, r in results.items()}
    info = {
        "threads": args.threads,
        "size": args.size,
        "parameters": count_parameters(model),
        "model": config.to_json(),
        "torch": torch.__version__,
        "frames_per_second": {str(b): round(v, 1) for b, v in results["predict"].items()},
        "reference_frames_per_second": {str(b): round(v, 1) for b, v in results["reference"].items()},
    }
    if args.baseline:
        info["default_frames_per_second"] = {str(b): round(v, 1) for b, v in results["default"].items()}
    if args.json:
        print(json.dumps(info))
        return
    print(
        f"SegDepthNet {info['parameters']:,} parameters, {args.size}x{args.size}, {args.threads} thread(s), torch {torch.__version__}"
    )
    extra = f" {'default':>10} {'vs default':>10}" if args.baseline else ""
    print(f"{'batch':>6} {'frames/s':>10} {'reference':>10} {'speed-up':>9}{extra}")
    for batch, fps in results["predict"].items():
        ref = results["reference"][batch]
        if args.baseline:
            base = results["default"][batch]
            extra = f" {base:>10.1f} {fps / base:>9.2f}x"
        print(f"{batch:>6} {fps:>10.1f} {ref:>10.1f} {fps / ref:>8.2f}x{extra}")


if __name__ == "__main__":
    main()
