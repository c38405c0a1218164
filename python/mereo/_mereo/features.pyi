"""
RANSAC primitives of organized clouds (the feature layer).
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['detect_primitives', 'label_image']
def detect_primitives(cloud: typing.Any, normals: typing.Any, roi: typing.Any = None, color: typing.Any = None, unfiltered: typing.Any = None, **kwargs) -> list[...]:
    """
    Planes, cylinders, spheres and tori of an (H, W, 3) cloud with (H, W, 3) normals, largest first (mereo.knowledge.Segment objects; .pixels holds each one's inlier pixel indices). `roi`: an (H, W) mask of the pixels to use. `unfiltered`: the (H, W, 3) points of the unfiltered depth when the cloud's was filtered; cylinders and spheres are then measured on them (smoothing flattens curved surfaces).
    
    Options (keyword arguments; mereo.options_of lists them):
        seed (int, default 0, 0..1e+15): the only source of randomness
        classes (list, default plane,cylinder,torus,sphere): classes to look for
        epsilon (float, default 0.006, 0.0001..0.1): inlier distance at 1 m, metres
        normal_deviation_deg (float, default 25, 1..90): inlier normal deviation
        min_support (int, default 250, 10..1e+07): fewest pixels of a segment
        min_support_torus (int, default 80, 10..1e+07): fewest pixels of a torus
        max_primitives (int, default 64, 1..10000): at most this many segments
        upright_bodies (bool, default true): given the support plane, also look for upright cylinders without normals (noisy depth)
        fit_along_rays (bool, default true): fit cylinders and spheres along the rays (depth noise along them); false: by geometric distance
        handles_near_cylinders (bool, default true): look for a torus next to every cylinder
        handle_body_min_radius (float, default 0.02, 0..1): ... whose radius is at least this, metres
        handle_body_max_radius (float, default 0.08, 0..1): ... and at most this
        handles_from_colour (bool, default true): where the depth shows no handle, look for its silhouette beside the body in the colour image
        colour_handle_turn_deg (float, default 60, 0..75): ... in planes turned from the limbs' about the body's axis by up to this (0: the limbs' planes only)
        max_handle_turn_deg (float, default 25, 0..90): a ring that fits better turned more than this from its body's axis is not a handle (90: no check)
    """
def label_image(segments: collections.abc.Sequence[...], rows: typing.SupportsInt, cols: typing.SupportsInt) -> numpy.typing.NDArray[numpy.int32]:
    """
    An (rows, cols) int32 image of the index of the segment owning each pixel (-1: none): the inlier masks.
    """
