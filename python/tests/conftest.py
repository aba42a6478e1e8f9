import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
# nmm.plot's figures are drawn off screen
os.environ.setdefault("MPLBACKEND", "Agg")

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def nmm_cli():
    """The `nmm` binary of this checkout (NMM_BIN, or target/release/nmm built by
    scripts/test), to compare the package with the command line."""
    path = os.environ.get("NMM_BIN") or str(REPO / "target" / "release" / "nmm")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        pytest.fail(f"the nmm binary is needed at {path}: run `cargo build --release` (scripts/test does)")
    return path


def cli(nmm_cli, *args, cwd=None):
    return subprocess.run([nmm_cli, *map(str, args)], capture_output=True, text=True, cwd=cwd)


@pytest.fixture(scope="module")
def client():
    """A dask.distributed LocalCluster of 2 single-thread worker processes (module-wide)."""
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    )
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()
