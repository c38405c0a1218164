"""The signal layer: per-image preprocessing with no outside knowledge (depth filtering, edges,
depth from a second camera registered to the colour camera)."""
from ._mereo.signal import detect_edges, filter_depth, register_depth

__all__ = ["detect_edges", "filter_depth", "register_depth"]
