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
    def borders(self) -> list[int]:
        """
        per polygon vertex, the image borders its pixel lies on (bits: 1 left, 2 right, 4 top, 8 bottom)
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
    def noise(self) -> float:
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
def estimate_normals(cloud: typing.Any, **kwargs) -> typing.Any:
    """
    Per-pixel unit normals of an (H, W, 3) cloud: (H, W, 3) float32, towards the camera, NaN where undefined. Windows never cross a depth jump larger than depth_change_factor * z (growing as z^2 beyond noise_depth metres).
    
    Options (keyword arguments; mereo.options_of lists them):
        method (str, default fast, one of fast covariance): fast: least-squares tangents; covariance: PCA through integral images
        window (int, default 5, 3..101): window side in pixels (odd)
        depth_change_factor (float, default 0.02, 0.0001..1): a depth jump larger than this times z breaks smoothing
        noise_depth (float, default 2, 0.1..100): metres: beyond it the jump threshold grows as z^2 (sensor noise)
        adaptive_window (bool, default true): covariance: the window shrinks with depth (constant metric size)
        reference_depth (float, default 1, 0.1..10): metres: depth at which the adaptive window equals `window`
    """
def find_support_plane(cloud: typing.Any, normals: typing.Any, up: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None, **kwargs) -> SupportPlane:
    """
    The dominant horizontal plane under the objects (the table) with its polygon, the mask of the points above it (roi) and a world frame with z up. `up`: the camera-frame direction against gravity when known. Raises InputError when there is no such plane.
    
    Options (keyword arguments; mereo.options_of lists them):
        seed (int, default 0, 0..1e+15): random seed of the plane hypotheses
        epsilon (float, default 0.008, 0.0001..0.1): inlier distance at 1 m, metres
        min_inliers (int, default 2000, 10..1e+07): fewest points of the plane
        candidates (int, default 4, 1..50): distinct planes compared
        min_share (float, default 0.3, 0..1): a higher plane's least share of the heaviest plane's weight
        min_area (float, default 0.05, 0..100): a higher plane's least area, square metres
        prefer (str, default highest, one of highest lowest): of parallel planes a step apart: the highest (a table) or the lowest (a room's floor)
        min_height (float, default 0.006, 0..1): ROI: lowest height above the plane, metres
        max_height (float, default 0.4, 0.01..5): ROI: highest height above the plane, metres
        margin (float, default 0, -1..1): ROI: polygon shrunk by this, metres
        beyond_border (float, default 0.25, 0..5): ROI: reach beyond the polygon's edges on the image's border, metres
    """
def fit_intrinsics(cloud: typing.Any) -> tuple:
    """
    Least-squares pinhole fit to an organized cloud: (Intrinsics, max residual px).
    """
