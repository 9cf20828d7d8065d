"""Where the module under test and the CLI are: the build tree of scripts/test.sh (build/), or the
folders named by RESTIR_PYTHONPATH / RESTIR_BIN (ctest sets both)."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build"
sys.path.insert(0, os.environ.get("RESTIR_PYTHONPATH", str(BUILD / "python")))
RESTIR_BIN = os.environ.get("RESTIR_BIN", str(BUILD / "bin" / "restir"))
CORNELL = str(ROOT / "scenes" / "cornell-box.pbrt")


@pytest.fixture(scope="session")
def rl():
    import restirlab
    return restirlab


@pytest.fixture(scope="session")
def cornell(rl):
    return rl.load_scene(CORNELL)


def run_cli(*args, check=True):
    """`restir ARGS...`: the completed process (stderr kept for its `error: ...` line)."""
    p = subprocess.run([RESTIR_BIN, *map(str, args)], capture_output=True, text=True, cwd=ROOT)
    if check and p.returncode != 0:
        raise AssertionError(f"restir {' '.join(map(str, args))} failed ({p.returncode}): {p.stderr}")
    return p
