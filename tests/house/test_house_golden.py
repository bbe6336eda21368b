"""Golden specs: the frozen generator house-gen-1 (objsearch/house/gen1) still reproduces seeds 0
and 1 exactly.

A generator version is frozen: a change that would alter these is a new generator package
(objsearch/house/generators.py), not an edit of gen1; `python tests/house/make_golden.py`
rewrites the golden specs.
"""

import importlib.util
from pathlib import Path

import pytest

from objsearch.house.gen1 import VERSION
from objsearch.house.generate import generate_house

_spec = importlib.util.spec_from_file_location("make_golden", Path(__file__).parent / "make_golden.py")
make_golden = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_golden)


@pytest.mark.parametrize("seed", make_golden.GOLDEN_SEEDS)
def test_golden_spec(seed):
    expected = make_golden.golden_path(seed).read_text()
    actual = generate_house(seed, generator="house-gen-1").spec.to_json_text()
    assert f'"generator_version": "{VERSION}"' in expected, "version bumped: regenerate the golden specs"
    assert actual == expected, (
        "house-gen-1 output changed: it is frozen; make the change a new generator package (objsearch/house/generators.py)"
    )
