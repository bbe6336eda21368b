# Every target creates .venv if it is missing and installs what the project needs.
PY      ?= python3
VENV    := .venv
BIN     := $(VENV)/bin
STAMP   := $(VENV)/.installed
export MUJOCO_GL ?= egl

.PHONY: demo test bench leaderboard leaderboard-tier2 install clean

$(BIN)/python:
	$(PY) -m venv $(VENV)

# torch first, pinned: on a CPU machine this takes the local CPU build and the
# `torch>=2.2` requirement of the package is then already met (no CUDA download).
$(STAMP): $(BIN)/python pyproject.toml
	$(BIN)/pip install --upgrade pip setuptools
	$(BIN)/pip install "torch==2.13.0"
	$(BIN)/pip install -e ".[test,bench,ray]"
	touch $(STAMP)

install: $(STAMP)

demo: $(STAMP)
	@echo "demo 1/4: random agent on the paper's grid world, every split, 5 seeds: the floor any method must beat"
	$(BIN)/objsearch-eval --suite gridworld
	@echo "demo 2/4: oracle (shortest paths) on the grid world: the ceiling, SR = SPL = 1 by construction"
	$(BIN)/objsearch-eval --suite gridworld --agent oracle
	@echo "demo 3/4: HRL-GRG (the paper's method, shipped checkpoint) on the grid world's unseen goals, 1 seed, 2 workers"
	$(BIN)/objsearch-eval --suite gridworld --agent hrl_grg --split unseen-goals --seeds 1 --workers 2
	@echo "demo 4/4: HRL-GRG in a 3D MuJoCo house (house-single, the default suite), 1 seed, 32 episodes in lockstep"
	$(BIN)/objsearch-eval --agent hrl_grg --seeds 1 --batch 32   # the main job: a house suite (house-single)

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/python -m pytest -q

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_gridworld.py

# Re-evaluate the shipped agents on every suite with the paper's seeds and store them on
# the leaderboard (house suites render their observation caches first: minutes).
LEADERBOARD_AGENTS ?= random oracle
LEADERBOARD_SUITES ?= gridworld house-single house-multi house-gen house-gen-v2 house-single-v2 house-multi-v2 house-gen-v2-objectnav house-gen-v2-shuffled rooms \
	house-large house-large-roomwise house-large-shuffled
# shipped checkpoints; the *_greedy agents play the same checkpoints greedily (epsilon 0)
LEADERBOARD_GRID_AGENTS ?= dqn hdqn hrl_grg hrl_grg_no_relation hrl_grg_no_termination hrl_grg_no_high_level \
	dqn_greedy hdqn_greedy hrl_grg_greedy
# house agents with shipped checkpoints: suite:agent, each evaluated on gt and on predicted observations
# (and rooms:random, so that Table 4 has every method on both observations)
# (predictions of house-gen's and house-gen-v2's 20 evaluation houses: 20-40 minutes of one core each the first time, a cache build)
LEADERBOARD_HOUSE ?= house-single:a3c house-single:dqn house-single:hdqn house-single:hrl_grg house-single:hdqn_explorer house-single:hrl_grg_explorer \
	house-multi:a3c house-multi:dqn house-multi:hdqn house-multi:hrl_grg house-multi:hrl_grg_explorer \
	house-gen:a3c house-gen:dqn house-gen:hrl_grg_explorer house-gen-v2:a3c house-gen-v2:hrl_grg house-gen-v2:hrl_grg_explorer \
	house-gen-v2-shuffled:a3c house-gen-v2-shuffled:hrl_grg rooms:a3c rooms:hrl_grg rooms:scene_priors rooms:random \
	house-gen-v2:grg_frontier house-gen-v2-shuffled:grg_frontier \
	house-large:room_prior_frontier house-large-roomwise:room_prior_frontier house-large-shuffled:room_prior_frontier \
	house-large:object_prior_frontier house-large-roomwise:object_prior_frontier house-large-shuffled:object_prior_frontier \
	house-large:inspect_frontier house-large-roomwise:inspect_frontier house-large-shuffled:inspect_frontier
# house agents also trained on predicted observations (agents/checkpoints/SUITE/AGENT/predicted/, the paper's
# setting), evaluated on predicted observations as entry AGENT_predicted_trained
LEADERBOARD_HOUSE_TRAINED_PREDICTED ?= house-single:a3c house-single:hrl_grg_explorer
# training-free reference agents on every house suite, evaluated on gt and on predicted observations
LEADERBOARD_HOUSE_REFERENCE ?= frontier
# the large-house tier's size sweep (docs/large_houses.md): frontier and the prior agents, gt, stored in one add
LEADERBOARD_SWEEP_SUITES ?= house-size-4 house-size-4-shuffled house-size-7 house-size-7-shuffled \
	house-size-10 house-size-10-shuffled house-size-14 house-size-14-shuffled
