"""The renderer's options from Python and the command line (SceneOptions described once: the
same names, defaults and ranges everywhere), the new scenes (varied handles, lying cans and jars,
free-form distractors, the stereo depth model) as files, and their evaluation."""
import json
import subprocess
import sys

import numpy as np
import pytest

import mereo
from mereo import cli
from mereo import evaluate as ev

S = mereo.synthetic
NEW = dict(depth_model="stereo", handle_shapes="varied", lying_containers=True, freeform_distractors=True)


def test_scene_options_are_their_description():
    described = {o["name"]: o for o in mereo.options_of("SceneOptions")}
    assert mereo.options_of(S.SceneOptions) == mereo.options_of("SceneOptions")
    o = S.SceneOptions()
    for name, info in described.items():
        assert getattr(o, name) == info["default"], name
        assert f"    {name} (" in S.SceneOptions.__doc__, name
    assert {"depth_model", "handle_shapes", "lying_containers", "freeform_distractors", "stereo_baseline"} <= set(described)
    assert described["depth_model"]["choices"] == ["kinect", "stereo"]
    assert repr(o) == "SceneOptions()"
    o = S.SceneOptions(**NEW, stereo_min_range=0.3)
    assert o.depth_model == "stereo" and o.stereo_min_range == 0.3 and o.noise
    assert "depth_model='stereo'" in repr(o)
    with pytest.raises(mereo.InputError, match="depth_model"):
        o.depth_model = "tof"
    with pytest.raises(mereo.InputError, match="stereo_baseline"):
        S.SceneOptions(stereo_baseline=-1.0)
    with pytest.raises(TypeError, match="its options: width"):
        S.SceneOptions(handles="varied")


