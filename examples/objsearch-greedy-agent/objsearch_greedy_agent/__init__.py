"""An example out-of-tree agent for objsearch's grid world.

When the goal is inside the 7x7 window it steps towards it (along the larger offset first,
the other axis if that move is blocked); otherwise it moves at random. It needs no
training, uses only what the agent sees, and draws its randomness from ``task.rng``.
"""

import numpy as np

UP, DOWN, LEFT, RIGHT = range(4)


class GreedyVisibleAgent:
    @classmethod
    def worlds(cls):
        return ("gridworld",)  # the harness refuses house suites before the first episode

    def reset(self, task):
        self.rng = task.rng
        self.goal = task.goal

    def act(self, observation):
        image = observation["image"]  # (17, 7, 7): obstacles, then one channel per goal
        cells = np.argwhere(image[1 + self.goal])
        if len(cells) == 0:
            return int(self.rng.integers(4))
        dr, dc = cells[0] - 3  # offset of the goal from the agent at the window centre
        vertical = [DOWN if dr > 0 else UP] if dr else []
        horizontal = [RIGHT if dc > 0 else LEFT] if dc else []
        moves = vertical + horizontal if abs(dr) >= abs(dc) else horizontal + vertical
        step = {UP: (-1, 0), DOWN: (1, 0), LEFT: (0, -1), RIGHT: (0, 1)}
        for move in moves:
            r, c = 3 + step[move][0], 3 + step[move][1]
            if not image[0, r, c]:
                return move
        return int(self.rng.integers(4))
