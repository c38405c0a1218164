"""Results of `mereo recognize` (JSON Lines, DESIGN.md's contract) as a pandas DataFrame and Parquet.

    df = mereo.results.to_dataframe("results.jsonl")     # one row per object
    mereo.results.to_parquet("results.jsonl", "results.parquet")

Columns: the frame's "source", "frame" (and "input", "index" from mereo.batch), the object's
"id", "model", "is_a" (the concepts the model specializes, nearest first, joined by "/"), "score",
"posterior", "accepted", "pose", "coverage", "track" where given, and per
part ROLE its parameters as "ROLE.NAME" (a vector as "ROLE.NAME[0]".. [2]); unknown objects' regions
as "region.NAME". A frame without objects gives no row. Needs pandas (pip install mereo[dask]).
"""
from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

__all__ = ["to_dataframe", "to_parquet", "rows"]

_FRAME_KEYS = ("source", "frame", "input", "index")
_OBJECT_KEYS = ("id", "model", "score", "posterior", "accepted", "pose", "coverage", "track", "rejected")


def _flatten(prefix: str, d: dict, row: dict) -> None:
    for k, v in d.items():
        if isinstance(v, (list, tuple)) and v and all(isinstance(x, (int, float)) for x in v) and len(v) <= 4:
            for i, x in enumerate(v):
                row[f"{prefix}.{k}[{i}]"] = x
        elif isinstance(v, (int, float, str, bool)) or v is None:
            row[f"{prefix}.{k}"] = v


def _results(source) -> Iterable[dict]:
    if isinstance(source, (str, Path)):
        from .evaluate import load_results

        return load_results(source)
    return source


def rows(results) -> list[dict]:
    """One flat dict per object of `results` (a JSON Lines path or an iterable of result dicts)."""
    out = []
    for r in _results(results):
        base = {k: r[k] for k in _FRAME_KEYS if k in r}
        for o in r.get("objects", []):
            row = dict(base)
            row.update({k: o[k] for k in _OBJECT_KEYS if k in o})
            if "is_a" in o:
                row["is_a"] = "/".join(o["is_a"])
            for role, part in (o.get("parts") or {}).items():
                _flatten(role, part, row)
            if "region" in o:
                _flatten("region", o["region"], row)
            out.append(row)
    return out


def to_dataframe(results):
    """A pandas DataFrame with one row per object (see the module's text)."""
    import pandas as pd

    return pd.DataFrame(rows(results))


def to_parquet(results, path: str | Path) -> None:
    """The DataFrame of `results` written as Parquet (pyarrow)."""
    to_dataframe(results).to_parquet(path, index=False)
