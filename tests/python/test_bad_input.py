"""Every bad input of bad_inputs.CASES, through each front end (`mereo recognize`, the Python API,
`mereo-run`): one clear line that names the file or value (or, for valid but extreme data, a
result), never a crash, a traceback or a silent wrong answer."""
import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mereo
from bad_inputs import CASES, cli_args, make_base, one_line

ROOT = Path(__file__).resolve().parents[2]
MEREO_RUN = shutil.which("mereo-run") or str(Path(sys.executable).parent / "mereo-run")


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    root = tmp_path_factory.mktemp("bad")
    make_base(root / "base")
    return root


def _folder(base: Path, case) -> tuple[Path, list[str]]:
    d = base / case.name
    if d.exists():
        shutil.rmtree(d)
    d.mkdir()
    return d, case.make(d)


def _no_crash(run: subprocess.CompletedProcess, what: str):
    assert run.returncode >= 0, f"{what} died of signal {-run.returncode}:\n{run.stderr[-2000:]}"
    assert "Traceback" not in run.stderr, f"{what} printed a traceback:\n{run.stderr[-3000:]}"


def _check_results(case, results: list[dict], where: str):
    """A result case: every frame has a result; objects found, or an empty result whose warning
    matches."""
    assert results, f"{where}: no result"
    for r in results:
        if case.objects:
            assert any(o["accepted"] for o in r["objects"]), f"{where}: no object found: {r.get('warnings')}"
        else:
            assert not r["objects"] and any(re.search(case.message, w) for w in r.get("warnings", [])), \
                f"{where}: expected an empty result with a warning matching {case.message!r}, got {r}"


@pytest.mark.parametrize("case", [c for c in CASES if "cli" in c.front_ends], ids=lambda c: c.name)
def test_cli(base, case):
    d, inputs = _folder(base, case)
    run = subprocess.run([sys.executable, "-m", "mereo.cli", *cli_args(case, inputs, d)], capture_output=True,
                         text=True, cwd=d, timeout=300)
    _no_crash(run, "mereo recognize")
    if case.result:
        assert run.returncode == 0, run.stderr
        _check_results(case, [json.loads(line) for line in run.stdout.splitlines()], "mereo recognize")
        return
    # an error: exit status 2 with one "mereo: error:" line, or (a frame that could not be read,
    # the run goes on) exit status 1 with the frame's warning
    line = one_line(run.stderr, case.message)
    assert line, f"no line of stderr matches {case.message!r}:\n{run.stderr[-3000:]}"
    assert run.returncode in (1, 2), run.returncode
    assert line.startswith("mereo: error: " if run.returncode == 2 else "mereo: warning: frame "), line


@pytest.mark.parametrize("case", [c for c in CASES if "python" in c.front_ends], ids=lambda c: c.name)
def test_python_api(base, case, monkeypatch):
    d, inputs = _folder(base, case)
    monkeypatch.chdir(d)
    o = case.options
    try:
        seq = mereo.io.open(inputs, intrinsics=o.get("intrinsics"), depth_scale=o.get("depth_scale", 0.0))
        graph = mereo.tabletop_graph(models_file=str(d / o["models"]) if "models" in o else "",
                                     graph=str(d / o["graph"]) if "graph" in o else None)
        results = mereo.recognize_all(seq, graph=graph)
    except (mereo.InputError, mereo.GraphError, mereo.NodeError) as e:
        assert not case.result, f"valid but extreme data raised {e}"
        assert re.search(case.message, str(e)), f"{str(e)!r} does not match {case.message!r}"
        assert "\n" not in str(e)
        return
    if case.result:
        _check_results(case, results, "recognize_all")
    else:  # a frame that could not be read: an empty result whose warning names the file
        warnings = [w for r in results for w in r.get("warnings", [])]
        assert any(re.search(case.message, w) for w in warnings), f"{warnings} do not match {case.message!r}"


@pytest.mark.parametrize("case", [c for c in CASES if "mereo-run" in c.front_ends], ids=lambda c: c.name)
def test_mereo_run(base, case):
    d, inputs = _folder(base, case)
    o = case.options
    args = [MEREO_RUN, str(d / o["graph"]) if "graph" in o else str(ROOT / "graphs" / "tabletop.yaml"), *inputs,
            "--result", "result.result"]
    if "intrinsics" in o:
        args += ["--intrinsics", o["intrinsics"]]
    if "depth_scale" in o:
        args += ["--depth-scale", "nan" if math.isnan(o["depth_scale"]) else repr(o["depth_scale"])]
    run = subprocess.run(args, capture_output=True, text=True, errors="backslashreplace", cwd=d, timeout=300)
    _no_crash(run, "mereo-run")
    lines = [json.loads(line) for line in run.stdout.splitlines() if line.startswith("{")]
    if case.result:
        assert run.returncode == 0, run.stderr
        _check_results(case, [r for r in lines if "objects" in r] or [{"objects": [], "warnings": [
            r.get("error", "") for r in lines]}], "mereo-run")
        return
    errors = [r["error"] for r in lines if r.get("error")]
    if run.returncode == 2:  # the run could not start: one line
        assert one_line(run.stderr, "^mereo-run: error: .*" + case.message), run.stderr[-3000:]
    else:  # the frame failed, the run went on
        assert any(re.search(case.message, e) for e in errors), f"{errors} / {run.stderr[-2000:]}"


def test_evaluate_names_a_file_that_is_not_utf8_or_not_json(tmp_path):
    (tmp_path / "latin.jsonl").write_bytes(b'{"frame": "caf\xe9"}\n')
    (tmp_path / "junk.jsonl").write_text('{"frame": "0000", "objects": []}\nnonsense\n')
    (tmp_path / "ok.jsonl").write_text('{"frame": "0000", "objects": []}\n')
    (tmp_path / "0000_truth.json").write_bytes(b"\xff\xfe{}")
    for args, message in [(["latin.jsonl", "synthetic:0"], r"latin\.jsonl: not UTF-8 text \(byte 14: b'\\xe9'\)"),
                          (["junk.jsonl", "synthetic:0"], r"junk\.jsonl:2: not a JSON object"),
                          (["ok.jsonl", "0000_truth.json"], r"0000_truth\.json: not UTF-8 text \(byte 0")]:
        run = subprocess.run([sys.executable, "-m", "mereo.cli", "evaluate", *args], capture_output=True, text=True,
                             cwd=tmp_path)
        assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
        assert re.fullmatch(r"mereo: error: " + message + r".*\n", run.stderr), run.stderr


@pytest.mark.parametrize("args, message", [
    (["demo", "--seed", "-1"], r"argument --seed: invalid _seed value: '-1'"),
    (["render", "synthetic:0", "--frames", "-1", "--out", "r"], r"--frames -1: must be at least 1"),
    (["recognize", "synthetic:0", "--frames", "0"], r"synthetic:0: the number of frames must be at least 1"),
    (["recognize", "synthetic:0", "--depth-scale", "abc"], r"argument --depth-scale: invalid float value: 'abc'"),
])
def test_cli_option_values_are_one_line(tmp_path, args, message):
    run = subprocess.run([sys.executable, "-m", "mereo.cli", *args], capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert re.search(message, run.stderr.strip().splitlines()[-1]), run.stderr
