import os

os.environ.setdefault("MUJOCO_GL", "egl")
# The test networks are tiny: one thread each is faster than two that fight over the
# machine's cores (and keeps timings steady when something else runs beside the tests).
os.environ.setdefault("OMP_NUM_THREADS", "1")
