"""Shared fixtures of the workflow tests: one LocalCluster (2 workers) for the session."""

from __future__ import annotations

import logging
import sys
from pathlib import Path

import pytest

HELPERS_DIR = Path(__file__).parent
if str(HELPERS_DIR) not in sys.path:  # dask workers import the test scenarios by name
    sys.path.insert(0, str(HELPERS_DIR))

import workflow_helpers  # noqa: E402,F401  (registers the test scenarios)


@pytest.fixture(scope="session")
def dask_client():
    """A dask Client on a LocalCluster with 2 single-threaded worker processes."""
    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client
