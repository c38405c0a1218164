"""The feature layer: planes, cylinders, spheres and tori found in organized clouds (work in
progress: see the issues for the accuracy figures still to meet)."""
from ._mereo.features import detect_primitives, label_image
from ._mereo.knowledge import Segment

__all__ = ["Segment", "detect_primitives", "label_image"]
