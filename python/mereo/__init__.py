"""mereo: recognize generic objects in RGB-D images by their parts.

The numeric work happens in C++ (``mereo._mereo``); this package names it::

    import mereo
    frame = mereo.io.read("synthetic:7")          # or a .pcd file, a PNG pair, a TUM folder
    cloud = mereo.extension.back_project(frame)   # (H, W, 3) float32, NaN where missing
    result = mereo.recognize(frame, models=["mug"])  # one line of `mereo recognize`, as a dict
"""
from . import _mereo
from ._mereo import Frame, InputError, Intrinsics, nodes, options_of
from . import extension, features, io, knowledge, preview, signal, synthetic
from .graph import FrameQueue, Graph, GraphError, NodeError
from . import evaluate, recognition
from .recognition import recognize, recognize_all, tabletop_graph

__version__ = _mereo.__version__

__all__ = [
    "Frame",
    "FrameQueue",
    "Graph",
    "GraphError",
    "InputError",
    "Intrinsics",
    "NodeError",
    "evaluate",
    "extension",
    "features",
    "io",
    "knowledge",
    "nodes",
    "options_of",
    "preview",
    "recognition",
    "recognize",
    "recognize_all",
    "signal",
    "synthetic",
    "tabletop_graph",
    "__version__",
]
