"""Recognition on labelled real frames (tests/bench/eval_real.py's judgement): what holds today
must keep holding. The figures themselves are the benchmark's to print."""
import importlib.util

import numpy as np
import pytest

from conftest import ROOT


def _eval_real():
    spec = importlib.util.spec_from_file_location("eval_real", ROOT / "tests" / "bench" / "eval_real.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("name", ["red_mug", "white_mug", "white_bowl", "green_bowl", "cylinder"])
def test_realsense_frames_report_their_object_on_its_mask(real, name):
    """red_mug: a mug whose handle (a thick D-shaped ring, not a torus) lies on the mug's mask."""
    import mereo
    from PIL import Image

    ev = _eval_real()
    base = real / "nv-6dof-graspnet" / name
    frame = mereo.io.read(str(base) + "-depth.png")
    result, labels = ev.run(frame)
    mask = np.asarray(Image.open(str(base) + "-mask.png").convert("L")) > 0
    ok, text = ev.eval_nv(name, result, labels, mask)
    assert ok, f"{name}: {text}"


def test_desk_found_over_a_larger_carpet_and_its_objects_recognized(real):
    """posecnn 000003: a school desk over a carpet that fills more of the view; its bowl and soup
    can are found on their labels (before: the carpet, then no support at all)."""
    import json

    import mereo

    ev = _eval_real()
    truth = json.loads((real / "posecnn" / "labels.json").read_text())["frames"]["000003"]
    frame = mereo.io.read(str(real / "posecnn" / "000003-depth.png"), **ev.POSECNN)
    result, labels = ev.run(frame)
    assert not result.get("warnings"), result.get("warnings")
    found = {truth[i]["class"] for o, i, _ in ev.match_posecnn(result, labels, truth)
             if i is not None and truth[i]["class"] in ev.COMPATIBLE.get(o["model"], set())}
    assert {"bowl", "can"} <= found, found


def test_a_pitcher_is_a_tall_body_with_a_handle(real):
    """posecnn 000004: the lidded pitcher's body (12 cm across, 22 cm seen) and its handle, a
    torus of 66 mm beside it, are a pitcher on its label (before the model: an unknown region)."""
    import json

    import mereo

    ev = _eval_real()
    truth = json.loads((real / "posecnn" / "labels.json").read_text())["frames"]["000004"]
    frame = mereo.io.read(str(real / "posecnn" / "000004-depth.png"), **ev.POSECNN)
    result, labels = ev.run(frame)
    on = [(o["model"], truth[i]["class"] if i is not None else None) for o, i, _ in ev.match_posecnn(result, labels, truth)]
    assert ("pitcher", "pitcher") in on, on
    pitcher = next(o for o in result["objects"] if o["model"] == "pitcher")
    assert set(pitcher["parts"]) == {"body", "handle"}


def test_a_real_can_is_closed_and_no_cup_precision_on_posecnn_holds(real):
    """posecnn 000001: the soup can's lid is seen (its end closed), so it is not a cup (before the
    end view: 'cup 0.90', its radius 38 mm being at the can's soft edge); every accepted object
    over the five frames lies on a compatible label."""
    import json

    import mereo

    ev = _eval_real()
    labels_file = json.loads((real / "posecnn" / "labels.json").read_text())["frames"]
    wrong = []
    for fid, truth in sorted(labels_file.items()):
        frame = mereo.io.read(str(real / "posecnn" / f"{fid}-depth.png"), **ev.POSECNN)
        result, labels = ev.run(frame)
        for o, i, _ in ev.match_posecnn(result, labels, truth):
            if i is None or truth[i]["class"] not in ev.COMPATIBLE.get(o["model"], set()):
                wrong.append((fid, o["model"], truth[i]["class"] if i is not None else None))
    assert not wrong, wrong


@pytest.mark.parametrize("name, at", [("learn42", (-0.07, 0.10, 0.69)), ("test32", (0.03, 0.09, 0.72)),
                                      ("test33", (0.03, 0.09, 0.71))])
def test_an_object_standing_on_a_tin_is_not_blamed_for_the_tins_lid(real, name, at):
    """mOSD: a tin or a mug stands on a wide cookie tin (at `at`, camera frame, metres); the lid
    around its foot is what it stands on, not a part of it that its body fails to explain (these
    were rejected at 43-50% coverage)."""
    import mereo

    result = mereo.recognize(mereo.io.read(str(real / "pcl-mosd" / f"{name}.pcd")))
    on_tin = [o for o in result["objects"] if o["accepted"] and o["model"] in ("jar", "can", "cup", "mug")
              and np.linalg.norm(np.subtract(o["parts"]["body"]["point"], at)) < 0.03]
    assert on_tin, [(o["model"], o.get("rejected")) for o in result["objects"]]


def test_squeeze_and_cleaner_bottles_are_free_form_bottles_and_the_drill_and_boxes_are_not(real):
    """posecnn: the mustard bottles (000001, 000004) and the Soft Scrub bottles (000002, 000005)
    are no cylinder; what no primitive's object explains is a free-form region, and a slender
    region standing on the table with a narrow top is a bottle (modality free_form) on its
    label. The regions beside them (the cracker and sugar boxes, the drill, the banana) are not."""
    import json

    import mereo

    ev = _eval_real()
    labels_file = json.loads((real / "posecnn" / "labels.json").read_text())["frames"]
    for fid in ("000001", "000002", "000004", "000005"):
        truth = labels_file[fid]
        frame = mereo.io.read(str(real / "posecnn" / f"{fid}-depth.png"), **ev.POSECNN)
        result, labels = ev.run(frame)
        matches = ev.match_posecnn(result, labels, truth)
        bottles = [(o, i) for o, i, _ in matches if o["model"] == "bottle"]
        assert len(bottles) == 1, (fid, [(o["model"], i) for o, i, _ in matches])
        o, i = bottles[0]
        assert i is not None and truth[i]["class"] == "bottle", (fid, i)
        assert o["modality"] == "free_form" and set(o["parts"]) == {"shape"}, (fid, o)
        shape = o["parts"]["shape"]
        assert shape["class"] == "region" and 0.15 < shape["height"] < 0.26 and shape["neck"] < 0.6, (fid, shape)


def test_a_cylinder_on_a_detergent_bottles_band_does_not_win_over_the_bottle(real):
    """pcl milk_cartoon_all_small_clorox: the Clorox jug and the "all" detergent bottle are
    free-form bottles. The cylinder fitted to the "all" bottle's band explains 41% of the bottle:
    no jar, even though the bottle's free-form region holds the band's pixels too (it must not
    take them from the jar's region, which would then look fully explained)."""
    import mereo

    result = mereo.recognize(mereo.io.read(str(real / "pcl" / "milk_cartoon_all_small_clorox.pcd")))
    accepted = sorted((o["model"], o.get("modality")) for o in result["objects"] if o["accepted"])
    assert accepted == [("bottle", "free_form"), ("bottle", "free_form")], accepted


def test_upright_bodies_stand_on_the_support_and_do_not_overlap(real):
    """The upright search (bodies as circles in the support plane, for wavy stereo depth) on real
    Kinect frames: the column of an office chair stands on its base, 13 cm above the floor, and is
    no jar (pcl-pairwise capture0005); a circle fitted to the PCL mug's handle overlaps the mug's
    body and is no jar beside it. Both were jars before the foot and overlap rules."""
    import mereo

    chair = mereo.recognize(mereo.io.read(str(real / "pcl-pairwise" / "capture0005.pcd")))
    # the column stands at about x = -0.45 m, 1.6-1.7 m away (camera frame); nothing accepted there
    # (a lying cylinder 0.8 m from it, on the ridges under the desk, is: see issue 18's note)
    for o in chair["objects"]:
        if o["accepted"]:
            x, _, z = o["parts"]["body"]["point"]
            assert (x + 0.45) ** 2 + (z - 1.65) ** 2 > 0.4**2, o
    mug = mereo.recognize(mereo.io.read(str(real / "pcl" / "table_scene_mug_stereo_textured.pcd")))
    assert [o["model"] for o in mug["objects"] if o["accepted"]] == ["mug"]
    assert any(p["class"] == "cylinder" for p in mug["primitives"])
