"""The Goals Relational Graph: posterior, weights, planning, termination, counting, files."""

import itertools

import numpy as np
import pytest

from objsearch_agents.core.grg import NOT_SEEN, GoalsRelationalGraph, max_product_plans, plan_termination


def test_prior_alone_gives_zero_weights_and_unit_diagonal():
    g = GoalsRelationalGraph(5, max_option_steps=10)
    post = g.posterior_mean()
    assert post.shape == (5, 5, 11)
    np.testing.assert_allclose(post[..., -1], 1.0)  # all mass on "not seen"
    np.testing.assert_allclose(g.edge_weights(), np.eye(5))


def test_posterior_mean_is_prior_plus_counts_normalised():
    g = GoalsRelationalGraph(3, max_option_steps=4, gamma=0.5)
    g.add_counts(0, 1, 0, 2)  # seen after 1 step twice
    g.add_counts(0, 1, 2, 1)  # seen after 3 steps once
    # prior (0,0,0,0,1) + counts (2,0,1,0,0) -> (2,0,1,0,1) / 4
    np.testing.assert_allclose(g.posterior_mean()[0, 1], [0.5, 0, 0.25, 0, 0.25])
    # w = 0.5 * 0.5^0 + 0.25 * 0.5^2
    assert g.edge_weights()[0, 1] == pytest.approx(0.5 + 0.25 * 0.25)
    assert g.edge_weights()[1, 0] == 0.0


def test_edge_weight_formula_against_hand_sum():
    rng = np.random.default_rng(0)
    g = GoalsRelationalGraph(4, max_option_steps=10, gamma=0.99)
    g.counts[...] = rng.integers(0, 5, size=g.counts.shape)
    w = g.edge_weights()
    for i, j in itertools.product(range(4), range(4)):
        if i == j:
            assert w[i, j] == 1.0
            continue
        a = g.prior + g.counts[i, j]
        p = a / a.sum()
        assert w[i, j] == pytest.approx(sum(p[k - 1] * 0.99 ** (k - 1) for k in range(1, 11)))


def test_counting_first_seen_and_not_seen():
    g = GoalsRelationalGraph(4, max_option_steps=10, observable=3)
    g.record_option(1, [3, NOT_SEEN, 1])
    g.record_options([1, 3], [[3, 2, NOT_SEEN], [NOT_SEEN, NOT_SEEN, 10]])
    assert g.counts[1, 0, 2] == 2  # node 0 first seen after 3 steps, twice
    assert g.counts[1, 1, 10] == 1 and g.counts[1, 1, 1] == 1
    assert g.counts[1, 2, 0] == 1 and g.counts[1, 2, 10] == 1
    assert g.counts[3, 2, 9] == 1 and g.counts[3, 0, 10] == 1
    assert g.counts[:, 3].sum() == 0  # the unobservable node is never counted
    assert g.counts.sum() == 9
    with pytest.raises(ValueError):
        g.record_option(0, [11, 0, 0])


def _brute_force(w, target):
    n = len(w)
    best = np.zeros(n)
    for i in range(n):
        if i == target:
            best[i] = 1.0
            continue
        others = [k for k in range(n) if k not in (i, target)]
        for r in range(len(others) + 1):
            for mid in itertools.permutations(others, r):
                path = (i, *mid, target)
                best[i] = max(best[i], np.prod([w[a, b] for a, b in zip(path, path[1:])]))
    return best


@pytest.mark.parametrize("seed", range(12))
def test_planning_equals_brute_force_max_product(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 7))
    w = rng.random((n, n)) * (rng.random((n, n)) < 0.6)  # sparse, with zero edges
    np.fill_diagonal(w, 1.0)
    plans = max_product_plans(w)
    for t in range(n):
        expected = _brute_force(w, t)
        np.testing.assert_allclose(plans.values[t], expected, rtol=1e-12, atol=1e-15)
        for i in range(n):
            path = plans.path(i, t)
            if expected[i] > 0:
                assert path[0] == i and path[-1] == t and len(set(path)) == len(path)
                assert np.prod([w[a, b] for a, b in zip(path, path[1:])]) == pytest.approx(expected[i])
            else:
                assert path == [i]
        succ = plans.successors()[t]
        for i in range(n):
            assert set(np.flatnonzero(succ[i])) == set(plans.path(i, t)[1:])


def test_plan_prefers_stronger_two_hop_path():
    w = np.eye(3)
    w[0, 2] = 0.3
    w[0, 1], w[1, 2] = 0.9, 0.8
    plans = max_product_plans(w)
    assert plans.path(0, 2) == [0, 1, 2] and plans.values[2, 0] == pytest.approx(0.72)


def test_termination_rule():
    plan = [4, 2, 7]  # chasing 4, final goal 7
    assert plan_termination(plan, {2})
    assert plan_termination(plan, {7})
    assert not plan_termination(plan, {4, 5})
    visible = np.zeros(8, dtype=bool)
    assert not plan_termination(plan, visible)
    visible[7] = True
    assert plan_termination(plan, visible)
    assert not plan_termination([7], visible)  # chasing the final goal itself


def test_save_load_round_trip(tmp_path):
    g = GoalsRelationalGraph(17, observable=16)
    rng = np.random.default_rng(3)
    g.record_options(rng.integers(0, 17, 50), rng.integers(0, 11, (50, 16)))
    g.save(tmp_path / "grg.npz")
    h = GoalsRelationalGraph.load(tmp_path / "grg.npz")
    np.testing.assert_array_equal(h.counts, g.counts)
    np.testing.assert_allclose(h.edge_weights(), g.edge_weights())
    assert h.observable == 16 and h.gamma == g.gamma
