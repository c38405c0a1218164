"""
RANSAC primitives of organized clouds (the feature layer).
"""
from __future__ import annotations
import collections.abc
import mereo._mereo
import numpy
import numpy.typing
import typing
__all__: list[str] = ['detect_edge_primitives', 'detect_primitives', 'find_legs', 'label_image', 'planar_patches']
@typing.overload
def detect_edge_primitives(frame: mereo._mereo.Frame, **kwargs) -> list[...]:
    """
    Lines and elliptical arcs of a frame's colour image (mereo.knowledge.Segment objects of class line and arc: pixel coordinates, the colours on both sides, and where the depth allows the 3-D segment or circle; .pixels holds each one's edge pixels). Also takes an (H, W, 3) uint8 colour array and an optional (H, W, 3) cloud.
    
    Options (keyword arguments; mereo.options_of lists them):
        method (str, default canny, one of canny edge_drawing): where the edge chains come from: Canny's edges linked here, or Edge Drawing's
        gradient_threshold (int, default 24, 1..1020): least gradient magnitude of an edge pixel
        texture_factor (float, default 2.5, 0..100): the threshold rises to this times the median gradient
        anchor_threshold (int, default 8, 0..255): Edge Drawing: how much an anchor exceeds its neighbours
        sigma (float, default 1, 0.3..10): Gaussian smoothing before the gradient, pixels
        min_chain_px (int, default 12, 2..100000): shortest edge chain kept, pixels
        subpixel (bool, default true): refine points to the gradient's sub-pixel peak across the edge
        split_tolerance_px (float, default 1, 0.1..20): a straight piece's distance to its chord, px
        min_line_px (float, default 15, 2..100000): shortest line, pixels
        arc_tolerance_px (float, default 0.7, 0.05..20): RMS distance of an arc's points to its ellipse, px
        max_arc_error_px (float, default 2, 0.1..50): largest distance of an arc's points to its ellipse, px
        min_arc_span_deg (float, default 60, 1..360): least share of its ellipse an arc covers, degrees
        max_turn_deg (float, default 60, 1..179): largest turn between an arc's consecutive pieces, degrees
        min_minor_px (float, default 3, 0.5..10000): an arc's ellipse's least semi-axis, pixels
        side_offset_px (float, default 3, 1..50): distance of the side colour samples from the edge, px
        lift (bool, default true): fit 3-D lines and circles where the frame has depth
        lift_window_px (int, default 2, 0..10): half-size of the window a pixel takes its depth from
        lift_tolerance (float, default 0.01, 0.0001..1): RMS about a lifted fit, metres at 1 m (grows with z)
    """
