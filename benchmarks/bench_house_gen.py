"""Time per house: spec + MJCF + compile + validation (what `objsearch generate` does, minus files).

    python benchmarks/bench_house_gen.py [--seeds 50] [--rooms small|medium|large]

Prints the median, mean and 90th percentile seconds per house, the mean number of
attempts (bounded resampling) and the time of one successful attempt split by stage.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from objsearch.house.generate import build_spec, generate_house
from objsearch.house.mjcf import build_mjspec
from objsearch.house.validate import validate_house


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--rooms", choices=("small", "medium", "large"))
    args = parser.parse_args()
    generate_house(10_000)  # warm-up: imports, mesh cache
    times, attempts, objects = [], [], []
    stages = {"spec": [], "mjcf": [], "compile": [], "validate": []}
    for seed in range(args.seeds):
        t = time.perf_counter()
        house = generate_house(seed, args.rooms)
        times.append(time.perf_counter() - t)
        attempts.append(house.spec.attempt + 1)
        objects.append(len(house.spec.objects))
        # stage split of the successful attempt
        t0 = time.perf_counter()
        spec = build_spec(seed, house.spec.size_class, "train", house.spec.attempt)
        t1 = time.perf_counter()
        s = build_mjspec(spec)
        t2 = time.perf_counter()
        model = s.compile()
        s.to_xml()
        t3 = time.perf_counter()
        validate_house(spec, model)
        t4 = time.perf_counter()
        for k, v in zip(stages, (t1 - t0, t2 - t1, t3 - t2, t4 - t3)):
            stages[k].append(v)
    print(
        f"houses: {args.seeds} (rooms: {args.rooms or 'per seed'}), objects/house: mean {np.mean(objects):.0f}, max {max(objects)}"
    )
    print(
        f"seconds per house: median {statistics.median(times):.3f}, mean {np.mean(times):.3f}, p90 {np.percentile(times, 90):.3f}, max {max(times):.3f}"
    )
    print(f"attempts per house: mean {np.mean(attempts):.2f}, max {max(attempts)}")
    print("one attempt, median seconds: " + ", ".join(f"{k} {statistics.median(v):.3f}" for k, v in stages.items()))


if __name__ == "__main__":
    main()
