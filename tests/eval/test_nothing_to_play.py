"""An evaluation with nothing to play is refused, naming the suite and the fix: a suite whose
``splits`` is empty, or chosen splits without episodes, never returns results with no
episodes (which read as a finished run)."""

import pytest

import objsearch
from objsearch.cli import eval_main
from objsearch.errors import UserError
from objsearch.eval.runner import EvalConfig, evaluate
from objsearch.eval.suites import REGISTERED, SUITES, check_splits, make_suite
from objsearch.eval.suites.gridworld import GridWorldSuite
from objsearch_agents.baselines.random_agent import RandomAgent


class NoSplits(GridWorldSuite):
    """The grid world with no splits at all."""

    def __init__(self, name="no-splits-42", maps=None, tasks=None, max_steps=100):
        super().__init__(name, maps, tasks, max_steps)
        self.splits = ()


class EmptyUnseen(GridWorldSuite):
    """The grid world whose split ``unseen-goals`` holds no episodes."""

    def __init__(self, name="empty-unseen-42", maps=None, tasks=None, max_steps=100):
        super().__init__(name, maps, tasks, max_steps)

    def episodes(self, split):
        return [] if split == "unseen-goals" else super().episodes(split)


class AllEmpty(GridWorldSuite):
    """The grid world whose splits all hold no episodes."""

    def __init__(self, name="all-empty-42", maps=None, tasks=None, max_steps=100):
        super().__init__(name, maps, tasks, max_steps)

    def episodes(self, split):
        return []


@pytest.fixture
def registered():
    names = {"no-splits-42": NoSplits, "empty-unseen-42": EmptyUnseen, "all-empty-42": AllEmpty}
    for name, cls in names.items():
        objsearch.register_suite(name, cls)
    yield names
    for name in names:
        SUITES.pop(name, None)
        REGISTERED.pop(name, None)


def test_a_registered_suite_with_no_splits_is_refused_naming_it(registered, tmp_path):
    out = tmp_path / "r.json"
    with pytest.raises(UserError, match=r"suite 'no-splits-42' has no splits .*nothing to play.*docs/add_a_suite.md"):
        objsearch.evaluate(RandomAgent(), "no-splits-42", seeds=[1], out=out)
    with pytest.raises(UserError, match="suite 'no-splits-42' has no splits"):
        evaluate(EvalConfig(agent="random", suite="no-splits-42", seeds=(1,)), progress=False)
    assert not out.exists() and not (tmp_path / "r.json.partial.jsonl").exists()


def test_splits_without_episodes_are_refused_naming_them_and_the_splits_that_have_some(registered):
    with pytest.raises(UserError) as err:
        objsearch.evaluate(RandomAgent(), "empty-unseen-42", seeds=[1], split="unseen-goals")
    message = str(err.value)
    assert "split 'unseen-goals' of suite 'empty-unseen-42' holds no episodes: nothing to play" in message
    assert "choose splits that have episodes (seen-goals, all-goals)" in message
    # all splits (the default) include the empty one: refused too, not a summary of nothing
    with pytest.raises(UserError, match="'unseen-goals' of suite 'empty-unseen-42' holds no episodes"):
        objsearch.evaluate(RandomAgent(), "empty-unseen-42", seeds=[1])
    # the splits that have episodes still play
    results = objsearch.evaluate(RandomAgent(), "empty-unseen-42", seeds=[1], split="seen-goals")
    assert list(results["splits"]) == ["seen-goals"] and results["episodes"]


def test_a_suite_whose_splits_all_lack_episodes_names_the_fix_in_the_suite(registered):
    with pytest.raises(
        UserError, match=r"splits 'seen-goals', 'unseen-goals', 'all-goals' of suite 'all-empty-42' hold"
    ):
        objsearch.evaluate("random", "all-empty-42", seeds=[1])
    with pytest.raises(UserError, match=r"at least one episode per split \(docs/add_a_suite.md\)"):
        objsearch.evaluate("random", "all-empty-42", seeds=[1])


def test_check_splits_refuses_a_suite_object_with_nothing_to_play():
    suite = make_suite("gridworld")
    assert check_splits(suite, None) == list(suite.splits)
    suite.splits = []
    with pytest.raises(UserError, match=r"suite 'gridworld' has no splits \(its splits is \[\]\)"):
        check_splits(suite, None)
    suite.splits = None
    with pytest.raises(UserError, match="suite 'gridworld' has no splits"):
        check_splits(suite, ["seen-goals"])


def test_the_command_line_exits_2_with_one_line(registered, capsys):
    assert eval_main(["--agent", "random", "--suite", "no-splits-42", "--seeds", "1", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("objsearch-eval: error: suite 'no-splits-42' has no splits")
    assert eval_main(["--agent", "random", "--suite", "empty-unseen-42", "--seeds", "1", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds no episodes" in err[0]
