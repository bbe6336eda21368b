"""The agents that learn no policy of the paper's methods: ``random_agent``, the privileged
``oracle``, ``frontier`` exploration (``frontier_geometry``), ``grg_frontier``, the
prior-guided frontiers (``prior_frontier``, ``room_frontier``) and Scene Priors
(``scene_priors``: the agent; ``_features``, ``_graph``, ``_net``, ``_train``: its parts by job)."""
