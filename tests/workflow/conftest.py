"""Shared fixtures of the workflow tests: one LocalCluster (2 workers) for the session."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

HELPERS_DIR = Path(__file__).parent
if str(HELPERS_DIR) not in sys.path:  # dask workers import the test scenarios by name
    sys.path.insert(0, str(HELPERS_DIR))

import workflow_helpers  # noqa: E402,F401  (registers the test scenarios)


@pytest.fixture(scope="session")
def dask_client():
    """A dask Client on a LocalCluster with 2 single-threaded worker processes (the
    package's own cluster set-up, ``sweep.runner.dask_client``)."""
    from dominowave.sweep.runner import dask_client as package_client

    with package_client(n_workers=2) as client:
        yield client