@typing.overload
def detect_edge_primitives(color: typing.Any, cloud: typing.Any = None, **kwargs) -> list[...]:
    """
    Lines and elliptical arcs of a frame's colour image (mereo.knowledge.Segment objects of class line and arc: pixel coordinates, the colours on both sides, and where the depth allows the 3-D segment or circle; .pixels holds each one's edge pixels). Also takes an (H, W, 3) uint8 colour array and an optional (H, W, 3) cloud.
    
    Options (keyword arguments; mereo.options_of lists them):
        method (str, default canny, one of canny edge_drawing): where the edge chains come from: Canny's edges linked here, or Edge Drawing's
        gradient_threshold (int, default 24, 1..1020): least gradient magnitude of an edge pixel
        texture_factor (float, default 2.5, 0..100): the threshold rises to this times the median gradient
        anchor_threshold (int, default 8, 0..255): Edge Drawing: how much an anchor exceeds its neighbours
        sigma (float, default 1, 0.3..10): Gaussian smoothing before the gradient, pixels
        min_chain_px (int, default 12, 2..100000): shortest edge chain kept, pixels
        subpixel (bool, default true): refine points to the gradient's sub-pixel peak across the edge
        split_tolerance_px (float, default 1, 0.1..20): a straight piece's distance to its chord, px
        min_line_px (float, default 15, 2..100000): shortest line, pixels
        arc_tolerance_px (float, default 0.7, 0.05..20): RMS distance of an arc's points to its ellipse, px
        max_arc_error_px (float, default 2, 0.1..50): largest distance of an arc's points to its ellipse, px
        min_arc_span_deg (float, default 60, 1..360): least share of its ellipse an arc covers, degrees
        max_turn_deg (float, default 60, 1..179): largest turn between an arc's consecutive pieces, degrees
        min_minor_px (float, default 3, 0.5..10000): an arc's ellipse's least semi-axis, pixels
        side_offset_px (float, default 3, 1..50): distance of the side colour samples from the edge, px
        lift (bool, default true): fit 3-D lines and circles where the frame has depth
        lift_window_px (int, default 2, 0..10): half-size of the window a pixel takes its depth from
        lift_tolerance (float, default 0.01, 0.0001..1): RMS about a lifted fit, metres at 1 m (grows with z)
    """
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
        handles_from_edges (bool, default true): where neither the depth nor the silhouette shows a handle, look for its outline among the colour image's edges
        max_handle_turn_deg (float, default 25, 0..90): a ring that fits better turned more than this from its body's axis is not a handle (90: no check)
    """
def find_legs(cloud: typing.Any, segments: collections.abc.Sequence[...], up: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], floor_d: typing.SupportsFloat, **kwargs) -> list[...]:
    """
    The legs under the level patches among `segments` (planar_patches) of an (H, W, 3) cloud: thin upright supports as segments of class cylinder (axis up). `up`, `floor_d`: the floor's normal and offset (up . x + floor_d is a point's height above it).
    
    Options (keyword arguments; mereo.options_of lists them):
        min_top (float, default 0.25, 0..10): lowest level patch looked under, metres above the floor
        max_top (float, default 1.2, 0..10): highest level patch looked under, metres above the floor
        max_tilt_deg (float, default 12, 0..90): a level patch's normal to up, degrees
        margin (float, default 0.06, 0..1): how far beyond the patch's rectangle a leg may stand, metres
        cell (float, default 0.03, 0.005..0.5): the horizontal grid's cell, metres
        floor_clear (float, default 0.1, 0..1): points lower than this above the floor are not looked at, metres
        top_clear (float, default 0.1, 0..1): nor those within this of the patch's height, metres
        max_width (float, default 0.18, 0.01..1): widest leg, metres
        min_span (float, default 0.5, 0..1): least share of the height under the patch a leg spans
        reach (float, default 0.2, 0..1): a leg's top lies within this of the patch, metres
        min_points (int, default 12, 1..1e+06): fewest points of a leg
        step (int, default 1, 1..16): pixel step of the scan
    """
def label_image(segments: collections.abc.Sequence[...], rows: typing.SupportsInt, cols: typing.SupportsInt) -> numpy.typing.NDArray[numpy.int32]:
    """
    An (rows, cols) int32 image of the index of the segment owning each pixel (-1: none): the inlier masks.
    """
def planar_patches(cloud: typing.Any, normals: typing.Any, up: typing.Any = None, color: typing.Any = None, **kwargs) -> list[...]:
    """
    Bounded planar patches of an (H, W, 3) cloud with (H, W, 3) normals, largest first (mereo.knowledge.Segment objects of class patch; .pixels holds each one's pixels). `up`: the direction against gravity in the camera frame (upright patches then have a horizontal u_axis).
    
    Options (keyword arguments; mereo.options_of lists them):
        step (int, default 2, 1..16): grid step of the region growing, pixels
        epsilon (float, default 0.012, 0.0001..0.5): a point's distance to its patch's plane at 1 m, metres
        max_angle_deg (float, default 20, 1..90): a point's normal to its patch's, degrees
        depth_jump (float, default 0.04, 0.001..1): a depth step between neighbours (times the depth) that parts patches
        min_area (float, default 0.02, 0..10000): least area of a patch, square metres
        min_pixels (int, default 300, 1..1e+07): fewest pixels of a patch
        upright_deg (float, default 30, 0..90): with gravity: patches this close to upright get a horizontal u_axis
        max_depth (float, default 6, 0.1..100): patches whose median depth is beyond this are none, metres
        rim (int, default 8, 0..64): pixels beside a patch, this far out, join the nearest plane (the normals' rim); 0: off
        colour_edge (float, default 0.15, 0..2): with colour: growth does not cross a colour step larger than this (0: off)
        level_deg (float, default 30, 0..90): with gravity: level patches take cells whose normals lean at most this from up
        level_min_width (float, default 0.1, 0..10): level regions narrower than this are bands across upright surfaces, metres
    """
