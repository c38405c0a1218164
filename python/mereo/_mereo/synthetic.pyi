"""
The built-in tabletop scene renderer with exact ground truth.
"""
from __future__ import annotations
import mereo._mereo
import numpy
import numpy.typing
import typing
__all__: list[str] = ['GroundTruth', 'Scene', 'SceneOptions', 'SyntheticFrame', 'generate_scene', 'render', 'render_sequence', 'render_view']
class SceneOptions:
    """
    Options of the synthetic tabletop scene: SceneOptions(depth_model='stereo', ...) or attribute by attribute.
    
    Options (keyword arguments; mereo.options_of lists them):
        width (int, default 640, 1..8192): image width, pixels
        height (int, default 480, 1..8192): image height, pixels
        noise (bool, default true): depth (and colour) noise of the depth model; off: the exact depth
        depth_model (str, default kinect, one of kinect stereo): depth errors of a structured-light (Kinect) or an active-stereo (RealSense D4xx) camera
        distractors (bool, default false): handle-like tori beside some jars
        ambiguous_distractors (bool, default false): rings leaning on some jars (a mug's handle from some views)
        tapered_cups (bool, default false): one or two tapered cups (cone bodies, 4-10 degrees) join the objects
        handle_shapes (str, default torus, one of torus varied): mug handles: torus arcs, or also D-shaped, squared and flat-band ones
        lying_containers (bool, default false): one or two cans or jars lying on their side join the objects
        freeform_distractors (bool, default false): blobs, bananas, drills and rounded boxes join the objects (model 'other')
        room (bool, default false): a room with furniture (tables, chairs, a door, a cabinet) instead of a tabletop
        min_objects (int, default 3, 0..50): objects on the table (besides distractors), at least
        max_objects (int, default 6, 0..50): objects on the table (besides distractors), at most
        min_distance (float, default 0.6, 0.05..20): camera distance to the table centre, metres, at least
        max_distance (float, default 1.4, 0.05..20): camera distance to the table centre, metres, at most
        min_elevation_deg (float, default 25, 0..89): the camera looks down at least this much
        max_elevation_deg (float, default 60, 0..89): the camera looks down at most this much
        orbit_step_deg (float, default 6, -180..180): azimuth step per frame of a sequence
        stereo_baseline (float, default 0.05, 0.01..0.5): stereo baseline, metres
        stereo_patch_noise_px (float, default 0.14, 0..5): smooth disparity noise (std), pixels
        stereo_pixel_noise_px (float, default 0.07, 0..5): per-pixel disparity noise (std), pixels
        stereo_noise_patch (float, default 9, 1..100): size of the smooth noise's patches, pixels
        stereo_subpixel (float, default 32, 1..1024): disparity steps per pixel
        stereo_min_range (float, default 0.28, 0..10): no depth nearer than this, metres
        stereo_max_range (float, default 3, 0.1..100): no depth farther than this, metres
        stereo_fattening_px (float, default 4, 0..20): widest foreground strip over the background, pixels
        stereo_thin_px (float, default 4, 0..50): structures narrower than this lose their depth, pixels
        stereo_dark_albedo (float, default 0.1, 0..1): surfaces darker than this lose depth, luminance 0-1
    """
    intrinsics: mereo._mereo.Intrinsics
    def __init__(self, **kwargs) -> None:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def ambiguous_distractors(self) -> bool:
        """
        rings leaning on some jars (a mug's handle from some views)
        """
    @ambiguous_distractors.setter
    def ambiguous_distractors(self, arg1: typing.Any) -> None:
        ...
    @property
    def depth_model(self) -> str:
        """
        depth errors of a structured-light (Kinect) or an active-stereo (RealSense D4xx) camera
        """
    @depth_model.setter
    def depth_model(self, arg1: typing.Any) -> None:
        ...
    @property
    def distractors(self) -> bool:
        """
        handle-like tori beside some jars
        """
    @distractors.setter
    def distractors(self, arg1: typing.Any) -> None:
        ...
    @property
    def freeform_distractors(self) -> bool:
        """
        blobs, bananas, drills and rounded boxes join the objects (model 'other')
        """
    @freeform_distractors.setter
    def freeform_distractors(self, arg1: typing.Any) -> None:
        ...
    @property
    def handle_shapes(self) -> str:
        """
        mug handles: torus arcs, or also D-shaped, squared and flat-band ones
        """
    @handle_shapes.setter
    def handle_shapes(self, arg1: typing.Any) -> None:
        ...
    @property
    def height(self) -> int:
        """
        image height, pixels
        """
    @height.setter
    def height(self, arg1: typing.Any) -> None:
        ...
    @property
    def lying_containers(self) -> bool:
        """
        one or two cans or jars lying on their side join the objects
        """
    @lying_containers.setter
    def lying_containers(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_distance(self) -> float:
        """
        camera distance to the table centre, metres, at most
        """
    @max_distance.setter
    def max_distance(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_elevation_deg(self) -> float:
        """
        the camera looks down at most this much
        """
    @max_elevation_deg.setter
    def max_elevation_deg(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_objects(self) -> int:
        """
        objects on the table (besides distractors), at most
        """
    @max_objects.setter
    def max_objects(self, arg1: typing.Any) -> None:
        ...
    @property
    def min_distance(self) -> float:
        """
        camera distance to the table centre, metres, at least
        """
    @min_distance.setter
    def min_distance(self, arg1: typing.Any) -> None:
        ...
    @property
    def min_elevation_deg(self) -> float:
        """
        the camera looks down at least this much
        """
    @min_elevation_deg.setter
    def min_elevation_deg(self, arg1: typing.Any) -> None:
        ...
    @property
    def min_objects(self) -> int:
        """
        objects on the table (besides distractors), at least
        """
    @min_objects.setter
    def min_objects(self, arg1: typing.Any) -> None:
        ...
    @property
    def noise(self) -> bool:
        """
        depth (and colour) noise of the depth model; off: the exact depth
        """
    @noise.setter
    def noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def orbit_step_deg(self) -> float:
        """
        azimuth step per frame of a sequence
        """
    @orbit_step_deg.setter
    def orbit_step_deg(self, arg1: typing.Any) -> None:
        ...
    @property
    def room(self) -> bool:
        """
        a room with furniture (tables, chairs, a door, a cabinet) instead of a tabletop
        """
    @room.setter
    def room(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_baseline(self) -> float:
        """
        stereo baseline, metres
        """
    @stereo_baseline.setter
    def stereo_baseline(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_dark_albedo(self) -> float:
        """
        surfaces darker than this lose depth, luminance 0-1
        """
    @stereo_dark_albedo.setter
    def stereo_dark_albedo(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_fattening_px(self) -> float:
        """
        widest foreground strip over the background, pixels
        """
    @stereo_fattening_px.setter
    def stereo_fattening_px(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_max_range(self) -> float:
        """
        no depth farther than this, metres
        """
    @stereo_max_range.setter
    def stereo_max_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_min_range(self) -> float:
        """
        no depth nearer than this, metres
        """
    @stereo_min_range.setter
    def stereo_min_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_noise_patch(self) -> float:
        """
        size of the smooth noise's patches, pixels
        """
    @stereo_noise_patch.setter
    def stereo_noise_patch(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_patch_noise_px(self) -> float:
        """
        smooth disparity noise (std), pixels
        """
    @stereo_patch_noise_px.setter
    def stereo_patch_noise_px(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_pixel_noise_px(self) -> float:
        """
        per-pixel disparity noise (std), pixels
        """
    @stereo_pixel_noise_px.setter
    def stereo_pixel_noise_px(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_subpixel(self) -> float:
        """
        disparity steps per pixel
        """
    @stereo_subpixel.setter
    def stereo_subpixel(self, arg1: typing.Any) -> None:
        ...
    @property
    def stereo_thin_px(self) -> float:
        """
        structures narrower than this lose their depth, pixels
        """
    @stereo_thin_px.setter
    def stereo_thin_px(self, arg1: typing.Any) -> None:
        ...
    @property
    def tapered_cups(self) -> bool:
        """
        one or two tapered cups (cone bodies, 4-10 degrees) join the objects
        """
    @tapered_cups.setter
    def tapered_cups(self, arg1: typing.Any) -> None:
        ...
    @property
    def width(self) -> int:
        """
        image width, pixels
        """
    @width.setter
    def width(self, arg1: typing.Any) -> None:
        ...
class GroundTruth:
    """
    Exact ground truth: clean depth, analytic normals, object and part labels.
    """
    @property
    def camera_pose(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 4]"]:
        ...
    @property
    def depth(self) -> typing.Any:
        ...
    @property
    def normals(self) -> typing.Any:
        ...
    @property
    def objects(self) -> typing.Any:
        ...
    @property
    def parts(self) -> typing.Any:
        ...
class SyntheticFrame:
    """
    A rendered frame and its ground truth.
    """
    def truth_json(self) -> str:
        """
        Objects, parts (camera and world frames), intrinsics and pose as JSON text.
        """
    @property
    def frame(self) -> mereo._mereo.Frame:
        ...
    @property
    def truth(self) -> GroundTruth:
        ...
class Scene:
    """
    A generated scene (world frame: z up, origin at the table top centre).
    """
    @property
    def camera_distance(self) -> float:
        ...
    @property
    def camera_elevation_deg(self) -> float:
        ...
    @property
    def models(self) -> list[str]:
        ...
    @property
    def seed(self) -> int:
        ...
def generate_scene(seed: typing.SupportsInt, options: SceneOptions = ...) -> Scene:
    """
    The scene of `seed` (deterministic).
    """
def render(seed: typing.SupportsInt, options: SceneOptions = ...) -> SyntheticFrame:
    """
    Renders the first frame of the scene of `seed`.
    """
def render_sequence(seed: typing.SupportsInt, frames: typing.SupportsInt, options: SceneOptions = ...) -> list[SyntheticFrame]:
    """
    `frames` frames with the camera orbiting the table.
    """
def render_view(scene: Scene, index: typing.SupportsInt, options: SceneOptions = ...) -> SyntheticFrame:
    """
    Frame `index` of the camera's orbit around the table.
    """
