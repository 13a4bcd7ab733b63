import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def cleave_binary():
    path = os.environ.get("CLEAVE_BINARY", str(ROOT / "build" / "app" / "cleave"))
    if not os.path.exists(path):
        pytest.fail(f"the cleave binary is not at {path} (set CLEAVE_BINARY)")
    return path
