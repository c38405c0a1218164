"""
mereo's C++ core; import the names from the mereo package instead.
"""
from __future__ import annotations
import collections.abc
import typing
from . import io
from . import signal
from . import extension
from . import synthetic
from . import features
from . import knowledge
from . import nodes
from . import _testing
__all__: list[str] = ['Frame', 'FrameQueue', 'Graph', 'GraphError', 'InputError', 'Intrinsics', 'Node', 'NodeError', 'NodeTemplate', 'Port', 'extension', 'features', 'io', 'knowledge', 'node_doc', 'nodes', 'options_of', 'signal', 'synthetic']
class InputError(ValueError):
    pass
class Intrinsics:
    """
    Pinhole intrinsics in pixels: u = fx x/z + cx, v = fy y/z + cy.
    """
    __hash__: typing.ClassVar[None] = None
    @staticmethod
    def parse(text: str) -> Intrinsics:
        """
        From 'fx,fy,cx,cy'.
        """
    def __eq__(self, arg0: Intrinsics) -> bool:
        ...
    @typing.overload
    def __init__(self) -> None:
        ...
    @typing.overload
    def __init__(self, fx: typing.SupportsFloat, fy: typing.SupportsFloat, cx: typing.SupportsFloat, cy: typing.SupportsFloat) -> None:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def cx(self) -> float:
        ...
    @cx.setter
    def cx(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def cy(self) -> float:
        ...
    @cy.setter
    def cy(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def fx(self) -> float:
        ...
    @fx.setter
    def fx(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def fy(self) -> float:
        ...
    @fy.setter
    def fy(self, arg0: typing.SupportsFloat) -> None:
        ...
class Frame:
    """
    An RGB-D frame. color (H,W,3) uint8 RGB, depth (H,W) float32 metres with NaN where missing, cloud (H,W,3) float32 XYZ; the arrays share memory with the frame.
    """
    cloud: typing.Any
    color: typing.Any
    depth: typing.Any
    id: str
    intrinsics: Intrinsics
    labels: typing.Any
    source: str
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def _buffer_address(self, arg0: str) -> int:
        """
        Address of an image's C++ buffer (for tests of zero-copy sharing).
        """
    def validate(self) -> None:
        """
        Raises ValueError if the images disagree in size.
        """
    @property
    def gravity_aligned(self) -> bool:
        """
        The pose's world z points against gravity (False for 7-Scenes/3DMatch poses: the support plane then finds 'up' from the data).
        """
    @gravity_aligned.setter
    def gravity_aligned(self, arg0: bool) -> None:
        ...
    @property
    def pose(self) -> typing.Any:
        """
        Camera-to-world 4x4 matrix, or None.
        """
    @pose.setter
    def pose(self, arg1: typing.Any) -> None:
        ...
    @property
    def shape(self) -> tuple:
        ...
    @property
    def timestamp(self) -> float:
        ...
    @timestamp.setter
    def timestamp(self, arg0: typing.SupportsFloat) -> None:
        ...
class GraphError(ValueError):
    pass
class NodeError(RuntimeError):
    pass
class Port:
    """
    A node's port in a graph: pass it to Graph.connect.
    """
    def __repr__(self) -> str:
        ...
    @property
    def node(self) -> str:
        ...
    @property
    def port(self) -> str:
        ...
class Node:
    """
    A node in a graph; its ports are attributes (node.cloud).
    """
    def __getattr__(self, arg0: str) -> Port:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def inputs(self) -> list[str]:
        ...
    @property
    def kind(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def outputs(self) -> list[str]:
        ...
class NodeTemplate:
    """
    A node kind with option values, made by mereo.nodes.<kind>(...).
    """
    def __repr__(self) -> str:
        ...
    @property
    def kind(self) -> str:
        ...
class FrameQueue:
    """
    A live source: push frames from any thread while a graph runs; overflow is 'block', 'drop_oldest' or 'keep_latest'.
    """
    def __init__(self, capacity: typing.SupportsInt = 2, overflow: str = 'block') -> None:
        ...
    def close(self) -> None:
        ...
    def push(self, frame: Frame) -> bool:
        ...
    @property
    def dropped(self) -> int:
        ...
    @property
    def pushed(self) -> int:
        ...
class Graph:
    """
    A dataflow graph: add nodes, connect ports, verify, run over frames (deterministic or parallel).
    """
    @staticmethod
    def load(path: typing.Any) -> Graph:
        """
        Loads a YAML graph file (errors name the file and line).
        """
    @staticmethod
    def parse(text: str, file_name: str = '<text>') -> Graph:
        ...
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def _repr_svg_(self) -> typing.Any:
        ...
    def add(self, kind: typing.Any, name: str | None = None, **kwargs) -> Node:
        """
        Adds a node: g.add('estimate_normals', 'normals', window=7) or g.add(mereo.nodes.estimate_normals(window=7), 'normals').
        """
    def add_python(self, fn: collections.abc.Callable, name: str, inputs: collections.abc.Sequence[tuple[str, str]], outputs: collections.abc.Sequence[tuple[str, str]], doc: str = '') -> Node:
        """
        Adds a Python callable as a node (for experiments; it runs serially with the GIL). inputs and outputs are lists of (port, type) pairs; fn gets the inputs as keyword arguments and returns its output (or a dict of outputs).
        """
    def connect(self, source: typing.Any, target: typing.Any) -> None:
        """
        Connects an output port to an input port ('a.out' or a.out).
        """
    def node(self, name: str) -> Node:
        ...
    def run(self, source: typing.Any, *, mode: str = 'deterministic', max_in_flight: typing.SupportsInt = 4, on_error: str = 'stop', keep: collections.abc.Sequence[str] = [], trace: bool = False, on_result: typing.Any = None) -> list:
        """
        Runs the graph over a source (a Sequence from mereo.io.open, a path or 'synthetic:N', a list of Frames, or a FrameQueue). Returns a list of {'index', 'frame', 'outputs', 'error'} in frame order, or calls on_result(result) for each instead. The GIL is released while it runs.
        """
    def save(self, path: typing.Any) -> None:
        ...
    def set_options(self, name: str, **kwargs) -> None:
        """
        Changes options of a node: g.set_options('objects', models='mug').
        """
    def set_overflow(self, policy: str, capacity: typing.SupportsInt = 2) -> None:
        ...
    def summary(self) -> dict:
        ...
    def timings(self) -> list:
        """
        Per-node timing statistics of the last run (count, mean, median, max, total ms).
        """
    def to_dot(self) -> str:
        """
        The graph in graphviz's dot language.
        """
    def to_yaml(self) -> str:
        ...
    def trace_json(self) -> str:
        """
        The last run's Chrome trace (run with trace=True).
        """
    def verify(self) -> None:
        """
        Checks ports, types, required inputs, options and cycles.
        """
    def write_trace(self, path: typing.Any) -> None:
        """
        Writes the Chrome trace (open it in chrome://tracing or Perfetto).
        """
    @property
    def edges(self) -> list[tuple[str, str]]:
        ...
    @property
    def nodes(self) -> list[Node]:
        ...
def node_doc(kind: str) -> str:
    """
    The doc, ports and options of a node kind.
    """
def options_of(what: typing.Any) -> list:
    """
    The options of an options struct ('DetectOptions'), a function that takes keyword options (mereo.features.detect_primitives) or a node kind ('detect_primitives', mereo.nodes.detect_primitives): a list of {'name', 'type', 'default', 'min', 'max', 'choices', 'doc'}.
    """
__version__: str = '0.1.0'
