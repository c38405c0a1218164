"""Atheris target over mereo's Python front end: the readers as Python calls them.

The first byte picks the reader, the rest is its input, passed on as bytes (so that any byte,
valid UTF-8 or not, reaches the C++ side and may come back in an error message):
  0  a PCD file: mereo.io.read(path of a .pcd file holding the bytes)
  1  a model file: mereo.knowledge.KnowledgeBase().parse(bytes, "fuzz.yaml")
  2  a graph file: mereo.Graph.parse(bytes, "graphs/fuzz.yaml")
The contract: each call returns or raises mereo.InputError (or mereo.GraphError for graphs).
Any other exception (a UnicodeDecodeError from a message that is not UTF-8, SystemError...)
escapes and atheris saves the input as a crash.

  python tests/fuzz/fuzz_python.py tests/fuzz/corpus/python -max_total_time=60 -rss_limit_mb=2048
(needs mereo built and `pip install atheris==3.0.0` in the same environment)
"""
import os
import pathlib
import sys
import tempfile

import atheris

with atheris.instrument_imports():
    import mereo

GRAPHS = pathlib.Path(__file__).resolve().parents[2] / "graphs"
# libFuzzer ends the process with exit(), past Python's cleanup: one file per process, removed
# after each call, in a folder shared by all runs
SCRATCH = pathlib.Path(tempfile.gettempdir()) / "mereo_pyfuzz"
PCD = SCRATCH / f"input_{os.getpid()}.pcd"


def read_pcd(payload: bytes) -> None:
    SCRATCH.mkdir(exist_ok=True)
    PCD.write_bytes(payload)
    try:
        mereo.io.read(str(PCD))
    except mereo.InputError:
        pass
    finally:
        PCD.unlink()


def parse_models(payload: bytes) -> None:
    try:
        mereo.knowledge.KnowledgeBase().parse(payload, "fuzz.yaml")
    except mereo.InputError:
        pass


def parse_graph(payload: bytes) -> None:
    try:
        mereo.Graph.parse(payload, str(GRAPHS / "fuzz.yaml"))
    except (mereo.GraphError, mereo.InputError):
        pass


READERS = (read_pcd, parse_models, parse_graph)


def test_one_input(data: bytes) -> None:
    if not data:
        return
    READERS[data[0] % len(READERS)](data[1:])


def main() -> None:
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
