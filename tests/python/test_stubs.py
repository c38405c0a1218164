"""The shipped type stubs (python/mereo/_mereo/*.pyi, py.typed) name everything the extension
exports; regenerate them with scripts/stubs.sh after changing bindings."""
import ast
from pathlib import Path

import pytest

import mereo
from mereo import _mereo

STUBS = Path(__file__).resolve().parents[2] / "python" / "mereo" / "_mereo"


def stub_names(path: Path) -> set:
    tree = ast.parse(path.read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


# every submodule of the extension, so that a new one without a stub fails here
SUBMODULES = sorted(n for n in dir(_mereo) if isinstance(getattr(_mereo, n), type(_mereo)))


@pytest.mark.parametrize("module", [""] + SUBMODULES)
def test_stub_covers_module(module):
    mod = getattr(_mereo, module) if module else _mereo
    stub = STUBS / (f"{module}.pyi" if module else "__init__.pyi")
    assert stub.is_file(), f"{stub} missing: run scripts/stubs.sh"
    public = {n for n in dir(mod) if not n.startswith("_") and not isinstance(getattr(mod, n), type(_mereo))}
    missing = public - stub_names(stub)
    assert not missing, f"{stub.name} lacks {sorted(missing)}: run scripts/stubs.sh"


def test_py_typed_is_shipped():
    assert (Path(mereo.__file__).parent / "py.typed").is_file()
