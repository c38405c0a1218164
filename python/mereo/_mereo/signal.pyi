"""
Per-image depth preprocessing (the signal layer).
"""
from __future__ import annotations
import mereo._mereo
import typing
__all__: list[str] = ['filter_depth']
@typing.overload
def filter_depth(frame: mereo._mereo.Frame, radius: typing.SupportsInt = 2, sigma_space: typing.SupportsFloat = 1.5, sigma_depth: typing.SupportsFloat = 0.004, depth_change_factor: typing.SupportsFloat = 0.02) -> mereo._mereo.Frame:
    """
    The frame with its depth (and its own cloud, if any) filtered; see the array overload.
    """
@typing.overload
def filter_depth(depth: typing.Any, radius: typing.SupportsInt = 2, sigma_space: typing.SupportsFloat = 1.5, sigma_depth: typing.SupportsFloat = 0.004, depth_change_factor: typing.SupportsFloat = 0.02) -> typing.Any:
    """
    Edge-preserving bilateral filter of depth (metres, NaN = missing): Gaussian weights on pixel distance and on depth difference (sigma_depth * z^2); depth jumps stay sharp, holes stay holes.
    """
