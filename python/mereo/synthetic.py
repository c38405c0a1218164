"""The built-in tabletop scene renderer with exact ground truth."""
from ._mereo.synthetic import (
    GroundTruth,
    Scene,
    SceneOptions,
    SyntheticFrame,
    generate_scene,
    render,
    render_sequence,
    render_view,
)

__all__ = [
    "GroundTruth",
    "Scene",
    "SceneOptions",
    "SyntheticFrame",
    "generate_scene",
    "render",
    "render_sequence",
    "render_view",
]
