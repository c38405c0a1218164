"""
Object models, segments and matching (the object layer).
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['Attribute', 'Concept', 'Constraint', 'Context', 'Detail', 'Hypothesis', 'KnowledgeBase', 'Lattice', 'MatchStats', 'Membership', 'Modality', 'Part', 'Segment', 'builtin_models', 'match', 'primitive_classes', 'recognize', 'select']
class Segment:
    """
    A primitive found in the data (a data instance): its class (one of the shape table's, mereo/shapes/) with that class's parameters (metres, camera frame, the JSON output's field names: a cylinder's point, axis, radius, height; a torus's center, normal, major_radius, minor_radius...), inliers, residual, colour. Segment('cylinder', point=..., axis=..., radius=..., height=...); a torus also takes point/axis/radius.
    """
    @staticmethod
    def from_dict(d: dict) -> Segment:
        """
        A segment from a part or primitive of a result (its "class" and fields).
        """
    def __getattr__(self, arg0: str) -> typing.Any:
        ...
    def __init__(self, cls: str, **kwargs) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def set(self, name: str, value: typing.Any) -> None:
        """
        Sets one of the class's parameters by its JSON name.
        """
    @property
    def bend(self) -> float:
        """
        how much an axial body bends along its axis, as its normals show (1 / m; 0: none)
        """
    @bend.setter
    def bend(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def cls(self) -> str:
        ...
    @property
    def end_closed(self) -> int:
        """
        pixels whose rays stop on the end facing the camera (a lid; cylinders, cones)
        """
    @end_closed.setter
    def end_closed(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def end_open(self) -> int:
        """
        pixels whose rays pass the end facing the camera into the body (an open vessel)
        """
    @end_open.setter
    def end_open(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def hue(self) -> float:
        ...
    @hue.setter
    def hue(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def id(self) -> int:
        ...
    @id.setter
    def id(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def inliers(self) -> int:
        ...
    @inliers.setter
    def inliers(self, arg0: typing.SupportsInt) -> None:
        ...
    @property
    def inward(self) -> bool:
        """
        seen from inside (a mug's inner wall)
        """
    @inward.setter
    def inward(self, arg0: bool) -> None:
        ...
    @property
    def mean_color(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def out_of_round(self) -> float:
        """
        how far an axial body's cross-section is from a circle (pattern RMS over radius; 0: none)
        """
    @out_of_round.setter
    def out_of_round(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def params(self) -> dict:
        """
        the class's parameters, by their JSON names
        """
    @property
    def pixels(self) -> numpy.typing.NDArray[numpy.int32]:
        """
        inlier pixel indices v * width + u (NumPy int32)
        """
    @property
    def residual(self) -> float:
        ...
    @residual.setter
    def residual(self, arg0: typing.SupportsFloat) -> None:
        ...
class Membership:
    """
    A trapezoidal fuzzy membership (a, b, c, d).
    """
    @staticmethod
    def at_least(zero: typing.SupportsFloat, full: typing.SupportsFloat) -> Membership:
        ...
    @staticmethod
    def at_most(full: typing.SupportsFloat, zero: typing.SupportsFloat) -> Membership:
        ...
    @staticmethod
    def range(lo: typing.SupportsFloat, hi: typing.SupportsFloat, margin: typing.SupportsFloat = 0.0) -> Membership:
        ...
    def __call__(self, x: typing.SupportsFloat) -> float:
        ...
    def __init__(self, arg0: typing.SupportsFloat, arg1: typing.SupportsFloat, arg2: typing.SupportsFloat, arg3: typing.SupportsFloat) -> None:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def a(self) -> float:
        ...
    @a.setter
    def a(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def b(self) -> float:
        ...
    @b.setter
    def b(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def c(self) -> float:
        ...
    @c.setter
    def c(self, arg0: typing.SupportsFloat) -> None:
        ...
    @property
    def d(self) -> float:
        ...
    @d.setter
    def d(self, arg0: typing.SupportsFloat) -> None:
        ...
class Detail:
    """
    Members:
    
      coarse
    
      fine
    """
    __members__: typing.ClassVar[dict[str, Detail]]
    coarse: typing.ClassVar[Detail]
    fine: typing.ClassVar[Detail]
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    def __init__(self, value: typing.SupportsInt) -> None:
        ...
    def __int__(self) -> int:
        ...
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: typing.SupportsInt) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class Part:
    """
    A part of a concept: a unique role and a class (a primitive or a concept).
    """
    cls: str
    detail: Detail
    group: str
    optional: bool
    role: str
    def __init__(self, role: str, cls: str, optional: bool = False, missing_score: typing.SupportsFloat = 0.5, detail: Detail = ..., group: str = '') -> None:
        ...
    @property
    def missing_score(self) -> float:
        ...
    @missing_score.setter
    def missing_score(self, arg0: typing.SupportsFloat) -> None:
        ...
class Attribute:
    """
    A fuzzy range over one attribute of one part.
    """
    name: str
    part: str
    range: Membership
    def __init__(self, part: str, name: str, range: Membership) -> None:
        ...
class Context:
    def __init__(self) -> None:
        ...
    @property
    def up(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @up.setter
    def up(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> None:
        ...
class Constraint:
    """
    A fuzzy relation between parts: a built-in predicate by name, or `custom`: a Python callable (segments, constraint, context) -> value in [0, 1].
    """
    predicate: str
    def __init__(self, predicate: str, parts: collections.abc.Sequence[str], params: collections.abc.Mapping[str, typing.SupportsFloat] = {}, custom: typing.Any = None) -> None:
        ...
    @property
    def params(self) -> dict[str, float]:
        ...
    @params.setter
    def params(self, arg0: collections.abc.Mapping[str, typing.SupportsFloat]) -> None:
        ...
    @property
    def parts(self) -> list[str]:
        ...
    @parts.setter
    def parts(self, arg0: collections.abc.Sequence[str]) -> None:
        ...
class Modality:
    name: str
    def __init__(self, name: str, parts: collections.abc.Sequence[str]) -> None:
        ...
    @property
    def parts(self) -> list[str]:
        ...
    @parts.setter
    def parts(self, arg0: collections.abc.Sequence[str]) -> None:
        ...
class Concept:
    """
    An object model: parts, attributes, constraints, modalities, a parent.
    """
    description: str
    name: str
    parent: str
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def attributes(self) -> list[Attribute]:
        ...
    @attributes.setter
    def attributes(self, arg0: collections.abc.Sequence[Attribute]) -> None:
        ...
    @property
    def constraints(self) -> list[Constraint]:
        ...
    @constraints.setter
    def constraints(self, arg0: collections.abc.Sequence[Constraint]) -> None:
        ...
    @property
    def modalities(self) -> list[Modality]:
        ...
    @modalities.setter
    def modalities(self, arg0: collections.abc.Sequence[Modality]) -> None:
        ...
    @property
    def parts(self) -> list[Part]:
        ...
    @parts.setter
    def parts(self, arg0: collections.abc.Sequence[Part]) -> None:
        ...
    @property
    def prior(self) -> float:
        ...
    @prior.setter
    def prior(self, arg1: typing.SupportsFloat) -> None:
        ...
class KnowledgeBase:
    """
    Concepts and their specialization links.
    """
    def __init__(self) -> None:
        ...
    def add(self, concept: Concept) -> None:
        ...
    def get(self, name: str) -> Concept:
        ...
    def has(self, name: str) -> bool:
        ...
    def is_a(self, cls: str, ancestor: str) -> bool:
        ...
    def load(self, path: str) -> None:
        """
        Adds the concepts of a YAML model file.
        """
    def names(self) -> list[str]:
        ...
    def parse(self, text: str, name: str = '<text>') -> None:
        ...
    def resolve(self, name: str) -> Concept:
        """
        The concept with what it inherits; raises InputError naming the origin and field of a mistake.
        """
    def validate(self) -> None:
        ...
class Hypothesis:
    """
    Segments assigned to a concept's parts (-1 = missing).
    """
    def __repr__(self) -> str:
        ...
    @property
    def assignment(self) -> list[int]:
        ...
    @property
    def children(self) -> list[Hypothesis]:
        """
        per part whose class is a concept: its sub-hypothesis
        """
    @property
    def concept(self) -> str:
        ...
    @property
    def modality(self) -> str:
        """
        the part set it was matched with ("" without alternatives)
        """
    @property
    def posterior(self) -> float:
        ...
    @property
    def score(self) -> float:
        ...
class MatchStats:
    @property
    def complete(self) -> int:
        ...
    @property
    def expanded(self) -> int:
        ...
    @property
    def pruned(self) -> int:
        ...
class Lattice:
    """
    Hypotheses and the exclusion arcs between those sharing a segment.
    """
    @property
    def excludes(self) -> list[tuple[int, int]]:
        ...
    @property
    def hypotheses(self) -> list[Hypothesis]:
        ...
    @property
    def same_place(self) -> list[tuple[int, int]]:
        ...
    @property
    def stats(self) -> MatchStats:
        ...
def builtin_models() -> KnowledgeBase:
    """
    The shipped models (graphs/models/*.yaml).
    """
def match(concept: Concept, segments: collections.abc.Sequence[Segment], up: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None, exhaustive: bool = False, kb: KnowledgeBase = None, support_d: typing.SupportsFloat = ..., **kwargs) -> tuple:
    """
    The N best hypotheses of a (resolved) concept and the search counters: (list, MatchStats). `kb` resolves parts whose class is a concept; `support_d` places the support surface (heights above it: up.dot(x) + support_d).
    
    Options (keyword arguments; mereo.options_of lists them):
        best (int, default 10, 1..1000): hypotheses kept per concept
        min_score (float, default 1e-06, 0..1): hypotheses below this score are dropped
    """
def primitive_classes() -> list[str]:
    """
    The shape table's classes, in its order.
    """
def recognize(kb: KnowledgeBase, concepts: collections.abc.Sequence[str], segments: collections.abc.Sequence[Segment], up: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None, support_d: typing.SupportsFloat = ..., **kwargs) -> Lattice:
    """
    Every concept matched (in parallel): the lattice of hypotheses; `support_d` places the support surface (heights above it: up.dot(x) + support_d).
    
    Options (keyword arguments; mereo.options_of lists them):
        best (int, default 10, 1..1000): hypotheses kept per concept
        min_score (float, default 1e-06, 0..1): hypotheses below this score are dropped
    """
def select(concept: Concept, modality: str = '', detail: Detail = ...) -> Concept:
    """
    One modality's parts at one level of detail, with their attributes and constraints.
    """
