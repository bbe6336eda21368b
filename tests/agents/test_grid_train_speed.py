"""The grid-world training loop's speed changes (issue 16) compute the same numbers as the
formulations they replaced: the trunk's memory-format order, the candidate inputs built
only for the scored pairs, and RMSProp's foreach form."""

import numpy as np
import torch
from torch import nn

from objsearch_agents.core.nets import seeded_init
from objsearch_agents.gridworld.nets import grg_high_net, low_level_net
from objsearch_agents.gridworld.policy import candidate_inputs, candidates


def old_trunk_forward(trunk, x):
    """The trunk as it was: ReLU in NCHW, then channels-last for the pool."""
    conv1, relu1, conv50, relu50, pool1, conv100, relu100, pool2, flatten = trunk.layers
    h = relu50(conv50(relu1(conv1(x))))
    h = pool1(h.contiguous(memory_format=torch.channels_last))
    return flatten(pool2(relu100(conv100(h))))


def test_trunk_values_and_gradients_are_unchanged():
    torch.set_num_threads(1)
    x = (torch.rand(64, 2, 7, 7, generator=torch.Generator().manual_seed(0)) < 0.3).float()
    net = seeded_init(low_level_net, 0)
    results = []
    for forward in (lambda: net(x), lambda: net.head(old_trunk_forward(net.trunk, x))):
        net.zero_grad()
        out = forward()
        (out**2).sum().backward()
        results.append((out.detach().clone(), [p.grad.clone() for p in net.parameters()]))
    (new_out, new_grads), (old_out, old_grads) = results
    assert torch.equal(new_out, old_out)
    assert all(torch.equal(a, b) for a, b in zip(new_grads, old_grads))


def test_trunk_values_are_unchanged_at_acting_batch_sizes():
    """Evaluation acts on batches of 1 to a few hundred: the forward pass must not change
    there either, or a shipped checkpoint would evaluate differently."""
    torch.set_num_threads(1)
    net = seeded_init(low_level_net, 1)
    gen = torch.Generator().manual_seed(2)
    with torch.no_grad():
        for n in [*range(1, 17), 33, 64, 340]:
            for _ in range(3):
                x = (torch.rand(n, 2, 7, 7, generator=gen) < 0.3).float() * torch.rand(n, 2, 1, 1, generator=gen)
                assert torch.equal(net(x), net.head(old_trunk_forward(net.trunk, x))), n


def dense_candidate_inputs(images, weights):
    """Every node of every image, as the policy built them before (then indexed)."""
    n, channels = len(images), images.shape[1]
    out = np.empty((n, channels, 2, *images.shape[2:]), dtype=np.float32)
    out[:, :, 0] = images[:, None, 0]
    out[:, :-1, 1] = images[:, 1:] * weights[:, :-1, None, None]
    out[:, -1, 1] = weights[:, -1, None, None]
    return out


def test_candidate_inputs_of_pairs_match_the_dense_inputs():
    rng = np.random.default_rng(0)
    images = (rng.random((32, 17, 7, 7)) < 0.05).astype(np.uint8)
    weights = rng.random((32, 17))
    rows, nodes = np.nonzero(candidates(images))
    assert (nodes == 16).sum() == 32 and (nodes < 16).any()  # "random" and real goals both occur
    pairs = candidate_inputs(images, weights, rows, nodes)
    assert pairs.dtype == np.float32
    np.testing.assert_array_equal(pairs, dense_candidate_inputs(images, weights)[rows, nodes])


def test_foreach_rmsprop_matches_the_per_tensor_loop():
    torch.set_num_threads(1)
    x = torch.rand(16, 2, 7, 7, generator=torch.Generator().manual_seed(1))
    params = []
    for foreach in (False, True):
        net = seeded_init(grg_high_net, 0)
        opt = torch.optim.RMSprop(net.parameters(), lr=1e-3, alpha=0.9, eps=1e-5, foreach=foreach)
        for _ in range(5):
            opt.zero_grad(set_to_none=True)
            (net(x) ** 2).mean().backward()
            nn.utils.clip_grad_norm_(net.parameters(), 40.0)
            opt.step()
        params.append([p.detach().clone() for p in net.parameters()])
    assert not torch.equal(params[0][0], seeded_init(grg_high_net, 0).trunk.layers[0].weight)  # it did learn
    assert all(torch.equal(a, b) for a, b in zip(*params))
