"""Perception network inference throughput on the CPU: frames per second at several batch sizes.

    python benchmarks/bench_perception.py [--threads 1] [--size 64] [--batches 1,16,64] [--json]

The default ``SegDepthNet`` (``objsearch.perception.model.ModelConfig()``), random
weights (speed does not depend on them), uint8 RGB in, what ``Predictor.predict`` returns
out (argmax category ids and depth in metres, as numpy arrays): the cost of filling a
predicted observation cache, or of predicted observations in live mode. Each figure is
the median of ``--repeats`` timed runs of at least ``--seconds`` after a warm-up.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np
import torch

from objsearch.perception.inference import Predictor
from objsearch.perception.model import ModelConfig, SegDepthNet, count_parameters
from objsearch.perception.train import init_weights
from objsearch.sim.camera import RenderSettings


def frames_per_second(predictor: Predictor, rgb: np.ndarray, seconds: float) -> float:
    predictor.predict(rgb)  # warm-up
    n, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        predictor.predict(rgb)
        n += len(rgb)
    return n / (time.perf_counter() - t0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (default: 1)")
    parser.add_argument("--size", type=int, default=64, help="frame width and height (default: 64)")
    parser.add_argument("--batches", default="1,16,64", help="batch sizes (default: 1,16,64)")
    parser.add_argument("--seconds", type=float, default=3.0, help="minimum time per timed run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per batch size; the median is reported")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    model = SegDepthNet(ModelConfig())
    init_weights(model, torch.Generator().manual_seed(0))
    predictor = Predictor(model, RenderSettings(width=args.size, height=args.size), key="bench", device="cpu")
    rng = np.random.default_rng(0)
    results = {}
    for batch in (int(b) for b in args.batches.split(",")):
        rgb = rng.integers(0, 256, (batch, args.size, args.size, 3), dtype=np.uint8)
        results[batch] = statistics.median(frames_per_second(predictor, rgb, args.seconds) for _ in range(args.repeats))
    info = {
        "threads": args.threads,
        "size": args.size,
        "parameters": count_parameters(model),
        "torch": torch.__version__,
        "frames_per_second": {str(b): round(v, 1) for b, v in results.items()},
    }
    if args.json:
        print(json.dumps(info))
        return
    print(
        f"SegDepthNet {info['parameters']:,} parameters, {args.size}x{args.size}, {args.threads} thread(s), torch {torch.__version__}"
    )
    print(f"{'batch':>6} {'frames/s':>10}")
    for batch, fps in results.items():
        print(f"{batch:>6} {fps:>10.1f}")


if __name__ == "__main__":
    main()
