"""
Depth to XYZ, normals, support plane (the extension layer).
"""
from __future__ import annotations
import mereo._mereo
import typing
__all__: list[str] = ['back_project', 'fit_intrinsics']
@typing.overload
def back_project(frame: mereo._mereo.Frame) -> typing.Any:
    """
    The frame's organized XYZ cloud, (H, W, 3) float32, NaN where missing.
    """
@typing.overload
def back_project(depth: typing.Any, intrinsics: mereo._mereo.Intrinsics) -> typing.Any:
    """
    Back-projects an (H, W) depth image in metres.
    """
def fit_intrinsics(cloud: typing.Any) -> tuple:
    """
    Least-squares pinhole fit to an organized cloud: (Intrinsics, max residual px).
    """
