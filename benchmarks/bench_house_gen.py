"""Time per house: spec + MJCF + compile + validation (what `objsearch generate` does, minus files).

    python benchmarks/bench_house_gen.py [--seeds 50] [--rooms small|medium|large] [--generator house-gen-2]

Prints the median, mean and 90th percentile seconds per house, the mean number of
attempts (bounded resampling) and the time of one successful attempt split by stage. With
``--generator house-gen-2`` it also counts, per rule of ``objsearch.house.gen2.rules``, the
houses that hold it (every generated house must: ``generate_house`` validates them) and the
houses with a corridor, an L-shaped room, an open-plan opening and an en-suite bathroom;
``--seeds 500`` is the issue's 500-seed sweep of every stage.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections import Counter

import numpy as np

from objsearch.house.generate import HouseGenerationError, generate_house, spec_builder
from objsearch.house.generators import GENERATORS
from objsearch.house.mjcf import build_mjspec
from objsearch.house.validate import validate_house


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--rooms", choices=("small", "medium", "large"))
    parser.add_argument("--generator", choices=GENERATORS, default="house-gen-1")
    args = parser.parse_args()
    build = spec_builder(args.generator)
    generate_house(10_000, generator=args.generator)  # warm-up: imports, mesh cache
    times, attempts, objects, failed = [], [], [], []
    stages = {"spec": [], "mjcf": [], "compile": [], "validate": []}
    rules, shapes = Counter(), Counter()
    for seed in range(args.seeds):
        t = time.perf_counter()
        try:
            house = generate_house(seed, args.rooms, generator=args.generator)
        except HouseGenerationError as err:
            failed.append(str(err).splitlines()[0])
            continue
        times.append(time.perf_counter() - t)
        attempts.append(house.spec.attempt + 1)
        objects.append(len(house.spec.objects))
        # stage split of the successful attempt
        t0 = time.perf_counter()
        spec = build(seed, house.spec.size_class, "train", house.spec.attempt)
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
        if args.generator == "house-gen-2":
            from objsearch.house.gen2.rules import rule_problems

            for rule, problems in rule_problems(spec).items():
                rules[rule] += not problems
            types = [r.type for r in spec.rooms]
            shapes["corridor"] += "hallway" in types
            shapes["L-shaped room"] += any(len(r.polygon) > 4 for r in spec.rooms)
            shapes["open plan"] += any(d.width > 1.5 for d in spec.doors)
            shapes["en-suite"] += any(
                spec.room(d.rooms[0] + d.rooms[1] - r.id).type == "bedroom"
                for r in spec.rooms
                if r.type == "bathroom"
                for d in spec.doors
                if r.id in d.rooms
            )
    print(
        f"generator {args.generator}, houses: {len(times)} of {args.seeds} (rooms: {args.rooms or 'per seed'}), "
        f"objects/house: mean {np.mean(objects):.0f}, max {max(objects)}"
    )
    print(
        f"seconds per house: median {statistics.median(times):.3f}, mean {np.mean(times):.3f}, p90 {np.percentile(times, 90):.3f}, max {max(times):.3f}"
    )
    print(f"attempts per house: mean {np.mean(attempts):.2f}, max {max(attempts)}")
    print("one attempt, median seconds: " + ", ".join(f"{k} {statistics.median(v):.3f}" for k, v in stages.items()))
    if rules:
        print("rules held (houses): " + ", ".join(f"{k} {v}/{len(times)}" for k, v in rules.items()))
        print("houses with: " + ", ".join(f"{k} {v}" for k, v in shapes.items()))
    for line in failed:
        print("FAILED", line)


if __name__ == "__main__":
    main()
