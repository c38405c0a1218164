"""The extension layer: depth to XYZ, per-pixel normals, the support plane and the region of interest."""
from ._mereo.extension import SupportPlane, back_project, estimate_normals, find_support_plane, fit_intrinsics

__all__ = ["SupportPlane", "back_project", "estimate_normals", "find_support_plane", "fit_intrinsics"]
