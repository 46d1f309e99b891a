"""Shared fixtures of the al_refine pytest suite (run by ctest as python.pytest).

The module is imported from the build folder (PYTHONPATH set by ctest); AL_REFINE_BIN is the CLI
built beside it, used to check that Python and the command line agree."""
import os
import subprocess
from pathlib import Path

import pytest

import al_refine as al

# A small synthetic room: big enough for a non-trivial refinement, small enough for CI.
N, SEED, VIEWS, WIDTH, HEIGHT = 20000, 3, 4, 64, 48


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("AL_REFINE_BIN")
    if not path or not Path(path).is_file():
        pytest.fail("AL_REFINE_BIN must name the al-refine binary (ctest sets it)")
    return path


def run_cli(cli, *args, check=True):
    proc = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, timeout=600)
    if check and proc.returncode != 0:
        raise AssertionError(f"al-refine {' '.join(map(str, args))} failed ({proc.returncode}): {proc.stderr}")
    return proc


@pytest.fixture(scope="session")
def synth_dir(cli, tmp_path_factory):
    """The scene written by `al-refine synth`, the CLI's side of every comparison."""
    out = tmp_path_factory.mktemp("synth")
    run_cli(cli, "synth", "--preset", "room", "--gaussians", N, "--seed", SEED, "--views", VIEWS,
            "--resolution", f"{WIDTH}x{HEIGHT}", "--quiet", "--out", out)
    return out


@pytest.fixture(scope="session")
def synth():
    """The same scene generated in memory by al_refine.synth."""
    return al.synth("room", N, seed=SEED, views=VIEWS, width=WIDTH, height=HEIGHT)