def test_every_scene_option_of_yes_or_no_or_a_choice_is_a_flag():
    parser = cli.build_parser()
    render = parser._subparsers._group_actions[0].choices["render"]
    flags = {a.dest: a for a in render._actions}
    for o in mereo.options_of("SceneOptions"):
        if o["type"] in ("bool", "str"):
            assert o["name"] in flags or o["name"] in cli._OWN_SCENE_FLAGS, o["name"]
    args = parser.parse_args(["render", "synthetic:1", "--out", "x", "--depth-model", "stereo", "--handle-shapes",
                              "varied", "--lying", "--freeform", "--leaning-distractors"])
    o = cli._scene_options(args)
    assert (o.depth_model, o.handle_shapes, o.lying_containers, o.freeform_distractors) == ("stereo", "varied", True, True)
    assert o.ambiguous_distractors and not o.distractors and o.noise


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    out = tmp_path_factory.mktemp("render")
    r = subprocess.run([sys.executable, "-m", "mereo.cli", "render", "synthetic:184", "--frames", "2", "--depth-model",
                        "stereo", "--handle-shapes", "varied", "--lying-containers", "--freeform-distractors",
                        "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return out


def test_cli_renders_the_new_scenes(rendered):
    truth = json.loads((rendered / "0000_truth.json").read_text())
    objects = truth["objects"]
    assert {o["kind"] for o in objects if o["model"] == "mug"} <= {"torus", "d", "squared", "band"}
    assert {p["class"] for o in objects if o["model"] == "mug" for p in o["parts"] if p["role"] == "handle"} & {"loop", "band"}
    assert any(o.get("pose") == "lying" for o in objects)
    assert all(o.get("pose") in ("lying", "upright") for o in objects if o["model"] in ("can", "jar"))
    others = [o for o in objects if o["model"] == "other"]
    assert others and all(o["kind"] in ("blob", "banana", "drill", "rounded_box") for o in others)
    assert all("visible_box" in o for o in objects if o["visible_pixels"] > 0)
    # the files hold the stereo model's depth: what the renderer gives for the same options
    frame = mereo.io.open(rendered)[0]
    sf = S.render(184, S.SceneOptions(**NEW))
    ok = np.isfinite(sf.frame.depth)
    assert np.array_equal(np.isfinite(frame.depth), ok)
    assert np.abs(frame.depth[ok] - sf.frame.depth[ok]).max() < 2e-4  # 1/5000 m in the PNG


def test_io_open_takes_the_scene_options():
    o = S.SceneOptions(**NEW)
    f = mereo.io.open("synthetic:184", frames=2, scene=o)[1]
    sf = S.render_view(S.generate_scene(184, o), 1, o)
    assert np.array_equal(f.depth, sf.frame.depth, equal_nan=True)
    # noise and distractors given as keywords override the scene's
    clean = mereo.io.read("synthetic:184", scene=o, noise=False)
    assert np.array_equal(clean.depth, S.render(184, S.SceneOptions(**NEW, noise=False)).truth.depth, equal_nan=True)
    default = mereo.io.read("synthetic:184")
    assert np.array_equal(default.depth, S.render(184).frame.depth, equal_nan=True)


def test_the_depth_models_differ_in_depth_only():
    k, s = S.render(184, S.SceneOptions(**dict(NEW, depth_model="kinect"))), S.render(184, S.SceneOptions(**NEW))
    assert np.array_equal(k.frame.color, s.frame.color)
    assert np.array_equal(k.truth.parts, s.truth.parts)
    assert not np.array_equal(k.frame.depth, s.frame.depth, equal_nan=True)
    near = np.isfinite(k.truth.depth) & (k.truth.depth < 1.0)
    err = (s.frame.depth - s.truth.depth)[near]
    assert 0.0005 < np.nanstd(err) < 0.01


def truth_answers(truths, other_too=False):
    """Perfect answers made from the ground truth; with other_too, a mug on each free-form distractor."""
    out = []
    for t in truths:
        objs = []
        for o in t["objects"]:
            body = [p for p in o["parts"] if p["role"] == "body" and p["class"] == "cylinder"]
            if body and o["model"] != "table":
                c = body[0]["camera"]
                objs.append({"model": o["model"], "parts": {"body": {"class": "cylinder", "point": c["point"],
                             "axis": c["axis"], "radius": c["radius"], "height": c["height"]}}})
            if other_too and o["model"] == "other" and o["visible_pixels"] > 0:
                box = o["visible_box"]
                centre = list((np.asarray(box["min"]) + np.asarray(box["max"])) / 2)
                objs.append({"model": "mug", "parts": {"body": {"class": "cylinder", "point": centre,
                             "axis": [0, -1, 0], "radius": 0.04, "height": 0.1}}})
        out.append({"objects": [dict(o, id=i, score=1.0, accepted=True) for i, o in enumerate(objs)]})
    return out


def test_evaluation_counts_results_on_free_form_distractors_and_recall_by_kind():
    o = S.SceneOptions(**NEW)
    truths = ev.load_truths(["synthetic:184:2", "synthetic:26"], o)
    assert len(truths) == 3
    others = sum(1 for t in truths for x in t["objects"] if x["model"] == "other" and x["visible_pixels"] > 0)
    assert others >= 3
    e = ev.evaluate(truth_answers(truths), truths)
    assert e.on_others == [0, 0, 0] and e.others == others
    summary = e.summary()
    assert summary["models"]["mug"]["precision"] == 1.0
    kinds = summary["kinds"]
    assert any(k.startswith("mug/") for k in kinds) and ("can/lying" in kinds or "jar/lying" in kinds)
    for name, k in summary["kinds"].items():
        assert k["recall"] == 1.0 or np.isnan(k["recall"]), name
    bad = ev.evaluate(truth_answers(truths, other_too=True), truths)
    assert sum(bad.on_others) == others and bad.on_others_per_frame == others / 3
    assert bad.summary()["models"]["mug"]["precision"] < 1.0
    assert any("free-form distractor" in m for m in bad.mistakes)
    table = ev.format_table(bad)
    assert "accepted objects on free-form distractors" in table and "recall by kind" in table


def test_cli_evaluate_with_scene_flags(tmp_path, capsys):
    o = S.SceneOptions(**NEW)
    truths = ev.load_truths(["synthetic:184:2"], o)
    results = tmp_path / "r.jsonl"
    results.write_text("".join(json.dumps(r) + "\n" for r in truth_answers(truths, other_too=True)))
    flags = ["--depth-model", "stereo", "--handle-shapes", "varied", "--lying-containers", "--freeform-distractors"]
    assert cli.main(["evaluate", str(results), "synthetic:184:2", *flags, "--json", str(tmp_path / "e.json")]) == 0
    out = capsys.readouterr().out
    assert "accepted objects on free-form distractors" in out
    figures = json.loads((tmp_path / "e.json").read_text())
    assert len(figures["on_others_by_frame"]) == 2 and figures["on_others"] >= 2
