"""Golden specs: the generator still reproduces seeds 0 and 1 exactly.

If this fails after an intended change of the generator, bump HOUSE_GENERATOR_VERSION in
objsearch/house/generate.py and run `python tests/house/make_golden.py`.
"""

import importlib.util
from pathlib import Path

import pytest

from objsearch.house.generate import HOUSE_GENERATOR_VERSION, generate_house

_spec = importlib.util.spec_from_file_location("make_golden", Path(__file__).parent / "make_golden.py")
make_golden = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_golden)


@pytest.mark.parametrize("seed", make_golden.GOLDEN_SEEDS)
def test_golden_spec(seed):
    expected = make_golden.golden_path(seed).read_text()
    actual = generate_house(seed, generator="house-gen-1").spec.to_json_text()
    assert f'"generator_version": "{HOUSE_GENERATOR_VERSION}"' in expected, (
        "version bumped: regenerate the golden specs"
    )
    assert actual == expected, (
        "generator output changed: if intended, bump HOUSE_GENERATOR_VERSION and run tests/house/make_golden.py"
    )
