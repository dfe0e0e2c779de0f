import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("STSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = SOURCE / "tests" / "data" / "highway"


@pytest.fixture(scope="session")
def stsim_binary():
    b = os.environ.get("STSIM_BINARY")
    if not b or not os.path.exists(b):
        pytest.skip("STSIM_BINARY not set (ctest sets it)")
    return b


def run_stsim(binary, *args, cwd=None):
    return subprocess.run([binary, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=300)
