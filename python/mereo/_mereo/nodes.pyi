"""
Every registered node kind: mereo.nodes.<kind>(**options).
"""
from __future__ import annotations
import mereo._mereo
__all__: list = ['frame_source', 'filter_depth', 'back_project', 'estimate_normals', 'support_plane', 'detect_primitives', 'detect_edges', 'find_regions', 'detect_patches', 'detect_legs', 'models', 'match_models', 'interpret', 'odometry', 'track_objects', 'report']
def back_project(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frame's organized XYZ cloud (metres, camera frame, NaN where depth is missing).
    
    Inputs:
        frame (Frame): an RGB-D frame
    Outputs:
        cloud (Cloud): H x W x 3 points
    """
def detect_edges(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Lines and elliptical arcs of the frame's colour image, with their side colours; 3-D where the cloud has depth.
    
    Inputs:
        frame (Frame): a frame with a colour image
        cloud (Cloud, optional): its organized cloud: the lines and arcs are lifted to 3-D
    Outputs:
        segments (Segments): arcs, then lines (classes arc and line)
    Options:
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
def detect_legs(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Thin upright supports under the level patches (table and chair legs, an office chair's column), as cylinders.
    
    Inputs:
        cloud (Cloud): organized XYZ cloud
        plane (SupportPlane): the floor (heights above it)
        segments (Segments): the patches (detect_patches)
    Outputs:
        segments (Segments): the patches, then the legs (class cylinder)
    Options:
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
def detect_patches(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Bounded planar patches (floor, walls, table tops, seats, doors) by organized region growing.
    
    Inputs:
        cloud (Cloud): organized XYZ cloud
        normals (NormalMap): per-pixel normals
        plane (SupportPlane, optional): the floor: its normal is up (upright patches' rectangles)
        frame (Frame, optional): the frame of the cloud: the patches' colour
    Outputs:
        segments (Segments): the patches, largest first
    Options:
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
def detect_primitives(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    RANSAC planes, cylinders, spheres and tori (Schnabel et al. 2007, on the image grid), largest first.
    
    Inputs:
        cloud (Cloud): organized XYZ cloud
        normals (NormalMap): per-pixel normals
        roi (Mask, optional): only these pixels (e.g. above the table)
        plane (SupportPlane, optional): the support: upright bodies on it are also looked for without normals
        frame (Frame, optional): the frame of the cloud: the segments' colour, its camera's focal length
        unfiltered (Cloud, optional): the cloud before depth filtering: cylinders and spheres are measured on it
    Outputs:
        segments (Segments): the primitives with parameters and inlier pixels
    Options:
        seed (int, default 0, 0..1e+15): the only source of randomness
        classes (str, default plane,cylinder,torus,sphere): classes to look for
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
def estimate_normals(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Per-pixel unit normals (camera frame, towards the camera, NaN where undefined); windows never cross a depth jump.
    
    Inputs:
        cloud (Cloud): organized XYZ cloud
    Outputs:
        normals (NormalMap): H x W x 3 unit normals
    Options:
        method (str, default fast, one of fast covariance): fast: least-squares tangents; covariance: PCA through integral images
        window (int, default 5, 3..101): window side in pixels (odd)
        depth_change_factor (float, default 0.02, 0.0001..1): a depth jump larger than this times z breaks smoothing
        noise_depth (float, default 2, 0.1..100): metres: beyond it the jump threshold grows as z^2 (sensor noise)
        adaptive_window (bool, default true): covariance: the window shrinks with depth (constant metric size)
        reference_depth (float, default 1, 0.1..10): metres: depth at which the adaptive window equals `window`
    """
def filter_depth(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frame with its depth smoothed by an edge-preserving bilateral filter (depth jumps stay sharp).
    
    Inputs:
        frame (Frame): an RGB-D frame
    Outputs:
        frame (Frame): the same frame, depth (and its own cloud, if any) filtered
    Options:
        radius (int, default 2, 1..10): window half-size, pixels
        sigma_space (float, default 1.5, 0.1..20): spatial sigma, pixels
        sigma_depth (float, default 0.004, 1e-05..0.1): range sigma at 1 m, metres (grows with z^2)
        depth_change_factor (float, default 0.02, 0.0001..1): neighbours further than this times z are ignored
    """
def find_regions(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The unknown objects of an interpretation as free-form regions, appended to the segments.
    
    Inputs:
        cloud (Cloud): organized XYZ cloud
        plane (SupportPlane): the support plane
        segments (Segments): the primitives; the regions follow them
        objects (Interpretation): an interpretation whose unknown objects carry their regions
        frame (Frame, optional): the frame of the cloud: the regions' colour
    Outputs:
        segments (Segments): the primitives, then one segment of class region per unknown object
    Options:
        min_height (float, default 0.02, 0..10): least height of a region above the support, metres
        neck_share (float, default 0.166667, 0.01..1): the top share of the height measured for the neck
    """
def frame_source(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frames of the run (a recorded sequence or a live queue), one per run step.
    
    Outputs:
        frame (Frame): the RGB-D frame
    """
def interpret(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frame's interpretation: hypotheses accepted one per set of segments (most explaining first), then the alternatives they exclude.
    
    Inputs:
        lattice (Lattice): the hypotheses of match_models
        models (ModelSet): the models they were matched from (the models node)
        segments (Segments, optional): the segments (with cloud and plane: each object must explain its region)
        cloud (Cloud, optional): the frame's points
        plane (SupportPlane, optional): the support plane and its region of interest
        normals (NormalMap, optional): per-pixel normals: silhouettes separate unknown objects that touch
    Outputs:
        objects (Interpretation): the accepted objects, then the listed alternatives
    Options:
        min_score (float, default 0.5, 0..1): hypotheses below this score are not accepted
        min_posterior (float, default 0.5, 0..1): nor below this posterior
        list_score (float, default 0.3, 0..1): alternatives at or above this are listed
        min_coverage (float, default 0.5, 0..1): an object's parts' least share of its region
        min_surface_coverage (float, default 0.7, 0..1): ... or with the pixels near its parts' surfaces, this share
        min_free_form_coverage (float, default 0.9, 0..1): the least share of an object made of free-form regions
        depth_jump (float, default 0.02, 0.001..1): a depth step (times the depth) that separates regions
        reach (float, default 0.02, 0..1): a region's reach beyond its object's extent, metres
        surface_tolerance (float, default 0.006, 0..1): a region's pixels this near an object's part (metres at 1 m) are explained by it
        surface_residual_factor (float, default 3, 0..100): ... or this times the part's fit residual, where that is larger
        surface_normal_deg (float, default 45, 0..90): ... with normals within this of the part's (degrees)
        open_tops (bool, default true): a region's pixels seen through the opening of an upright cylinder among the parts are explained by it
        min_unknown_pixels (int, default 800, 0..1e+07): least pixels of an unknown object (0: none)
        max_grazing_deg (float, default 75, 0..90): with normals: pixels seen more obliquely join no unknown region
        one_per_place (bool, default false): hypotheses of one concept at the same place are one object
    """
def match_models(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Object hypotheses: concepts matched to the segments by branch and bound, with exclusion arcs.
    
    Inputs:
        segments (Segments): the frame's segments (camera frame)
        models (ModelSet): the knowledge base and the concepts to look for (the models node)
        frame (Frame, optional): the frame; with a pose, 'up' comes from it (else the camera's -y)
        plane (SupportPlane, optional): the support plane; its normal is 'up' (before the frame's pose)
    Outputs:
        lattice (Lattice): hypotheses (best first per concept) and exclusion arcs
    Options:
        best (int, default 10, 1..1000): hypotheses kept per concept
        min_score (float, default 0.05, 0..1): hypotheses below this score are dropped
    """
def models(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The object models (a knowledge base) and the concepts looked for; loaded once per run.
    
    Outputs:
        models (ModelSet): the knowledge base and the concepts looked for
    Options:
        models (str, default mug,cup,tapered_cup,pitcher,jar,can,bottle,plate,bowl): comma-separated concepts to look for
        file (str, default ): a YAML model file (empty: the shipped models)
    """
def odometry(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Camera poses from the frames (OpenCV RGB-D ICP odometry, frame to frame; the first frame is the world), corrected against the table and the upright cylinders (and handles) on it when those are connected.
    
    Inputs:
        frame (Frame): an RGB-D frame
        plane (SupportPlane, optional): the frame's table: the landmarks' plane (with segments)
        segments (Segments, optional): the frame's segments: its upright cylinders are landmarks
    Outputs:
        frame (Frame): the same frame with its estimated pose
    Options:
        replace (bool, default false): estimate even where the frame has a pose
        max_depth (float, default 4, 0.5..20): farther points are not used, metres
        max_jump (float, default 0.1, 0.001..100): a motion this far from the last one (metres) is a failed alignment: the last motion is taken
        max_turn_deg (float, default 10, 0.1..180): ... or turned this far from it, degrees
    """
def report(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frame's JSON result: its accepted objects and their alternatives (or its tracked objects), segments and support plane, and the scene relations between the objects (what each stands on).
    
    Inputs:
        frame (Frame): the frame (its id and source)
        segments (Segments): the frame's segments
        objects (Interpretation): the frame's interpretation (interpret)
        plane (SupportPlane, optional): the support plane, reported when given
        tracks (Tracks, optional): tracked objects (track_objects): reported instead of the frame's own
    Outputs:
        result (Text): the frame's result, one JSON object
    Options:
        track_probability (float, default 0.5, 0..1): with tracks: those at or above this are reported
    """
def support_plane(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The dominant horizontal plane under the objects (the table) and the mask of the points above it.
    
    Inputs:
        cloud (Cloud): organized XYZ cloud
        normals (NormalMap): per-pixel normals
        frame (Frame, optional): the frame; when it has a pose, gravity comes from it
    Outputs:
        plane (SupportPlane): normal, offset, polygon, inliers, world frame
        roi (Mask): pixels above the plane, inside its polygon
    Options:
        seed (int, default 0, 0..1e+15): random seed of the plane hypotheses
        epsilon (float, default 0.008, 0.0001..0.1): inlier distance at 1 m, metres
        min_inliers (int, default 2000, 10..1e+07): fewest points of the plane
        candidates (int, default 4, 1..50): distinct planes compared
        min_share (float, default 0.3, 0..1): a higher plane's least share of the heaviest plane's weight
        min_area (float, default 0.05, 0..100): a higher plane's least area, square metres
        prefer (str, default highest, one of highest lowest): of parallel planes a step apart: the highest (a table) or the lowest (a room's floor)
        min_height (float, default 0.006, 0..1): ROI: lowest height above the plane, metres
        max_height (float, default 0.4, 0.01..5): ROI: highest height above the plane, metres
        margin (float, default 0, -1..1): ROI: polygon shrunk by this, metres
        beyond_border (float, default 0.25, 0..5): ROI: reach beyond the polygon's edges on the image's border, metres
    """
def track_objects(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Object hypotheses tracked across frames (world frame): rescored per view, Kalman-refined, rejected when their parts drift apart; stable track ids.
    
    Inputs:
        frame (Frame): the frame; its pose (camera to world) places the hypotheses
        segments (Segments): the frame's segments
        objects (Interpretation): the frame's hypotheses, accepted or not (interpret)
    Outputs:
        tracks (Tracks): the live tracks, by id
    Options:
        max_distance (float, default 0.03, 0.001..1): association: body centres, metres
        max_radius_difference (float, default 0.01, 0.0001..10): association: body sizes (a radius; a patch's half length), metres
        part_tolerance (float, default 0.01, 0.001..1): a part stays put relative to its body
        visible_pixels (float, default 300, 1..1e+06): a missing part this large in the image (pixels, where the frame's depth shows its place) is a full contradiction
        max_handle_turn_deg (float, default 25, 0..90): the last views around a handle fitted together: a ring turned further from the body's axis is no handle
        max_missed (int, default 30, 1..100000): frames unseen before a track is dropped
        report (float, default 0.5, 0..1): probability at which a track is reported
    """
