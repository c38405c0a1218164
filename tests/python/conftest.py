from pathlib import Path

import pytest

from mereo import _mereo

# The test-only node kinds (identity, checksum, fail_on_frame) for the engine's tests; they are
# not in the library's list, so users never see them.
_mereo._testing.register_test_nodes()

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT.parent / "shared" / "data" / "real"


@pytest.fixture
def real():
    """The shared real RGB-D frames (../shared/data/real), skipped where absent."""
    if not REAL.is_dir():
        pytest.skip(f"shared data not found: {REAL}")
    return REAL
