"""The object layer: object models (concepts), segments and matching.

Models are YAML files (``graphs/models/``) or Python, and both load into the same C++
structures::

    import mereo
    kb = mereo.knowledge.load_models()                     # the shipped models
    kb.add(mereo.knowledge.concept(
        "teapot", parent="container",
        parts={"spout": "cylinder", "handle": ("torus", {"optional": True})},
        attributes={"body.radius": (0.05, 0.1, 0.01), "spout.radius": (0.005, 0.02)},
        constraints=[("near", "spout", "body", {"max": 0.02}),
                     ("handle_opposite", my_predicate, "handle", "spout")]))   # a Python predicate
    hyps, stats = mereo.knowledge.match(kb.resolve("teapot"), segments)
"""
from __future__ import annotations

from typing import Callable, Iterable, Mapping

from ._mereo.knowledge import (
    Attribute,
    Concept,
    Constraint,
    Context,
    Detail,
    Hypothesis,
    KnowledgeBase,
    Lattice,
    MatchStats,
    Membership,
    Modality,
    Part,
    Segment,
    builtin_models,
    match,
    primitive_classes,
    recognize,
    select,
)

__all__ = [
    "Attribute", "Concept", "Constraint", "Context", "Detail", "Hypothesis", "KnowledgeBase", "Lattice",
    "MatchStats", "Membership", "Modality", "Part", "Segment", "builtin_models", "concept", "load_models",
    "match", "primitive_classes", "recognize", "select",
]


def load_models(path: str | None = None) -> KnowledgeBase:
    """The shipped models, plus the concepts of a YAML model file if `path` is given (a file may
    specialize the shipped concepts). Mistakes raise InputError naming the file, line and field."""
    kb = builtin_models()
    if path is not None:
        kb.load(str(path))
    return kb


def _range(value) -> Membership:
    if isinstance(value, Membership):
        return value
    lo, hi, *margin = value
    return Membership.range(lo, hi, margin[0] if margin else 0.0)


def concept(name: str, parts: Mapping[str, object], *, parent: str = "", description: str = "",
            attributes: Mapping[str, object] | None = None, constraints: Iterable[tuple] = (),
            modalities: Mapping[str, Iterable[str]] | None = None, prior: float | None = None) -> Concept:
    """A concept from plain Python values.

    parts: role -> class, or role -> (class, {"optional": bool, "missing_score": float,
    "detail": "coarse" | "fine", "group": str}). attributes: "role.attribute" -> (lo, hi[, margin])
    or a Membership. constraints: (predicate, role, role[, {params}]) with a built-in predicate
    name, or (name, callable, role, role[, {params}]) with a Python predicate
    callable(segments, constraint, context) -> float in [0, 1].
    """
    c = Concept()
    c.name, c.parent, c.description = name, parent, description
    c.parts = []
    for role, spec in parts.items():
        cls, opts = (spec, {}) if isinstance(spec, str) else spec
        opts = dict(opts)
        if "detail" in opts:
            opts["detail"] = Detail.fine if opts["detail"] == "fine" else Detail.coarse
        c.parts = c.parts + [Part(role, cls, **opts)]
    c.attributes = [Attribute(*key.split(".", 1), _range(value)) for key, value in (attributes or {}).items()]
    made = []
    for spec in constraints:
        spec = list(spec)
        params = spec.pop() if isinstance(spec[-1], Mapping) else {}
        if len(spec) > 1 and callable(spec[1]):
            name_, fn, *roles = spec
            made.append(Constraint(name_, roles, dict(params), fn))
        else:
            pred, *roles = spec
            made.append(Constraint(pred, roles, dict(params)))
    c.constraints = made
    c.modalities = [Modality(k, list(v)) for k, v in (modalities or {}).items()]
    if prior is not None:
        c.prior = prior
    return c
