"""``ObjSearch/Suite-v1``: a suite's fixed episodes as one Gymnasium env, in one call.

```python
import gymnasium, objsearch

env = gymnasium.make("ObjSearch/Suite-v1", suite="house-single", split="seen-goals")
obs, info = env.reset()  # the split's episode 0 with the first standard seed; each reset() the next
task = env.unwrapped.agent_task  # what objsearch-eval hands an agent's reset(task)
```

One id for every suite, its name an argument, as dm_control's ``suite.load(domain, task)``
and habitat's benchmark config take theirs, rather than an id per suite: suite names carry
their own versions (``house-gen-v2``, ``house-single-v2``), so ids such as
``ObjSearch/house-gen-v2-v1`` would hold two versions, and one id also plays every suite a
name can give (a suite file's path, one registered with ``register_suite`` or by a package).
"""

from __future__ import annotations

from typing import Any, Iterable

import gymnasium

from objsearch.errors import UserError


class SuiteEnv(gymnasium.Env):
    """The fixed episodes of a suite's splits, one per ``reset()``, exactly as ``objsearch-eval``
    plays them.

    ## Description
    The env of the suite (``make_suite(suite, **config).make_env()``: ``ObjSearch/House-v1``'s
    for a house suite, ``ObjSearch/GridWorld-v0``'s for ``gridworld``) reset to the suite's
    episodes in the harness's order: for each split (in report order), for each seed, every
    episode in the split's order (``objsearch.eval.plan.plan_units``). Each episode starts as
    the harness starts it (``env.reset(seed=<evaluation seed>, options={"task": ...})``), so an
    agent stepping this env sees what ``objsearch-eval --suite SUITE --split SPLIT --seeds ...``
    shows it, and ends with the same records (``tests/eval/test_suite_env.py``).

    ## Observation Space, Action Space, Rewards, Episode End
    Those of the suite's env (``HouseEnv``, ``GridWorldEnv``: their docstrings), with the
    suite's options: its step limit, its protocol (``objectnav`` suites have the STOP action),
    ``observation="predicted"``, ...

    ## Starting State
    ``reset()`` starts the next episode of the sequence and, after the last, the first again
    (one lap is the evaluation). ``reset(seed=...)`` starts the sequence over at its first
    episode: the episodes are fixed, so a seed chooses none of them (Gymnasium's rule holds:
    the same seed, the same episodes after it); the evaluation seeds are ``seeds``. The reset
    ``info`` adds to the suite env's: ``suite``, ``split``, ``seed`` (the evaluation seed),
    ``episode_id``, ``goal`` (the goal's label in records), ``index`` (the episode's place in
    the sequence) and ``num_episodes`` (the sequence's length). ``agent_task`` is then the
    ``objsearch.eval.agent.AgentTask`` the harness gives the agent (its ``rng``:
    ``episode_rng(seed, split, episode_id)``; ``privileged``: ground truth for the oracle).

    ## Arguments
    ``suite``: a suite name (``objsearch suite list``) or a suite file's path. ``split``: one
    split, several, or None for all of the suite's (as ``objsearch-eval`` without ``--split``).
    ``seeds``: the evaluation seeds (default: the suite's standard seeds,
    ``objsearch.eval.suites.standard_seeds``). ``episodes``: only the first that many episodes
    of each split (``--episodes``). ``render_mode``: the suite env's (``rgb_array``). Any other
    keyword is the suite's option (``make_suite``; e.g. ``mode``, ``cache_dir``, ``max_steps``,
    ``observation`` for house suites; ``maps``, ``tasks`` for the grid world).

    ## Version History
    * v1: initial release. Numbered with ``ObjSearch/House-v1``, whose observations (with
      ``pose`` and ``collided``) a house suite's episodes give.
    """

    metadata = {"render_modes": ["rgb_array"]}  # both worlds' envs have it; an instance holds its env's

    def __init__(
        self,
        suite: str | None = None,
        split: str | Iterable[str] | None = None,
        seeds: Iterable[int] | None = None,
        episodes: int | None = None,
        render_mode: str | None = None,
        **config,
    ):
        from objsearch.eval.config import check_seeds
        from objsearch.eval.plan import plan_units
        from objsearch.eval.suites import check_splits, make_suite, standard_seeds

        if not isinstance(suite, str) or not suite:
            raise UserError(
                'ObjSearch/Suite-v1 needs the suite: gymnasium.make("ObjSearch/Suite-v1", suite="house-single", '
                'split="seen-goals") (objsearch suite list names them all)'
            )
        if episodes is not None and (isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1):
            raise UserError(f"episodes={episodes!r}: give an integer >= 1 (the first episodes of each split), or None")
        self.suite_name = suite
        self.suite = make_suite(suite, **config)
        splits = [split] if isinstance(split, str) else list(split or ())
        self.splits = check_splits(self.suite, splits)
        self.seeds = standard_seeds(suite) if seeds is None else check_seeds(seeds)
        self.units = plan_units(self.suite, self.splits, self.seeds, episodes)
        self._episodes = {s: {ep.episode_id: ep for ep in self.suite.episodes(s)} for s in self.splits}
        self.env = self.suite.make_env()
        self.metadata = dict(getattr(self.env, "metadata", {}))
        if render_mode is not None:
            modes = self.metadata.get("render_modes", [])
            if render_mode not in modes:
                raise ValueError(f"render_mode must be one of {modes}, not {render_mode!r}")
            self.env.render_mode = render_mode
        self.render_mode = render_mode
        self.observation_space = self.env.observation_space
        self.action_space = self.env.action_space
        self.index = -1  # the place in ``units`` of the episode playing (-1: none yet)
        self.agent_task = None

    @property
    def num_episodes(self) -> int:
        """Episodes in one lap of the sequence: splits x seeds x episodes."""
        return len(self.units)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start the next episode of the sequence (after the last, the first), or with ``seed``
        the first; returns (observation, info)."""
        from objsearch.eval.episode import agent_task

        super().reset(seed=seed)
        self.index = 0 if seed is not None else (self.index + 1) % len(self.units)
        split, eval_seed, episode_id = self.units[self.index]
        episode = self._episodes[split][episode_id]
        # as the harness starts an episode (objsearch.eval.episode.start_episode)
        obs, info = self.env.reset(seed=eval_seed, options={"task": episode.task})
        self.agent_task = agent_task(
            self.suite_name, split, episode, eval_seed, info, self.observation_space, self.action_space
        )
        info = {
            **info,
            "suite": self.suite_name,
            "split": split,
            "seed": eval_seed,
            "episode_id": episode_id,
            "goal": episode.goal_name,
            "index": self.index,
            "num_episodes": len(self.units),
        }
        return obs, info

    def step(self, action):
        """The suite env's step: (observation, reward, terminated, truncated, info)."""
        return self.env.step(action)

    def render(self):
        """The suite env's ``render()`` (``render_mode="rgb_array"``: the current view)."""
        return self.env.render()

    def close(self):
        """Close the suite env (its renderers and caches); can be called twice."""
        self.env.close()
