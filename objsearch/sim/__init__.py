"""Simulation of generated houses: rendering (RGB, depth, segmentation), poses, envs, caches."""
