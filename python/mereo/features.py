"""The feature layer: planes, cylinders, cones, spheres and tori found in organized clouds; lines
and elliptical arcs of the colour image (the edge modality)."""
from ._mereo.features import detect_edge_primitives, detect_primitives, label_image
from ._mereo.knowledge import Segment

__all__ = ["Segment", "detect_edge_primitives", "detect_primitives", "label_image"]
