"""The extension layer: depth to XYZ (and, later, normals and the support plane)."""
from ._mereo.extension import back_project, fit_intrinsics

__all__ = ["back_project", "fit_intrinsics"]
