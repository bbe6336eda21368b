from collections import deque

import numpy as np

from objsearch.house.occupancy import occupancy_grid
from objsearch.sim.navgraph import GRID, NUM_MOVE_ACTIONS, STOP


def forward_bfs(graph, start, goals):
    """Brute force: plain BFS forward from one start over the transition table."""
    goals = set(goals)
    seen, queue = {start: 0}, deque([start])
    while queue:
        pose = queue.popleft()
        if pose in goals:
            return seen[pose]
        for action in range(NUM_MOVE_ACTIONS):
            nxt = int(graph.next_pose[pose, action])
            if nxt not in seen:
                seen[nxt] = seen[pose] + 1
                queue.append(nxt)
    return -1


def test_shortest_steps_match_brute_force(small_world):
    graph = small_world.graph
    rng = np.random.default_rng(0)
    goals = rng.choice(graph.num_poses, size=5, replace=False)
    dist = graph.shortest_steps(goals)
    for start in rng.choice(graph.num_poses, size=40, replace=False):
        assert dist[start] == forward_bfs(graph, int(start), goals.tolist())


def test_shortest_path_follows_the_graph(small_world):
    graph = small_world.graph
    goals = [10, 11]
    dist = graph.shortest_steps(goals)
    start = int(np.argmax(dist))
    path = graph.shortest_path(start, goals)
    assert len(path) == dist[start] > 0
    pose = start
    for action in path:
        pose = int(graph.next_pose[pose, action])
    assert pose in goals


def test_rotations_and_moves_are_consistent(small_world):
    graph = small_world.graph
    n = graph.next_pose
    poses = np.arange(graph.num_poses)
    assert (n[n[poses, 1], 2] == poses).all(), "rotate left then right returns"
    assert (n[poses, 1] // 4 == poses // 4).all(), "rotation keeps the cell"
    assert (n[poses, STOP] == poses).all()
    moved = n[poses, 0] != poses
    assert (n[n[poses, 0], 3][moved] == poses[moved]).all(), "ahead then back returns"
    assert ((n[poses, 0] % 4) == poses % 4).all(), "moves keep the heading"
    # a move changes the cell by exactly one grid step
    a, b = graph.cells[poses[moved] // 4], graph.cells[n[poses, 0][moved] // 4]
    assert (np.abs(a - b).sum(axis=1) == 1).all()


def test_free_cells_keep_the_agent_clear_of_obstacles(small_world):
    graph = small_world.graph
    fine = occupancy_grid(small_world.spec, 0.05)
    xy = graph.world_poses(np.arange(0, graph.num_poses, 4))[:, :2]
    assert all(fine.is_free(x, y) for x, y in xy)
    # and every room is represented: the graph is one connected component
    assert (graph.shortest_steps([0]) >= 0).all()


def test_geodesic_distance_is_at_least_the_straight_line(small_world):
    graph = small_world.graph
    rng = np.random.default_rng(1)
    for start, goal in rng.choice(graph.num_poses, size=(10, 2)):
        d = graph.geodesic_distance(int(start), [int(goal)])
        (x0, y0, _), (x1, y1, _) = graph.world_poses([start, goal])
        assert d >= np.hypot(x1 - x0, y1 - y0) - 1e-9
        assert d % GRID == 0 or np.isclose(d % GRID, GRID) or np.isclose(d % GRID, 0)
