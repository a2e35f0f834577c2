"""The package's tests run against the build tree: PYTHONPATH=build/<preset>/python, with
VIADUCT_BIN (the CLI, whose files the results must equal) and VIADUCT_SRC (the source tree)."""
import os
import pathlib

import pytest


@pytest.fixture(scope="session")
def src():
    return pathlib.Path(os.environ.get("VIADUCT_SRC", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("VIADUCT_BIN")
    if not path:
        pytest.fail("VIADUCT_BIN: the viaduct CLI of the same build")
    return path
