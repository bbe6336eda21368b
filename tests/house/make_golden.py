"""Regenerate the golden specs of house-gen-1 (objsearch/house/gen1, frozen: run only if its
version's output was meant to change):

    python tests/house/make_golden.py
"""

from pathlib import Path

from objsearch.fileio import atomic_write
from objsearch.house.generate import generate_house

GOLDEN_SEEDS = (0, 1)
GOLDEN_DIR = Path(__file__).parent / "golden"


def golden_path(seed: int) -> Path:
    return GOLDEN_DIR / f"spec_{seed:06d}.json"


if __name__ == "__main__":
    for seed in GOLDEN_SEEDS:
        with atomic_write(golden_path(seed)) as f:
            f.write(generate_house(seed, generator="house-gen-1").spec.to_json_text())
        print(f"wrote {golden_path(seed)}")
