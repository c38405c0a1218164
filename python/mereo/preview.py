"""Pictures of frames: colour, false-colour depth, normals and labels side by side."""
from __future__ import annotations

import numpy as np

from . import io


def frame_preview(frame, truth=None) -> np.ndarray:
    """An (H, W', 3) uint8 RGB strip: colour | depth, and with ground truth also
    normals | object labels. The colouring runs in C++ (mereo.io.colorize_*)."""
    panels = []
    if frame.color is not None:
        panels.append(frame.color)
    panels.append(io.colorize_depth(frame.depth))
    if truth is not None:
        panels.append(io.colorize_normals(truth.normals))
        panels.append(io.colorize_labels(truth.objects))
    return io.hstack(panels)


def save_preview(path, frame, truth=None) -> str:
    """Writes frame_preview(...) as a PNG and returns its path."""
    io.write_image(str(path), frame_preview(frame, truth))
    return str(path)
