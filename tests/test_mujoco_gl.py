"""``import objsearch`` leaves ``MUJOCO_GL`` as the user set it, and imports no MuJoCo: the value
is read when the first renderer is made (``objsearch.sim.glbackend``). A value that
``import mujoco`` would fail on still lets the packages that import MuJoCo load."""

import os
import subprocess
import sys

import pytest

CODE = """
import os, sys
gl = lambda: {k: v for k, v in os.environ.items() if "MUJOCO" in k}  # (mujoco.egl sets PYOPENGL_PLATFORM itself)
before = gl()
import objsearch
after_package = (gl() == before, "mujoco" in sys.modules)
import objsearch.sim.world, objsearch.house.generate
print(after_package, gl() == before, "mujoco" in sys.modules, repr(os.environ.get("MUJOCO_GL")))
"""


@pytest.mark.parametrize("value", ["bogus", "egl", "disable", None])
def test_import_objsearch_leaves_mujoco_gl_untouched(value):
    env = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    if value is not None:
        env["MUJOCO_GL"] = value
    proc = subprocess.run([sys.executable, "-c", CODE], env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    # the environment is as it was after `import objsearch` (which imports no MuJoCo) and after
    # the modules that import MuJoCo, whatever the value
    assert proc.stdout.split() == ["(True,", "False)", "True", "True", repr(value)]
