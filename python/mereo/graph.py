"""The dataflow engine: build graphs node by node or load them from graphs/*.yaml, run them
over frames in deterministic or parallel mode, inspect timings and traces.

    g = mereo.Graph()
    src = g.add("frame_source", "source")
    cloud = g.add(mereo.nodes.back_project(), "cloud")
    g.connect(src.frame, cloud.frame)
    results = g.run(mereo.io.open("synthetic:3", frames=10), mode="parallel")
"""
from __future__ import annotations

import shutil
import subprocess

from ._mereo import FrameQueue, Graph, GraphError, Node, NodeError, NodeTemplate, Port, node_doc

__all__ = ["FrameQueue", "Graph", "GraphError", "Node", "NodeError", "NodeTemplate", "Port", "dot_to_svg", "node_doc"]


def dot_to_svg(dot: str) -> str:
    """Renders graphviz text to SVG with the `dot` program (Debian's graphviz); Jupyter shows
    a Graph through this. Raises RuntimeError when graphviz is not installed."""
    exe = shutil.which("dot")
    if exe is None:
        raise RuntimeError("graphviz's `dot` is not installed (apt-get install graphviz)")
    return subprocess.run([exe, "-Tsvg"], input=dot, capture_output=True, text=True, check=True).stdout
