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
    Options of the synthetic tabletop scene.
    """
    ambiguous_distractors: bool
    distractors: bool
    intrinsics: mereo._mereo.Intrinsics
    noise: bool
    def __init__(self) -> None:
        ...
    @property
    def height(self) -> int:
        ...
    @height.setter
    def height(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def max_distance(self) -> float:
        ...
    @max_distance.setter
    def max_distance(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def max_elevation_deg(self) -> float:
        ...
    @max_elevation_deg.setter
    def max_elevation_deg(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def max_objects(self) -> int:
        ...
    @max_objects.setter
    def max_objects(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def min_distance(self) -> float:
        ...
    @min_distance.setter
    def min_distance(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def min_elevation_deg(self) -> float:
        ...
    @min_elevation_deg.setter
    def min_elevation_deg(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def min_objects(self) -> int:
        ...
    @min_objects.setter
    def min_objects(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def orbit_step_deg(self) -> float:
        ...
    @orbit_step_deg.setter
    def orbit_step_deg(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def tapered_cups(self) -> bool:
        """
        one or two tapered cups (cone bodies, 4-10 degrees) join the objects
        """
    @tapered_cups.setter
    def tapered_cups(self, arg0: bool) -> None:
        ...
    @property
    def width(self) -> int:
        ...
    @width.setter
    def width(self, arg0: typing.SupportsInt) -> None:
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