LEADERBOARD_SWEEP_AGENTS ?= frontier room_prior_frontier object_prior_frontier
# the large-house tier, version 2 (docs/large_houses.md): its goal caches are not kept, so it renders live
LEADERBOARD_TIER2_SUITES ?= house-large-v2 house-large-v2-shuffled house-large-v2-p50 house-large-v2-p25 house-large-v2-p75 \
	house-large-v2-roomwise
LEADERBOARD_TIER2_AGENTS ?= frontier object_prior_frontier room_prior_frontier inspect_frontier
# one shell step of the loops below: evaluate $$agent on $$suite on gt and on predicted observations, store both
EVAL_GT_AND_PREDICTED = $(BIN)/objsearch-eval --agent $$agent --suite $$suite --batch 32 --quiet --out build/$$suite-$$agent.json && \
	  $(BIN)/objsearch leaderboard add build/$$suite-$$agent.json --replace && \
	  $(BIN)/objsearch-eval --agent $$agent --suite $$suite --batch 32 --quiet --observation predicted \
	    --out build/$$suite-$${agent}_predicted.json && \
	  $(BIN)/objsearch leaderboard add build/$$suite-$${agent}_predicted.json --name $${agent}_predicted --replace
leaderboard: $(STAMP)
	mkdir -p build && date +%s > build/.leaderboard-start
	for pair in $(LEADERBOARD_HOUSE); do suite=$${pair%%:*}; agent=$${pair#*:}; \
	  $(EVAL_GT_AND_PREDICTED) || exit 1; \
	done
	for pair in $(LEADERBOARD_HOUSE_TRAINED_PREDICTED); do suite=$${pair%%:*}; agent=$${pair#*:}; \
	  $(BIN)/objsearch-eval --agent $$agent --suite $$suite --batch 32 --quiet --observation predicted \
	    --checkpoint agents/checkpoints/$$suite/$$agent/predicted --out build/$$suite-$${agent}_predicted_trained.json && \
	  $(BIN)/objsearch leaderboard add build/$$suite-$${agent}_predicted_trained.json --name $${agent}_predicted_trained \
	    --replace || exit 1; \
	done
	for suite in $(filter-out gridworld,$(LEADERBOARD_SUITES)); do for agent in $(LEADERBOARD_HOUSE_REFERENCE); do \
	  $(EVAL_GT_AND_PREDICTED) || exit 1; \
	done; done
	for suite in $(LEADERBOARD_SUITES); do for agent in $(LEADERBOARD_AGENTS); do \
	  $(BIN)/objsearch-eval --agent $$agent --suite $$suite --batch 32 --quiet --out build/$$suite-$$agent.json && \
	  $(BIN)/objsearch leaderboard add build/$$suite-$$agent.json --replace || exit 1; \
	done; done
	for suite in $(LEADERBOARD_SWEEP_SUITES); do for agent in $(LEADERBOARD_SWEEP_AGENTS); do \
	  $(BIN)/objsearch-eval --agent $$agent --suite $$suite --batch 16 --quiet --out build/$$suite-$$agent.json || exit 1; \
	done; done
	$(BIN)/objsearch leaderboard add --replace $(foreach s,$(LEADERBOARD_SWEEP_SUITES),$(foreach a,$(LEADERBOARD_SWEEP_AGENTS),build/$(s)-$(a).json))
	$(MAKE) leaderboard-tier2
	for agent in $(LEADERBOARD_GRID_AGENTS); do \
	  $(BIN)/objsearch-eval --agent $$agent --suite gridworld --workers 2 --batch 64 --quiet --out build/gridworld-$$agent.json && \
	  $(BIN)/objsearch leaderboard add build/gridworld-$$agent.json --replace || exit 1; \
	done
	# replay a random sample of every stored entry, large enough to catch 5% altered records (docs/failure_modes.md)
	$(BIN)/objsearch leaderboard verify --all
	@echo "make leaderboard: $$(( $$(date +%s) - $$(cat build/.leaderboard-start) )) s"

# the tier's version 2 alone, an entry at a time (10-20 minutes each, live; an interrupted
# evaluation resumes from its build/ file when rerun)
leaderboard-tier2: $(STAMP)
	mkdir -p build
	for agent in $(LEADERBOARD_TIER2_AGENTS); do for suite in $(LEADERBOARD_TIER2_SUITES); do \
	  $(BIN)/objsearch-eval --agent $$agent --suite $$suite --render live --batch 16 --quiet --out build/$$suite-$$agent.json && \
	  $(BIN)/objsearch leaderboard add build/$$suite-$$agent.json --replace || exit 1; \
	done; done

clean:
	rm -rf $(VENV) build *.egg-info
