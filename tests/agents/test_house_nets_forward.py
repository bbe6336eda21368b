"""The house networks' forward passes skip the submodule calls (issue 43): they must give the
very numbers, and gradients, of calling the layers as modules."""

import numpy as np
import torch

from objsearch_agents.core.nets import seeded_init
from objsearch_agents.house.nets import ActorCritic, CandidateQ, CategoryQ, TwoStream
from objsearch_agents.house.tables import NUM_CATEGORIES


def body_by_modules(body: TwoStream, mask, depth, extra=None):
    parts = [torch.relu(body.mask(mask.flatten(1))), torch.relu(body.depth(depth.flatten(1)))]
    if extra is not None:
        parts.append(extra)
    return torch.relu(body.embed(torch.cat(parts, dim=1)))


def inputs(n: int, seed: int):
    g = torch.Generator().manual_seed(seed)
    return torch.rand(n, 4, 10, 10, generator=g), torch.rand(n, 4, 10, 10, generator=g)


def same_with_grads(net, fast, slow) -> None:
    """Equal outputs, and equal gradients of every parameter for a loss on them."""
    grads = []
    for fn in (fast, slow):
        net.zero_grad(set_to_none=True)
        out = fn()
        outs = out if isinstance(out, tuple) else (out,)
        sum((o * (i + 1.5)).square().mean() for i, o in enumerate(outs)).backward()
        grads.append(([o.detach().clone() for o in outs], [p.grad.clone() for p in net.parameters()]))
    (out_a, grad_a), (out_b, grad_b) = grads
    assert all(torch.equal(a, b) for a, b in zip(out_a, out_b))
    assert all(torch.equal(a, b) for a, b in zip(grad_a, grad_b))


def test_actor_critic_and_candidate_q_match_their_modules():
    torch.set_num_threads(1)
    for n in (1, 32, 320):
        mask, depth = inputs(n, n)
        ac = seeded_init(ActorCritic, 3)

        def actor_critic_by_modules():
            h = body_by_modules(ac.body, mask, depth)
            return ac.policy(h), ac.value(h)[:, 0]

        same_with_grads(ac, lambda: ac(mask, depth), actor_critic_by_modules)
        cq = seeded_init(CandidateQ, 4)
        same_with_grads(cq, lambda: cq(mask, depth), lambda: cq.out(body_by_modules(cq.body, mask, depth))[:, 0])


def test_category_q_matches_its_modules():
    torch.set_num_threads(1)
    rng = np.random.default_rng(0)
    n, m = 64, 7
    net = seeded_init(CategoryQ, 5, NUM_CATEGORIES, 6)
    cats = torch.from_numpy(rng.integers(NUM_CATEGORIES, size=(n, 4, m)))
    masks = torch.from_numpy(rng.random((n, 4, m, 10, 10), dtype=np.float32))
    _, depth = inputs(n, 9)
    target = torch.eye(NUM_CATEGORIES)[torch.from_numpy(rng.integers(NUM_CATEGORIES, size=n))]

    def slow():
        w = net.pixel.weight[0][cats]
        seg = (masks * w[..., None, None]).sum(dim=2) + net.pixel.bias
        return net.out(body_by_modules(net.body, seg, depth, target))

    same_with_grads(net, lambda: net(cats, masks, depth, target), slow)
