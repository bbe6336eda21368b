"""The rules a ``house-gen-3`` house must hold: ``house-gen-2``'s (``gen2.rules``) with this
version's area limits, and ``targets``: at most ``MAX_TARGET_INSTANCES`` objects of each small
target category."""

from __future__ import annotations

from collections import Counter

from objsearch.house.gen2.rules import rule_problems
from objsearch.house.gen3.build import AREA_LIMITS, MAX_TARGET_INSTANCES, SMALL_TARGETS
from objsearch.house.spec import HouseSpec


def check_rules(spec: HouseSpec) -> list[str]:
    """Every problem of every rule, as one list (``validate_house`` appends it for ``house-gen-3``)."""
    problems = [f"{rule}: {msg}" for rule, msgs in rule_problems(spec, AREA_LIMITS).items() for msg in msgs]
    counts = Counter(o.category for o in spec.objects if o.category in SMALL_TARGETS)
    return problems + [
        f"targets: {n} {cat} objects, more than {MAX_TARGET_INSTANCES}"
        for cat, n in sorted(counts.items())
        if n > MAX_TARGET_INSTANCES
    ]
