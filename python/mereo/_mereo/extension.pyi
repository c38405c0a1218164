"""
Depth to XYZ, normals, support plane (the extension layer).
"""
from __future__ import annotations
import mereo._mereo
import numpy
import numpy.typing
import typing
__all__: list[str] = ['SupportPlane', 'back_project', 'estimate_normals', 'find_support_plane', 'fit_intrinsics']
class SupportPlane:
    """
    The table plane: normal (towards the camera), d (normal . x + d = 0), polygon (N, 3), inliers and roi masks, world_from_camera (4x4, z up).
    """
    def __repr__(self) -> str:
        ...
    def height(self, point: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> float:
        """
        Signed height of a camera-frame point above the plane, metres.
        """
    @property
    def d(self) -> float:
        ...
    @property
    def inlier_count(self) -> int:
        ...
    @property
    def inliers(self) -> typing.Any:
        ...
    @property
    def normal(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def polygon(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 3]"]:
        ...
    @property
    def rms(self) -> float:
        ...
    @property
    def roi(self) -> typing.Any:
        ...
    @property
    def world_from_camera(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 4]"]:
        ...
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
def estimate_normals(cloud: typing.Any, method: str = 'fast', window: typing.SupportsInt = 5, depth_change_factor: typing.SupportsFloat = 0.02, adaptive_window: bool = True, reference_depth: typing.SupportsFloat = 1.0, noise_depth: typing.SupportsFloat = 2.0) -> typing.Any:
    """
    Per-pixel unit normals of an (H, W, 3) cloud: (H, W, 3) float32, towards the camera, NaN where undefined. method 'fast' (least-squares tangents) or 'covariance' (PCA, integral images); windows never cross a depth jump larger than depth_change_factor * z (growing as z^2 beyond noise_depth metres).
    """
def find_support_plane(cloud: typing.Any, normals: typing.Any, up: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None, epsilon: typing.SupportsFloat = 0.008, min_inliers: typing.SupportsInt = 2000, min_height: typing.SupportsFloat = 0.006, max_height: typing.SupportsFloat = 0.4, margin: typing.SupportsFloat = 0.0, seed: typing.SupportsInt = 0) -> SupportPlane:
    """
    The dominant horizontal plane under the objects (the table) with its polygon, the mask of the points above it (roi) and a world frame with z up. `up`: the camera-frame direction against gravity when known. Raises InputError when there is no such plane.
    """
def fit_intrinsics(cloud: typing.Any) -> tuple:
    """
    Least-squares pinhole fit to an organized cloud: (Intrinsics, max residual px).
    """
