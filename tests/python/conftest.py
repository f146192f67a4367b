"""Shared fixtures of the Python package's tests (docs/python.md): the emrm program of the same
build, whose output the package must reproduce number for number, and the shipped examples."""

import os
import subprocess
from pathlib import Path

import pytest

import emrm

SOURCE_DIR = Path(__file__).resolve().parents[2]
EXAMPLES = SOURCE_DIR / "examples" / "tjunction"


def emrm_program() -> Path:
    """The emrm program: EMRM_EXE (ctest sets it), else the one beside the package's build folder."""
    if "EMRM_EXE" in os.environ:
        return Path(os.environ["EMRM_EXE"])
    return Path(emrm.__file__).resolve().parents[2] / "emrm"


def run_emrm(*args, cwd=None) -> subprocess.CompletedProcess:
    """Runs `emrm ARGS...` and returns what it printed and its exit code."""
    return subprocess.run([str(emrm_program()), *map(str, args)], capture_output=True, text=True, cwd=cwd)


@pytest.fixture(scope="session")
def examples() -> Path:
    return EXAMPLES
