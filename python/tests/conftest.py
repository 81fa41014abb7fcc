"""Shared fixtures of the partslam pytest suite: the built-in simulator's log and submaps (built once per
session, like core/testing/simulated_maps.h), the CLI binary and the real-data folder.

ctest sets PYTHONPATH to <build>/python; run by hand, the suite falls back to ../../build/python."""
import os
import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

try:
    import partslam  # noqa: F401
except ImportError:
    sys.path.insert(0, str(REPO / "build" / "python"))
    import partslam  # noqa: F401


@pytest.fixture(scope="session")
def sim_scans():
    """The default simulated building's scans (seed 1), with exact poses."""
    return partslam.load_scan_source("sim").scans


@pytest.fixture(scope="session")
def sim_submaps(sim_scans):
    """Its submaps with the default SubmapConfig."""
    return partslam.build_submaps(sim_scans)


@pytest.fixture(scope="session")
def cli():
    """Path of the partslam CLI: $PARTSLAM_BINARY (ctest), else the build folder the module sits in."""
    path = os.environ.get("PARTSLAM_BINARY") or str(pathlib.Path(partslam.__file__).resolve().parents[1] / "partslam")
    if not os.access(path, os.X_OK):
        pytest.fail(f"the partslam CLI is not built at {path} (build the 'partslam' target)")
    return path


def shared_data():
    """The real-data folder: $PARTSLAM_SHARED_DATA, else ../shared/data beside the repository."""
    return pathlib.Path(os.environ.get("PARTSLAM_SHARED_DATA") or REPO.parent / "shared" / "data")
