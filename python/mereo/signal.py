"""The signal layer: per-image preprocessing with no outside knowledge (depth filtering, edges)."""
from ._mereo.signal import detect_edges, filter_depth

__all__ = ["detect_edges", "filter_depth"]
