"""
Frame sources and writers (the hardware layer).
"""
from __future__ import annotations
import collections.abc
import mereo._mereo
import typing
__all__: list[str] = ['Sequence', 'colorize_depth', 'colorize_labels', 'colorize_normals', 'draw_objects', 'hstack', 'open', 'read', 'read_intrinsics', 'write_image', 'write_pcd', 'write_png_pair']
class Sequence:
    """
    Frames loaded lazily, in order: len(seq), seq[i], iteration.
    """
    def __getitem__(self: typing.Sequence, arg0: typing.SupportsInt) -> mereo._mereo.Frame:
        ...
    def __len__(self: typing.Sequence) -> int:
        ...
    @property
    def ids(self) -> list[str]:
        ...
    @property
    def sources(self) -> list[str]:
        ...
def colorize_depth(depth: typing.Any) -> typing.Any:
    """
    Depth (H, W) metres as an (H, W, 3) uint8 false-colour image.
    """
def colorize_labels(labels: typing.Any) -> typing.Any:
    """
    Integer labels (H, W) as distinct colours, 0 black.
    """
def colorize_normals(normals: typing.Any) -> typing.Any:
    """
    Normals (H, W, 3) as colours (n + 1) / 2, black where missing.
    """
def draw_objects(image: typing.Any, intrinsics: mereo._mereo.Intrinsics, objects: collections.abc.Sequence[tuple[str, collections.abc.Sequence[...]]], boxes: collections.abc.Sequence[tuple[str, typing.Annotated[collections.abc.Sequence[typing.SupportsInt], "FixedSize(4)"]]] = []) -> typing.Any:
    """
    The image with each (label, [Segment, ...]) drawn: projected part outlines and the label; each (label, (u0, v0, u1, v1)) of `boxes` (objects without parts: unknown ones) as a grey box.
    """
def hstack(images: collections.abc.Sequence[typing.Any], gap: typing.SupportsInt = 4) -> typing.Any:
    """
    RGB images side by side.
    """
def open(inputs: typing.Any, *, intrinsics: typing.Any = None, depth_scale: typing.SupportsFloat = 0.0, frames: typing.SupportsInt = 1, noise: typing.Any = None, distractors: typing.Any = None, scene: typing.Any = None, depth_format: str = 'units') -> typing.Sequence:
    """
    Opens files, folders or 'synthetic:SEED' as a Sequence. intrinsics: Intrinsics, 'fx,fy,cx,cy' or a JSON file (its "depth_camera": depth from a second camera, registered to the colour camera); depth_scale: depth units per metre (0 = the format's default); depth_format: 'units', or 'sun3d' / 'nyu-raw' for those datasets' 16-bit depth (the files do not say); frames, scene, noise, distractors: for synthetic:SEED (scene: a mereo.synthetic.SceneOptions; noise and distractors, when given, override its: distractors False, True or 'beside' for handle-like tori beside some jars, 'leaning' for rings leaning on jars).
    """
def read(input: typing.Any, *, intrinsics: typing.Any = None, depth_scale: typing.SupportsFloat = 0.0, noise: typing.Any = None, distractors: typing.Any = None, scene: typing.Any = None, depth_format: str = 'units') -> mereo._mereo.Frame:
    """
    The first frame of a .pcd file, a PNG pair, a folder, a TUM folder or 'synthetic:SEED'. intrinsics: Intrinsics, 'fx,fy,cx,cy' or a JSON file (its "depth_camera": depth from a second camera, registered to the colour camera); depth_scale: depth units per metre (0 = the format's default); depth_format: 'units', or 'sun3d' / 'nyu-raw' for those datasets' 16-bit depth (the files do not say); frames, scene, noise, distractors: for synthetic:SEED (scene: a mereo.synthetic.SceneOptions; noise and distractors, when given, override its: distractors False, True or 'beside' for handle-like tori beside some jars, 'leaning' for rings leaning on jars).
    """
def read_intrinsics(text_or_path: str) -> mereo._mereo.Intrinsics:
    ...
def write_image(path: typing.Any, image: typing.Any) -> None:
    """
    Writes an (H, W, 3) uint8 RGB image (PNG by extension).
    """
def write_pcd(path: typing.Any, frame: mereo._mereo.Frame) -> None:
    """
    Writes a binary-compressed organized PCD (xyz, rgba, label).
    """
def write_png_pair(dir: typing.Any, name: str, frame: mereo._mereo.Frame, depth_scale: typing.SupportsFloat = 1000.0) -> list[str]:
    """
    Writes DIR/NAME_rgb.png, DIR/NAME_depth.png (16-bit) and DIR/intrinsics.json.
    """
