"""tests/bench/eval_cameras.py --ransac-seeds: the seed reaches the primitives' RANSAC (other
primitives come out), and the summary gives a line per seed and the mean and range; --set reaches
the graph's nodes."""
import importlib.util

import pytest

from conftest import ROOT


def _eval_cameras():
    spec = importlib.util.spec_from_file_location("eval_cameras", ROOT / "tests" / "bench" / "eval_cameras.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_ransac_seed_changes_the_primitives():
    import mereo

    so = mereo.synthetic.SceneOptions()
    so.depth_model = "stereo"
    frame = mereo.io.read("synthetic:7000", scene=so)
    fits = []
    for k in (0, 1):
        g = mereo.tabletop_graph()
        g.set_options("primitives", seed=k)
        r = mereo.recognize_all([frame], graph=g)[0]
        fits.append(sorted((p["class"], p["inliers"]) for p in r["primitives"]))
    assert fits[0] != fits[1]


def test_a_line_per_seed_then_mean_and_range(capsys):
    assert _eval_cameras().main(["--first", "7000", "--frames", "2", "--depth-model", "stereo",
                                 "--ransac-seeds", "0", "1"]) == 0
    out = capsys.readouterr().out
    assert out.count("RANSAC seed ") == 2
    for name in ("mug recall", "mug precision", "distractors per frame"):
        assert f"{name}: mean " in out and "over 2 seeds" in out


def test_set_changes_the_shipped_graphs_options(capsys):
    """--set NODE.OPTION=VALUE reaches the graph: handles from the depth's surfaces alone give no
    handle the colour image found (one frame whose mug's handle only the colour image shows), and
    a malformed or unknown option is an error."""
    args = ["--first", "4490", "--frames", "1", "--depth-model", "stereo"]
    assert _eval_cameras().main(args) == 0
    both = capsys.readouterr().out
    assert _eval_cameras().main(args + ["--set", "primitives.handles_from_colour=false",
                                        "primitives.handles_from_edges=false"]) == 0
    surfaces = capsys.readouterr().out
    recall = lambda out: [l.split()[4] for l in out.splitlines() if l.startswith("mug ")][0]
    assert float(recall(surfaces)) < float(recall(both)), (both, surfaces)
    with pytest.raises(SystemExit):
        _eval_cameras().main(args + ["--set", "handles_from_colour"])
    with pytest.raises(Exception):
        _eval_cameras().main(args + ["--set", "primitives.no_such_option=1"])
