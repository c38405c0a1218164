"""Frame sources and writers (the hardware layer): PCD, PNG pairs, TUM folders, synthetic:SEED."""
from ._mereo.io import (
    Sequence,
    colorize_depth,
    colorize_labels,
    colorize_normals,
    hstack,
    open,
    read,
    read_intrinsics,
    write_image,
    write_pcd,
    write_png_pair,
)

__all__ = [
    "Sequence",
    "colorize_depth",
    "colorize_labels",
    "colorize_normals",
    "hstack",
    "open",
    "read",
    "read_intrinsics",
    "write_image",
    "write_pcd",
    "write_png_pair",
]
