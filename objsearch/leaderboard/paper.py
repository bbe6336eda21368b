"""The paper's published numbers (Ye et al., CVPR 2021), shown beside our rows for reference.

Grid world: Tables 1 and 2 (unseen maps); values are SR, AS, MS, SPL. House3D: Table 3
(SR and SPL only), beside our ``house-single`` and ``house-multi`` suites, which follow its
protocol in our own generated houses.
"""

GRIDWORLD_SPLITS = ("seen-goals", "unseen-goals", "all-goals")

_GRIDWORLD = {
    # method: (SR, AS, MS, SPL) for seen goals, unseen goals, all goals
    "Oracle": ((1.00, 11.81, 11.81, 1.00), (1.00, 11.28, 11.28, 1.00), (1.00, 10.38, 10.38, 1.00)),
    "Random": ((0.16, 42.15, 5.47, 0.03), (0.15, 42.38, 4.81, 0.04), (0.18, 36.62, 4.69, 0.05)),
    "DQN": ((0.20, 20.28, 5.47, 0.13), (0.20, 11.90, 4.10, 0.15), (0.32, 16.23, 5.71, 0.23)),
    "h-DQN": ((0.43, 20.25, 7.95, 0.28), (0.19, 26.09, 6.38, 0.08), (0.45, 20.84, 7.16, 0.26)),
    "HRL-GRG": ((0.57, 28.71, 9.03, 0.33), (0.70, 24.19, 8.73, 0.45), (0.74, 24.02, 8.65, 0.46)),
    "HRL-GRG -relation": ((0.26, 33.20, 6.16, 0.10), (0.35, 31.93, 6.84, 0.14), (0.40, 29.39, 6.14, 0.18)),
    "HRL-GRG -termination": ((0.55, 31.36, 8.81, 0.27), (0.58, 27.91, 8.11, 0.32), (0.64, 25.56, 7.88, 0.37)),
    "HRL-GRG -high-level": ((0.56, 29.97, 9.03, 0.31), (0.65, 23.63, 8.65, 0.42), (0.66, 22.86, 7.86, 0.41)),
}


# Our grid-world entries in the paper's Tables 1 (methods) and 2 (ablations), by submission name.
PAPER_NAMES = {
    "random": "Random",
    "oracle": "Oracle",
    "dqn": "DQN",
    "a3c": "A3C",
    "hdqn": "h-DQN",
    "hrl_grg": "HRL-GRG",
    "hdqn_explorer": "h-DQN + explorer (ours)",
    "hrl_grg_explorer": "HRL-GRG + explorer (ours)",
    "hrl_grg_no_relation": "HRL-GRG -relation",
    "hrl_grg_no_termination": "HRL-GRG -termination",
    "hrl_grg_no_high_level": "HRL-GRG -high-level",
    "frontier": "Frontier (not in the paper)",
    "scene_priors": "Scene Priors",
}
GRIDWORLD_TABLES = {
    "Table 1: methods": ("random", "oracle", "dqn", "hdqn", "hrl_grg"),
    "Table 2: ablations of HRL-GRG": (
        "hrl_grg",
        "hrl_grg_no_relation",
        "hrl_grg_no_termination",
        "hrl_grg_no_high_level",
    ),
}
GREEDY_SUFFIX = "_greedy"
"""A submission ``<name>_greedy`` is ``<name>`` evaluated with epsilon 0 (shown under it)."""


def paper_gridworld(name: str) -> dict[str, tuple] | None:
    """{split: (SR, AS, MS, SPL)} the paper reports for an entry of ``PAPER_NAMES``."""
    values = _GRIDWORLD.get(PAPER_NAMES.get(name, ""))
    return None if values is None else dict(zip(GRIDWORLD_SPLITS, values))


_HOUSE3D = {
    # method: (SR, SPL) for single env seen goals, unseen goals; multiple envs seen, unseen
    "Random": ((0.20, 0.05), (0.23, 0.04), (0.39, 0.03), (0.60, 0.05)),
    "DQN": ((0.58, 0.27), (0.18, 0.05), (0.42, 0.06), (0.39, 0.04)),
    "A3C": ((0.53, 0.18), (0.27, 0.09), (0.48, 0.03), (0.47, 0.03)),
    "h-DQN": ((0.77, 0.15), (0.05, 0.00), (0.43, 0.05), (0.28, 0.02)),
    "HRL-GRG": ((0.88, 0.33), (0.79, 0.21), (0.76, 0.20), (0.62, 0.10)),
}
HOUSE3D_TABLE = ("random", "dqn", "a3c", "hdqn", "hrl_grg", "hdqn_explorer", "hrl_grg_explorer", "frontier")
"""The rows of the paper's Table 3 (its "Hrl" is our ``hdqn``), by submission name, then rows
the paper did not have: the paper's hierarchical methods with a trained A3C in the back-up
node (our extension, ``*_explorer``) and ``frontier``, the training-free reference agent."""
PREDICTED_SUFFIX = "_predicted"
"""A submission ``<name>_predicted`` is ``<name>`` evaluated on the perception network's predictions."""
TRAINED_ON_PREDICTED_SUFFIX = "_predicted_trained"
"""A submission ``<name>_predicted_trained`` is ``<name>`` trained and evaluated on the perception
network's predictions, the paper's setting (checkpoints ``agents/checkpoints/<suite>/<name>/predicted/``)."""
HOUSE3D_SPLITS = {
    ("house-single", "seen-goals"): 0,
    ("house-single", "unseen-goals"): 1,
    ("house-multi", "seen-envs"): 2,
    ("house-multi", "unseen-envs"): 3,
}


def paper_house3d(name: str) -> dict[tuple[str, str], tuple] | None:
    """{(suite, split): (SR, SPL)} the paper's Table 3 reports for an entry of ``HOUSE3D_TABLE``."""
    values = _HOUSE3D.get(PAPER_NAMES.get(name, ""))
    return None if values is None else {key: values[i] for key, i in HOUSE3D_SPLITS.items()}


def paper_rows(suite: str, split: str) -> list[dict]:
    """The paper's rows for a suite and split ([] where the paper has none)."""
    if (suite, split) in HOUSE3D_SPLITS:
        i = HOUSE3D_SPLITS[(suite, split)]
        # the paper's House3D agents saw its DeepLabv3+'s predictions, not ground truth
        return [
            {"name": name, "observation": "predicted", "sr": v[i][0], "as": None, "ms": None, "spl": v[i][1]}
            for name, v in _HOUSE3D.items()
        ]
    if suite != "gridworld" or split not in GRIDWORLD_SPLITS:
        return []
    i = GRIDWORLD_SPLITS.index(split)
    return [
        {"name": name, "observation": "gt", "sr": v[i][0], "as": v[i][1], "ms": v[i][2], "spl": v[i][3]}
        for name, v in _GRIDWORLD.items()
    ]
