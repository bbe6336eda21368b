"""The leaderboard: validated result submissions and the pages generated from them."""
