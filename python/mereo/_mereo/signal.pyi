"""
Per-image depth preprocessing (the signal layer).
"""
from __future__ import annotations
import mereo._mereo
import typing
__all__: list[str] = ['filter_depth']
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
