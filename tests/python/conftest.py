from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT.parent / "shared" / "data" / "real"


@pytest.fixture
def real():
    """The shared real RGB-D frames (../shared/data/real), skipped where absent."""
    if not REAL.is_dir():
        pytest.skip(f"shared data not found: {REAL}")
    return REAL
