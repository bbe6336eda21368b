import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.gridworld import dataset
from objsearch.gridworld.maps import (
    INTERIOR_OBSTACLES,
    MOVES,
    GridMap,
    bfs_distances,
    generate_map,
    load_map,
    load_map_dir,
    save_map,
    shortest_path_actions,
)


def all_shipped_maps():
    return list((dataset.train_maps() | dataset.test_maps()).values())


def check_paper_rules(m: GridMap):
    obs = m.obstacles
    assert obs.shape == (16, 16) and obs.dtype == np.uint8
    assert obs[0].all() and obs[-1].all() and obs[:, 0].all() and obs[:, -1].all(), "border must be obstacle"
    assert INTERIOR_OBSTACLES[0] <= obs[1:-1, 1:-1].sum() <= INTERIOR_OBSTACLES[1]
    assert m.goals.shape == (16, 2)
    assert len({tuple(g) for g in m.goals}) == 16, "goals on distinct cells"
    assert not obs[m.goals[:, 0], m.goals[:, 1]].any(), "goals on free cells"
    for i in range(16):
        if i in (0, 8):
            continue
        chebyshev = np.abs(m.goals[i] - m.goals[i - 1]).max()
        assert chebyshev in (2, 3), f"g{i} must be in the 7x7 window of g{i - 1}, not adjacent"
    dist = bfs_distances(obs, tuple(m.goals[0]))
    assert (dist[m.goals[:, 0], m.goals[:, 1]] >= 0).all(), "all goals mutually reachable"


def test_shipped_maps_follow_the_paper():
    maps = all_shipped_maps()
    assert len(maps) == 120
    for m in maps:
        check_paper_rules(m)
    density = np.mean([m.obstacles[1:-1, 1:-1].mean() for m in maps])
    assert 0.26 < density < 0.32  # the published maps: ~29% of the interior


def test_generator_follows_the_paper_for_fresh_seeds():
    for seed in range(30):
        check_paper_rules(generate_map(np.random.default_rng(seed)))


def test_generator_is_deterministic():
    a = generate_map(np.random.default_rng(7))
    b = generate_map(np.random.default_rng(7))
    assert np.array_equal(a.obstacles, b.obstacles) and np.array_equal(a.goals, b.goals)


def brute_force_distances(obstacles, source):
    # Bellman-Ford relaxation: an independent check of the BFS.
    h, w = obstacles.shape
    dist = np.full((h, w), 10**6)
    dist[source] = 0
    for _ in range(h * w):
        for r in range(h):
            for c in range(w):
                if obstacles[r, c]:
                    continue
                for dr, dc in MOVES:
                    nr, nc = r + dr, c + dc
                    if 0 <= nr < h and 0 <= nc < w and not obstacles[nr, nc]:
                        dist[r, c] = min(dist[r, c], dist[nr, nc] + 1)
    return np.where(dist >= 10**6, -1, dist)


def test_bfs_matches_brute_force_on_small_random_grids():
    rng = np.random.default_rng(0)
    for _ in range(5):
        obstacles = (rng.random((6, 7)) < 0.35).astype(np.uint8)
        obstacles[2, 3] = 0
        assert np.array_equal(bfs_distances(obstacles, (2, 3)), brute_force_distances(obstacles, (2, 3)))


def test_shortest_path_reaches_goal_in_minimal_steps():
    m = dataset.test_maps()["map_0100"]
    goal = tuple(m.goals[5])
    dist = bfs_distances(m.obstacles, goal)
    for start in map(tuple, np.argwhere(dist > 0)[:20]):
        path = shortest_path_actions(m.obstacles, start, goal)
        assert len(path) == dist[start]
        pos = np.array(start)
        for a in path:
            pos = pos + MOVES[a]
            assert not m.obstacles[tuple(pos)]
        assert tuple(pos) == goal


def test_save_load_round_trip(tmp_path):
    m = dataset.test_maps()["map_0101"]
    save_map(m, tmp_path)
    loaded = load_map_dir(tmp_path)["map_0101"]
    assert np.array_equal(loaded.obstacles, m.obstacles) and np.array_equal(loaded.goals, m.goals)
    assert not list(tmp_path.glob("*.tmp")), "no temp file left behind"


def test_corrupt_map_file_is_a_clear_error(tmp_path):
    (tmp_path / "map_0000.npz").write_bytes(b"not a zip file")
    with pytest.raises(UserError, match="map_0000.npz"):
        load_map(tmp_path / "map_0000.npz")


def test_map_file_missing_array_is_a_clear_error(tmp_path):
    np.savez(tmp_path / "map_0001.npz", obstacles=np.zeros((4, 4), np.uint8))
    with pytest.raises(UserError, match="goals"):
        load_map(tmp_path / "map_0001.npz")


def test_goal_on_obstacle_is_rejected(tmp_path):
    obstacles = np.zeros((4, 4), np.uint8)
    obstacles[1, 1] = 1
    np.savez(tmp_path / "map_0002.npz", obstacles=obstacles, goals=np.array([[1, 1]]))
    with pytest.raises(UserError, match="goal 0 .* obstacle"):
        load_map(tmp_path / "map_0002.npz")
