"""mereo: recognize generic objects in RGB-D images by their parts.

The numeric work happens in C++ (``mereo._mereo``); this package names it::

    import mereo
    frame = mereo.io.read("synthetic:7")          # or a .pcd file, a PNG pair, a TUM folder
    cloud = mereo.extension.back_project(frame)   # (H, W, 3) float32, NaN where missing
"""
from . import _mereo
from ._mereo import Frame, InputError, Intrinsics
from . import extension, io, synthetic

__version__ = _mereo.__version__

__all__ = ["Frame", "InputError", "Intrinsics", "extension", "io", "synthetic", "__version__"]
