"""What the learned agents of both worlds share, world-free: the Goals Relational Graph
(``grg``), the learners and their losses (``double_dqn``: Double DQN; ``a2c``: the actor-critic),
the replay memory (``replay``), the training loop (``training_loop``), the configs' base
(``config``), per-row randomness (``rows``) and seeded networks (``nets``)."""
