"""The signal layer: per-image depth preprocessing with no outside knowledge."""
from ._mereo.signal import filter_depth

__all__ = ["filter_depth"]
