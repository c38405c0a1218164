"""The feature layer: planes, cylinders, cones, spheres and tori found in organized clouds; bounded
planar patches (a room's floor, walls, table tops, seats) and the legs under them; lines and elliptical arcs of the colour
image (the edge modality)."""
from ._mereo.features import detect_edge_primitives, detect_primitives, find_legs, label_image, planar_patches
from ._mereo.knowledge import Segment

__all__ = ["Segment", "detect_edge_primitives", "detect_primitives", "draw_edge_primitives", "find_legs", "label_image",
           "planar_patches"]


def draw_edge_primitives(frame, segments):
    """The frame's colour image (an (H, W, 3) uint8 array) with the lines (red) and arcs (green)
    of `segments` drawn over it as they were seen in the image."""
    from ._mereo.io import draw_objects

    lines = [s for s in segments if s.cls == "line"]
    arcs = [s for s in segments if s.cls == "arc"]
    return draw_objects(frame.color, frame.intrinsics, [("", lines), ("", arcs)])
