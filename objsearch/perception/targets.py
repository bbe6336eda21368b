"""The category ids perception is scored on and a dataset looks for: the house suites' targets
and the large-house tier's small targets (``objsearch.perception.dataset.frame_targets`` picks a
dataset suite's)."""

from __future__ import annotations


def target_categories() -> list[int]:
    """Category ids that the house suites house-single, house-multi and house-gen search for
    (the v1 suites, fixed, so that ``miou_targets`` keeps its meaning as suites are added)."""
    from objsearch.house.categories import CATEGORY_IDS
    from objsearch.sim.suites import load_suite_file

    names = set()
    for suite in ("house-single", "house-multi", "house-gen"):
        for group in load_suite_file(suite)["categories"].values():
            names.update(group)
    return sorted(CATEGORY_IDS[name] for name in names)


def small_target_categories() -> list[int]:
    """Category ids of the large-house tier's small targets (``house-gen-3``'s ``SMALL_TARGETS``:
    a cup, a remote, an alarm clock, ...), seen only from close by."""
    from objsearch.house.categories import CATEGORY_IDS
    from objsearch.house.gen3.build import SMALL_TARGETS

    return sorted(CATEGORY_IDS[name] for name in SMALL_TARGETS)
