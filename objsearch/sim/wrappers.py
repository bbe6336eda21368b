"""Wrappers that give house agents the small observations of the paper.

``TargetMaskDepth`` turns the full observation into (target mask, depth) at 10 x 10, the
input of the paper's House3D agents; ``FrameHistory`` stacks the last 4 of them.

    env = FrameHistory(TargetMaskDepth(HouseEnv(...)), 4)   # obs: float32 (4, 2, 10, 10)
"""

from __future__ import annotations

from collections import deque

import cv2
import gymnasium
import numpy as np
from gymnasium import spaces


class TargetMaskDepth(gymnasium.ObservationWrapper):
    """Observation -> float32 (2, size, size): the fraction of each block that shows the
    target category, and the block's mean depth in metres (area averaging)."""

    def __init__(self, env: gymnasium.Env, size: int = 10, semantic_key: str = "semantic"):
        super().__init__(env)
        self.size, self.semantic_key = size, semantic_key
        far = float(np.max(env.observation_space["depth"].high))
        high = np.stack([np.ones((size, size), np.float32), np.full((size, size), far, np.float32)])
        self.observation_space = spaces.Box(np.zeros_like(high), high, dtype=np.float32)

    def observation(self, observation):
        """The (2, size, size) float32 target-fraction and depth channels of ``observation``."""
        mask = (np.asarray(observation[self.semantic_key]) == observation["target"]).astype(np.float32)
        depth = np.asarray(observation["depth"], dtype=np.float32)
        shape = (self.size, self.size)
        return np.stack(
            [
                cv2.resize(mask, shape, interpolation=cv2.INTER_AREA),
                cv2.resize(depth, shape, interpolation=cv2.INTER_AREA),
            ]
        )


class FrameHistory(gymnasium.Wrapper):
    """Stacks the last ``k`` observations (a Box) along a new first axis; at reset the
    first observation fills the history."""

    def __init__(self, env: gymnasium.Env, k: int = 4):
        super().__init__(env)
        inner = env.observation_space
        if not isinstance(inner, spaces.Box):
            raise TypeError("FrameHistory stacks Box observations; wrap with TargetMaskDepth first")
        self.k = k
        self.observation_space = spaces.Box(
            np.repeat(inner.low[None], k, axis=0), np.repeat(inner.high[None], k, axis=0), dtype=inner.dtype
        )
        self._frames: deque = deque(maxlen=k)

    def reset(self, **kwargs):
        """Reset the env and fill the history with the first observation; returns ((k, ...) stack, info)."""
        obs, info = self.env.reset(**kwargs)
        self._frames.extend([obs] * self.k)
        return np.stack(self._frames), info

    def step(self, action):
        """Step the env and push the observation; returns the (k, ...) stack with the env's other results."""
        obs, reward, terminated, truncated, info = self.env.step(action)
        self._frames.append(obs)
        return np.stack(self._frames), reward, terminated, truncated, info
