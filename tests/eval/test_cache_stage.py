"""Caches an evaluation needs are built as a stage of their own, before the first episode,
so that the episodes' progress and ETA never count the minutes of rendering."""

from own_houses import run

from objsearch.eval.suites import make_suite


def test_missing_caches_are_built_before_the_episodes_progress_starts(made, tmp_path):
    caches = tmp_path / "fresh-cache"  # nothing built yet
    suite = make_suite(str(made / "my-suite.json"), cache_dir=str(caches))
    houses = {ep.task.house for ep in suite.episodes("my-suite")[:2]}
    assert sorted(suite.missing_caches(houses)) == sorted(houses)
    args = ["--agent", "random", "--suite", "my-suite.json", "--seeds", "1", "--episodes", "2", "--max-steps", "3"]
    out = run("objsearch-eval", *args, "--cache-dir", str(caches), cwd=made)
    assert out.returncode == 0, out.stderr
    lines = out.stderr.splitlines()  # stderr is no terminal: one line per status
    building = next(i for i, line in enumerate(lines) if line.startswith("building the observation caches of"))
    built = next(i for i, line in enumerate(lines) if line.startswith("built "))
    episodes = [i for i, line in enumerate(lines) if line.startswith("random on my-suite.json: ")]
    assert episodes and building < built < episodes[0], lines  # the episode ETA starts after the build
    assert suite.missing_caches(houses) == []
    again = run("objsearch-eval", *args, "--cache-dir", str(caches), cwd=made)
    assert again.returncode == 0 and "building the observation caches" not in again.stderr, again.stderr
    live = make_suite(str(made / "my-suite.json"), cache_dir=str(tmp_path / "other"), mode="live")
    assert live.missing_caches(houses) == []  # live rendering needs none
