"""mereo: recognize generic objects in RGB-D images by their parts.

The numeric work happens in C++ (``mereo._mereo``); this package names it::

    import mereo
    frame = mereo.io.read("synthetic:7")          # or a .pcd file, a PNG pair, a TUM folder
    cloud = mereo.extension.back_project(frame)   # (H, W, 3) float32, NaN where missing
"""
from . import _mereo
from ._mereo import Frame, InputError, Intrinsics, nodes
from . import extension, features, io, knowledge, preview, signal, synthetic
from .graph import FrameQueue, Graph, GraphError, NodeError

__version__ = _mereo.__version__

__all__ = [
    "Frame",
    "FrameQueue",
    "Graph",
    "GraphError",
    "InputError",
    "Intrinsics",
    "NodeError",
    "extension",
    "features",
    "io",
    "knowledge",
    "nodes",
    "preview",
    "signal",
    "synthetic",
    "__version__",
]
