"""
RANSAC primitives of organized clouds (the feature layer).
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['detect_primitives', 'label_image']
def detect_primitives(cloud: typing.Any, normals: typing.Any, seed: typing.SupportsInt = 0, classes: collections.abc.Sequence[str] = ['plane', 'cylinder', 'sphere', 'torus'], epsilon: typing.SupportsFloat = 0.006, normal_deviation_deg: typing.SupportsFloat = 25.0, min_support: typing.SupportsInt = 250, min_support_torus: typing.SupportsInt = 80, max_primitives: typing.SupportsInt = 64, handles_near_cylinders: bool = True, roi: typing.Any = None, color: typing.Any = None, unfiltered: typing.Any = None, fit_along_rays: bool = True) -> list[...]:
    """
    Planes, cylinders, spheres and tori of an (H, W, 3) cloud with (H, W, 3) normals, largest first (mereo.knowledge.Segment objects; .pixels holds each one's inlier pixel indices). `unfiltered`: the (H, W, 3) points of the unfiltered depth when the cloud's was filtered; cylinders and spheres are then measured on them (smoothing flattens curved surfaces). `fit_along_rays`: cylinders and spheres fitted along the rays (depth noise lies along them), else by geometric distance.
    """
def label_image(segments: collections.abc.Sequence[...], rows: typing.SupportsInt, cols: typing.SupportsInt) -> numpy.typing.NDArray[numpy.int32]:
    """
    An (rows, cols) int32 image of the index of the segment owning each pixel (-1: none): the inlier masks.
    """
