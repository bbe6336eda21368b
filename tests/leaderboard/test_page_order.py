"""index.html opens on the default suite: the page's data lists it first."""

import json

from objsearch.eval.suites import DEFAULT_SUITE
from objsearch.leaderboard.render import DATA_PLACEHOLDER, page_template, render_html


def test_the_default_suite_comes_first_then_the_registry_order_then_suite_files():
    row = {"name": "oracle", "sr": 1.0, "spl": 1.0}
    tables = {suite: {"test": [row]} for suite in ("a-file.json", "gridworld", "house-multi", DEFAULT_SUITE)}
    before, after = page_template().split(DATA_PLACEHOLDER)
    data = json.loads(render_html(tables)[len(before) : -len(after)])
    assert list(data["tables"]) == [DEFAULT_SUITE, "gridworld", "house-multi", "a-file.json"]
    assert data["default_suite"] == DEFAULT_SUITE == "house-single"
