"""
Per-image depth preprocessing (the signal layer).
"""
from __future__ import annotations
import mereo._mereo
import numpy
import numpy.typing
import typing
__all__: list[str] = ['detect_edges', 'filter_depth', 'register_depth']
def detect_edges(color: typing.Any, **kwargs) -> list:
    """
    The edge chains of an (H, W, 3) uint8 RGB image, longest first: a list of (N, 2) float32 arrays of (x, y) image coordinates, sub-pixel, in the order the points are connected (Edge Drawing, OpenCV ximgproc).
    
    Options (keyword arguments; mereo.options_of lists them):
        method (str, default canny, one of canny edge_drawing): where the edge chains come from: Canny's edges linked here, or Edge Drawing's
        gradient_threshold (int, default 24, 1..1020): least gradient magnitude of an edge pixel
        texture_factor (float, default 2.5, 0..100): the threshold rises to this times the median gradient
        anchor_threshold (int, default 8, 0..255): Edge Drawing: how much an anchor exceeds its neighbours
        sigma (float, default 1, 0.3..10): Gaussian smoothing before the gradient, pixels
        min_chain_px (int, default 12, 2..100000): shortest edge chain kept, pixels
        subpixel (bool, default true): refine points to the gradient's sub-pixel peak across the edge
    """
@typing.overload
def filter_depth(frame: mereo._mereo.Frame, **kwargs) -> mereo._mereo.Frame:
    """
    The frame with its depth (and its own cloud, if any) filtered; see the array overload.
    """
@typing.overload
def filter_depth(depth: typing.Any, **kwargs) -> typing.Any:
    """
    Edge-preserving bilateral filter of depth (metres, NaN = missing): Gaussian weights on pixel distance and on depth difference (sigma_depth * z^2); depth jumps stay sharp, holes stay holes.
    
    Options (keyword arguments; mereo.options_of lists them):
        radius (int, default 2, 1..10): window half-size, pixels
        sigma_space (float, default 1.5, 0.1..20): spatial sigma, pixels
        sigma_depth (float, default 0.004, 1e-05..0.1): range sigma at 1 m, metres (grows with z^2)
        depth_change_factor (float, default 0.02, 0.0001..1): neighbours further than this times z are ignored
    """
def register_depth(depth: typing.Any, depth_intrinsics: mereo._mereo.Intrinsics, to_color: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 4]"], color_intrinsics: mereo._mereo.Intrinsics, rows: typing.SupportsInt, cols: typing.SupportsInt) -> typing.Any:
    """
    The depth image (metres, NaN = missing) of a camera with depth_intrinsics, as the colour camera with color_intrinsics and a rows x cols image sees it; to_color: the 4x4 transform from the depth camera's frame to the colour camera's. NaN where no point lands (OpenCV's rgbd::registerDepth).
    """
