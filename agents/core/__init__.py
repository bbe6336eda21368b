"""What the learned agents of both worlds share, world-free: the Goals Relational Graph
(``grg``), the learners and their losses (``dqn``: Double DQN; ``a2c``: the actor-critic),
the replay memory (``replay``), the training loop (``training_loop``), per-row randomness
(``rows``) and seeded networks (``nets``)."""
