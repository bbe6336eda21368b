"""CPU cost of one grid-world gradient update, and the training speed it caps (issue 16).

One Double-DQN update of the real learner (``gridworld.world.flat_loss`` and ``Learner.step``,
the low-level / DQN network, batch 64: three forward passes and one backward) in float32,
and the same update under ``torch.autocast("cpu", dtype=torch.bfloat16)``, interleaved,
one torch thread; and the convolutional trunk's forward and backward as oneDNN runs it
against the same trunk written as gathers and matrix products (``trunk_as_matmuls``). The
paper's protocol runs one such update per level per 10 transitions,
so 10 / (CPU seconds per update) is the most env steps per CPU second any loop can reach
on this machine with that arithmetic, however cheap acting and the env become.

    .venv/bin/python benchmarks/bench_grid_update.py [--updates 400] [--rounds 2] [--json]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import statistics
import time

import numpy as np
import torch
import torch.nn.functional as F

from objsearch_agents.core.double_dqn import Learner
from objsearch_agents.core.nets import seeded_init
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.gridworld.nets import low_level_net
from objsearch_agents.gridworld.world import flat_loss

UPDATES_PER_TRANSITION = 0.1  # the paper's: one update per level every 10 transitions


def batch(rng: np.random.Generator, size: int = 64) -> dict:
    """A replay batch of random 2-channel 7x7 windows (sparse obstacles and goals)."""

    def obs():
        return (rng.random((size, 2, 7, 7)) < 0.3).astype(np.float32)

    return {
        "obs": obs(),
        "next_obs": obs(),
        "action": rng.integers(0, 4, size),
        "reward": (rng.random(size) < 0.1).astype(np.float32),
        "done": (rng.random(size) < 0.1).astype(np.float32),
    }


def ms_per_update(learner: Learner, batches: list[dict], bf16: bool) -> float:
    """CPU milliseconds per update over ``batches`` (after 20 warm-up updates)."""
    ctx = (lambda: torch.autocast("cpu", dtype=torch.bfloat16)) if bf16 else contextlib.nullcontext
    for b in batches[:20]:
        with ctx():
            loss = flat_loss(learner, b)
        learner.step(loss.float())
    t = time.process_time()
    for b in batches:
        with ctx():
            loss = flat_loss(learner, b)
        learner.step(loss.float())
    return (time.process_time() - t) / len(batches) * 1e3


# 3x3 "same" patches of a 7x7 map padded to 9x9: (49 positions, 9 taps) flat indices
_PATCHES = torch.tensor([[(r + i) * 9 + c + j for i in range(3) for j in range(3)] for r in range(7) for c in range(7)])


def trunk_as_matmuls(trunk, x: torch.Tensor) -> torch.Tensor:
    """``trunk(x)`` (``nets.ConvTrunk`` on (N, C, 7, 7)) as gathers and matrix products."""
    c1, _, c50, _, _, c100, *_ = trunk.layers
    n = len(x)
    h = F.relu(torch.einsum("nchw,c->nhw", x, c1.weight[0, :, 0, 0]) + c1.bias[0])
    patches = F.pad(h, (1, 1, 1, 1)).reshape(n, 81)[:, _PATCHES]  # (n, 49, 9)
    y = F.relu(patches @ c50.weight.reshape(50, 9).t() + c50.bias).reshape(n, 7, 7, 50)
    y = F.pad(y, (0, 0, 0, 1, 0, 1), value=-1.0).reshape(n, 4, 2, 4, 2, 50).amax(dim=(2, 4))  # ceil pool
    p = y.unfold(1, 3, 1).unfold(2, 3, 1).reshape(n, 4, 450)  # (n, 2 x 2 positions, 50 x 3 x 3)
    return F.relu(p @ c100.weight.reshape(100, 450).t() + c100.bias).amax(dim=1)


def trunk_ms(forward, x: torch.Tensor, n: int) -> float:
    """CPU milliseconds of one forward and backward of ``forward`` on ``x``."""
    for _ in range(20):
        forward(x).sum().backward()
    t = time.process_time()
    for _ in range(n):
        forward(x).sum().backward()
    return (time.process_time() - t) / n * 1e3


def main() -> None:
    """Print (or ``--json``) the CPU ms per update and the steps/s cap of each precision."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--updates", type=int, default=400)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    torch.set_num_threads(1)
    rng = np.random.default_rng(0)
    batches = [batch(rng) for _ in range(args.updates)]
    learner = Learner(seeded_init(low_level_net, 0), GridAgentConfig())
    times = {"float32": [], "bfloat16": []}
    trunk, x = learner.online.trunk, torch.from_numpy(batches[0]["obs"])
    assert torch.allclose(trunk(x), trunk_as_matmuls(trunk, x), atol=1e-5)
    trunk_times = {"onednn": [], "matmuls": []}
    for _ in range(args.rounds):
        for name in times:
            times[name].append(ms_per_update(learner, batches, bf16=name == "bfloat16"))
        trunk_times["onednn"].append(trunk_ms(trunk, x, args.updates))
        trunk_times["matmuls"].append(trunk_ms(lambda v: trunk_as_matmuls(trunk, v), x, args.updates))
    result = {
        name: {
            "cpu_ms_per_update": round(statistics.median(t), 3),
            "max_env_steps_per_cpu_s": round(1e3 / statistics.median(t) / UPDATES_PER_TRANSITION),
        }
        for name, t in times.items()
    }
    for name, r in result.items():
        print(
            f"{name:<9} {r['cpu_ms_per_update']:7.2f} ms/update (CPU)   "
            f"cap at 1 update / 10 transitions: {r['max_env_steps_per_cpu_s']:,} env steps per CPU s"
        )
    result["trunk_forward_backward_cpu_ms"] = {k: round(statistics.median(v), 3) for k, v in trunk_times.items()}
    print("trunk forward + backward of 64 (CPU ms):", result["trunk_forward_backward_cpu_ms"])
    if args.json:
        print(json.dumps(result))


if __name__ == "__main__":
    main()
