"""index.html comes from the package's template file, with the data in its one placeholder."""

import json

from objsearch.leaderboard.render import DATA_PLACEHOLDER, page_template, render_html


def test_the_template_has_one_placeholder_and_the_page_is_the_template_around_the_data():
    template = page_template()
    assert template.startswith("<!DOCTYPE html>") and template.endswith("</html>\n")
    assert template.count(DATA_PLACEHOLDER) == 1
    tables = {"gridworld": {"unseen-goals": [{"name": "x</script><!--<script>&\u2028", "sr": 1.0, "spl": 1.0}]}}
    page = render_html(tables)
    before, after = template.split(DATA_PLACEHOLDER)
    assert page.startswith(before) and page.endswith(after)
    data = page[len(before) : len(page) - len(after)]
    assert not any(c in data for c in "<>&\u2028")  # a name cannot end the script or open a comment in it
    assert json.loads(data)["tables"] == tables
