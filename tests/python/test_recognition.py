"""The main job end to end: the tabletop pipeline from Python, the node-by-node graph, the
command line (recognize, evaluate), the evaluation itself, and the figures of the issue: mugs on
50 noisy synthetic frames from seeds used for nothing else (2000-2049) and the real mug."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mereo
from mereo import cli
from mereo import evaluate as ev

ROOT = Path(__file__).resolve().parents[2]
EVAL_SEEDS = range(2000, 2050)  # the recognition figures' frames: used by this test only


def accepted(result, model=None):
    return [o for o in result["objects"] if o["accepted"] and (model is None or o["model"] == model)]


@pytest.fixture(scope="module")
def scene():
    return mereo.synthetic.render(903)  # three mugs, their handles in view


@pytest.fixture(scope="module")
def result(scene):
    return mereo.recognize(scene.frame)


def test_recognize_returns_the_contract(scene, result):
    assert result["frame"] == "0000" and result["source"] == "synthetic:903"
    assert {"objects", "primitives", "support_plane", "timing_ms"} <= set(result)
    assert result["timing_ms"]["total"] >= result["timing_ms"]["primitives"] > 0
    mugs = accepted(result, "mug")
    truth = [o for o in json.loads(scene.truth_json())["objects"] if o["model"] == "mug"]
    assert len(mugs) == len(truth) == 3
    for m in mugs:
        body, handle = m["parts"]["body"], m["parts"]["handle"]
        assert body["class"] == "cylinder" and handle["class"] == "torus"
        assert set(body) >= {"point", "axis", "radius", "height", "inliers"}
        assert set(handle) >= {"center", "normal", "major_radius", "minor_radius", "inliers"}
        # the nearest true mug body: the same radius within 3 mm
        t = min(truth, key=lambda o: np.linalg.norm(np.subtract(o["parts"][0]["camera"]["point"], body["point"])))
        assert abs(t["parts"][0]["camera"]["radius"] - body["radius"]) < 0.003
    # alternatives (a cup or a jar on a mug's body) are listed, excluded by the accepted mug
    ids = {o["id"]: o for o in result["objects"]}
    for o in result["objects"]:
        if not o["accepted"]:
            assert any(ids[e]["accepted"] for e in o["excludes"])


def test_the_same_pipeline_built_node_by_node(scene, result):
    g = mereo.Graph()
    src = g.add("frame_source", "source")
    models = g.add("models", "models")
    filt = g.add("filter_depth", "filter", radius=1)
    cloud = g.add("back_project", "cloud")
    raw = g.add("back_project", "raw_cloud")
    normals = g.add("estimate_normals", "normals")
    table = g.add("support_plane", "table")
    prims = g.add("detect_primitives", "primitives", classes="plane,cylinder,cone,sphere,torus")
    objects = g.add("match_models", "objects")
    interpretation = g.add("interpret", "interpretation")
    report = g.add("report", "result")
    for a, b in [(src.frame, filt.frame), (filt.frame, cloud.frame), (src.frame, raw.frame),
                 (cloud.cloud, normals.cloud), (cloud.cloud, table.cloud), (normals.normals, table.normals),
                 (src.frame, table.frame), (cloud.cloud, prims.cloud), (normals.normals, prims.normals),
                 (table.roi, prims.roi), (src.frame, prims.frame), (raw.cloud, prims.unfiltered),
                 (prims.segments, objects.segments), (models.models, objects.models), (table.plane, objects.plane),
                 (objects.lattice, interpretation.lattice), (models.models, interpretation.models),
                 (prims.segments, interpretation.segments), (cloud.cloud, interpretation.cloud),
                 (table.plane, interpretation.plane), (normals.normals, interpretation.normals),
                 (src.frame, report.frame), (prims.segments, report.segments),
                 (interpretation.objects, report.objects), (table.plane, report.plane)]:
        g.connect(a, b)
    mine = mereo.recognize(scene.frame, graph=g)
    strip = lambda r: {k: v for k, v in r.items() if k != "timing_ms"}  # noqa: E731
    assert strip(mine) == strip(result)


def test_mereo_run_gives_the_same_objects(result):
    run = subprocess.run([str(Path(sys.executable).parent / "mereo-run"), str(ROOT / "graphs/tabletop.yaml"),
                          "synthetic:903", "--result", "result.result", "--mode", "deterministic"],
                         capture_output=True, text=True, check=True)
    line = json.loads(run.stdout.splitlines()[0])
    assert line["objects"] == result["objects"] and line["primitives"] == result["primitives"]
    assert set(line["timing_ms"]) >= {"normals", "primitives", "objects", "total"}


def test_goal_restricts_the_models_and_the_search(scene):
    g = mereo.tabletop_graph(goal="jar")
    r = mereo.recognize(scene.frame, graph=g)
    # three open mugs: no jar (before the end view they were taken for jars), three unknown regions
    assert [o["model"] for o in r["objects"]] == ["unknown"] * 3
    assert not [p for p in r["primitives"] if p["class"] == "torus"]  # no handle search for a jar
    opts = mereo.recognition.goal_options("mug")
    assert opts["classes"] == "cylinder,torus" and 0.02 < opts["handle_body_min_radius"] < 0.03
    assert 0.055 < opts["handle_body_max_radius"] < 0.07  # the mug body's range and its margin
    with pytest.raises(mereo.InputError, match="teapot"):
        mereo.tabletop_graph(goal="teapot")


def test_cli_recognize_writes_lines_and_overlays(tmp_path, capsys):
    out, overlay = tmp_path / "r.jsonl", tmp_path / "overlay"
    assert cli.main(["recognize", "synthetic:903", "synthetic:905", "--out", str(out), "--overlay", str(overlay)]) == 0
    lines = [json.loads(s) for s in out.read_text().splitlines()]
    assert [r["source"] for r in lines] == ["synthetic:903", "synthetic:905"]
    pngs = sorted(overlay.glob("*_overlay.png"))
    assert len(pngs) == 2
    import matplotlib.image

    picture = matplotlib.image.imread(pngs[0])
    assert picture.shape[:2] == (480, 640)
    colour = mereo.synthetic.render(903).frame.color
    assert (np.abs(picture[..., :3] * 255 - colour).max(axis=2) > 60).sum() > 500  # outlines drawn
    assert "mug" in capsys.readouterr().err  # the summary names what was found


def test_overlay_of_a_frame_without_colour_draws_on_its_depth():
    """A depth-only frame (an XYZ PCD, a depth PNG alone): the overlay is drawn on the depth in false
    colour (it crashed on the missing colour image before)."""
    frame = mereo.io.read("synthetic:903")
    depth_only = mereo.Frame()
    depth_only.depth = frame.depth
    depth_only.intrinsics = frame.intrinsics
    result = mereo.recognize(depth_only)
    assert any(o["model"] == "mug" and o["accepted"] for o in result["objects"])
    picture = mereo.recognition.draw_result(depth_only, result)
    assert picture.shape == frame.depth.shape + (3,) and picture.dtype == np.uint8
    plain = mereo.recognition.draw_result(depth_only, {"objects": []})
    assert len(np.unique(plain.reshape(-1, 3), axis=0)) > 20  # the depth in false colour, not black
    assert (np.abs(picture.astype(int) - plain).max(axis=2) > 60).sum() > 500  # the mug's outline
    # a tracked object not seen in this frame is not drawn (its predicted place may lie off the image)
    unseen = {"objects": [dict(o, in_view=False) for o in result["objects"] if "region" not in o]}
    assert np.array_equal(mereo.recognition.draw_result(depth_only, unseen), plain)


def test_cli_bad_input_is_one_clear_line(tmp_path, capsys):
    assert cli.main(["recognize", str(tmp_path / "missing.pcd")]) == 2
    assert "missing.pcd" in capsys.readouterr().err
    assert cli.main(["recognize", "synthetic:1", "--models", "mug,teapot"]) == 2
    assert "teapot" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text("concepts:\n  - name: pot\n    parent: container\n    attributes:\n"
                   "      - {part: body, attribute: radius, rnage: [0.05, 0.1]}\n")
    assert cli.main(["recognize", "synthetic:1", "--models", str(bad)]) == 2
    assert "bad.yaml:5" in capsys.readouterr().err
    results = tmp_path / "r.jsonl"
    results.write_text('{"frame": "0000", "objects": []}\nnot json\n')
    assert cli.main(["evaluate", str(results), "synthetic:1"]) == 2
    assert "r.jsonl:2" in capsys.readouterr().err


def test_a_model_file_of_ones_own(tmp_path):
    """--models FILE: the file's concepts (beside the shipped ones) are looked for, on single frames
    and on a tracked sequence alike: the graph's one models node loads the file for the matcher
    and the judgement that the report and the tracker read."""
    mine = tmp_path / "mine.yaml"
    mine.write_text("concepts:\n  - name: my_mug\n    parent: mug\n    attributes:\n"
                    "      - {part: body, attribute: radius, range: [0.035, 0.05], margin: 0.005}\n")
    g = mereo.tabletop_graph(models_file=str(mine), models=["my_mug"])
    assert 'file: "' + str(mine) in g.to_yaml() and g.to_yaml().count("my_mug") == 1
    out = tmp_path / "r.jsonl"
    assert cli.main(["recognize", "synthetic:903", "--models", str(mine), "--out", str(out)]) == 0
    (single,) = [json.loads(s) for s in out.read_text().splitlines()]
    assert len(accepted(single, "my_mug")) == 3 and {o["model"] for o in single["objects"]} == {"my_mug"}
    assert cli.main(["recognize", "synthetic:703", "--frames", "3", "--models", str(mine), "--out", str(out)]) == 0
    tracked = [json.loads(s) for s in out.read_text().splitlines()]
    assert [o["model"] for o in tracked[-1]["objects"]] and {o["model"] for r in tracked for o in r["objects"]} == {"my_mug"}


def test_evaluate_against_a_perfect_and_a_wrong_answer():
    """The evaluation itself, on answers made from the ground truth (independent of detection)."""
    truths = ev.load_truths(["synthetic:903", "synthetic:905"])
    perfect, wrong = [], []
    for t in truths:
        objs = []
        for o in t["objects"]:
            body = [p for p in o["parts"] if p["role"] == "body" and p["class"] == "cylinder"]
            if not body or o["model"] in ("table",):
                continue
            c = body[0]["camera"]
            objs.append({"id": len(objs), "model": o["model"], "score": 1.0, "accepted": True,
                         "parts": {"body": {"class": "cylinder", "point": c["point"], "axis": c["axis"],
                                            "radius": c["radius"], "height": c["height"]}}})
        perfect.append({"objects": objs})
        wrong.append({"objects": [dict(o, model="mug" if o["model"] != "mug" else "jar") for o in objs]})
    e = ev.evaluate(perfect, truths)
    for name, s in e.summary()["models"].items():
        assert s["precision"] == 1.0, name
        assert np.isnan(s["recall"]) or s["recall"] == 1.0, name
    assert e.summary()["models"]["mug"]["median_radius_mm"] == 0.0
    w = ev.evaluate(wrong, truths)
    assert w.summary()["models"]["mug"]["precision"] == 0.0 and w.jars_cans_not_mugs == 0.0
    assert "mug" in ev.format_table(e)


def test_mugs_on_50_noisy_frames():
    """Issue figures: mug precision >= 95%, recall >= 90% (handle >= 150 px), >= 95% of jars and
    cans not taken for mugs."""
    frames = [mereo.synthetic.render(s).frame for s in EVAL_SEEDS]
    results = mereo.recognize_all(frames)
    e = ev.evaluate(results, ev.load_truths([f"synthetic:{s}" for s in EVAL_SEEDS]))
    mug = e.summary()["models"]["mug"]
    print(ev.format_table(e))
    assert mug["eligible"] >= 40
    assert mug["precision"] >= 0.95 and mug["recall"] >= 0.90
    assert e.jars_cans >= 40 and e.jars_cans_not_mugs >= 0.95
    assert mug["median_radius_mm"] < 2.0 and mug["median_axis_deg"] < 2.0


def test_the_real_mug(real):
    """pcl/table_scene_mug_stereo_textured.pcd: a mug, body radius within 5 mm of a circle fitted
    to its wall (the points above the table whose normals are horizontal, trimmed of the handle)."""
    frame = mereo.io.read(str(real / "pcl" / "table_scene_mug_stereo_textured.pcd"))
    r = mereo.recognize(frame)
    mugs = accepted(r, "mug")
    assert len(mugs) == 1
    cloud = mereo.extension.back_project(frame)
    normals = mereo.extension.estimate_normals(cloud)
    plane = mereo.extension.find_support_plane(cloud, normals)
    up = np.asarray(plane.normal)
    e1 = np.cross(up, [1.0, 0, 0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    wall = (plane.roi > 0) & (np.abs(normals @ up) < 0.5) & np.isfinite(cloud[..., 2])
    xy = np.stack([cloud[wall] @ e1, cloud[wall] @ e2], axis=1).astype(np.float64)
    keep = np.ones(len(xy), bool)
    for _ in range(4):  # Kasa fit, trimmed to the points within 1 cm of the circle
        A = np.column_stack([xy[keep], np.ones(keep.sum())])
        sol = np.linalg.lstsq(A, -(xy[keep] ** 2).sum(1), rcond=None)[0]
        c = -sol[:2] / 2
        radius = np.sqrt(c @ c - sol[2])
        keep = np.abs(np.linalg.norm(xy - c, axis=1) - radius) < 0.01
    assert abs(mugs[0]["parts"]["body"]["radius"] - radius) < 0.005


def test_a_sequence_is_tracked(tmp_path):
    """`mereo recognize` on a sequence runs the tracking pipeline: every reported object has a
    track id and stands on the table (its relations), a mug is reported from its second view on
    and keeps its id from frame to frame, and --no-track recognizes frames alone."""
    out = tmp_path / "seq.jsonl"
    assert cli.main(["recognize", "synthetic:703", "--frames", "6", "--out", str(out)]) == 0
    lines = [json.loads(s) for s in out.read_text().splitlines()]
    assert len(lines) == 6
    ids = [sorted(o["track"] for o in r["objects"] if o["model"] == "mug") for r in lines]
    assert not ids[0]  # one view does not make a report; the second that agrees does
    assert ids[1] and all(i == ids[1] for i in ids[2:])
    assert all({"track", "probability", "in_view"} <= set(o) for r in lines for o in r["objects"])
    # the tracked objects' relations: each stands on the table
    assert all(dict(_relations(r, "on")).get(o["id"]) == "support_plane" for r in lines for o in r["objects"])
    assert cli.main(["recognize", "synthetic:703", "--frames", "2", "--no-track", "--out", str(out)]) == 0
    assert all("track" not in o for s in out.read_text().splitlines() for o in json.loads(s)["objects"])
    g = mereo.tabletop_graph(tracking=True, odometry=True)
    assert "poses" in g.to_yaml() and "tracks" in g.to_yaml()


def test_poses_by_odometry_give_the_same_tracks(tmp_path):
    """`--odometry` (poses estimated from the frames, corrected against the table and its upright
    cylinders) on a steep view of rings leaning on jars, where OpenCV's odometry alone slides along
    the untextured table: the mugs keep the tracks they get with the renderer's poses, and the
    reported bodies stay where the given poses put them."""
    runs = {}
    for name, extra in (("given", []), ("odometry", ["--odometry"])):
        out = tmp_path / f"{name}.jsonl"
        args = ["recognize", "synthetic:701", "--frames", "10", "--leaning-distractors", "--out", str(out)]
        assert cli.main(args + extra) == 0
        runs[name] = [json.loads(s) for s in out.read_text().splitlines()]
    assert len(runs["given"]) == len(runs["odometry"]) == 10
    for a, b in zip(runs["given"], runs["odometry"]):
        mugs_a = {o["track"]: o for o in a["objects"] if o["model"] == "mug"}
        mugs_b = {o["track"]: o for o in b["objects"] if o["model"] == "mug"}
        assert mugs_a.keys() == mugs_b.keys()
        for t in mugs_a:  # camera frame: where this frame's camera sees the tracked body
            pa, pb = (np.array(m[t]["parts"]["body"]["point"]) for m in (mugs_a, mugs_b))
            assert np.linalg.norm(pa - pb) < 0.01
    assert any(mugs for mugs in ([o for o in r["objects"] if o["model"] == "mug"] for r in runs["given"]))
    # each line carries its camera pose (camera to world): the renderer's, or the odometry's whose
    # world is the first camera; relative to the first frame they agree
    def pose(r):
        x, y, z, w = r["camera_pose"]["quaternion"]
        T = np.eye(4)
        T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        T[:3, 3] = r["camera_pose"]["translation"]
        return T
    given0, est0 = pose(runs["given"][0]), pose(runs["odometry"][0])
    np.testing.assert_allclose(est0, np.eye(4), atol=1e-9)
    for a, b in zip(runs["given"][1:], runs["odometry"][1:]):
        truth = np.linalg.inv(given0) @ pose(a)
        assert np.linalg.norm(truth[:3, 3]) > 0.01  # the camera moves
        assert np.linalg.norm(truth[:3, 3] - (np.linalg.inv(est0) @ pose(b))[:3, 3]) < 0.01


@pytest.mark.parametrize("track", [False, True])
def test_a_frame_without_a_support_surface_is_a_warning_and_the_run_goes_on(tmp_path, capsys, track):
    """The middle frame of three shows only a wall (no surface faces up): by default its line has
    no objects and a warning naming the node and why, and the frames around it are recognized;
    --on-error stop stops at it with one line."""
    seq = tmp_path / "seq"
    seq.mkdir()
    for k, seed in enumerate([903, None, 905]):
        f = mereo.synthetic.render(seed if seed is not None else 903).frame
        if seed is None:
            f.depth = np.full_like(f.depth, 1.5)  # a wall facing the camera
        mereo.io.write_png_pair(seq, f"{k:04d}", f)
    out = tmp_path / "r.jsonl"
    extra = [] if track else ["--no-track"]
    assert cli.main(["recognize", str(seq), "--out", str(out), "--mode", "deterministic", *extra]) == 0
    lines = [json.loads(s) for s in out.read_text().splitlines()]
    assert [r["frame"] for r in lines] == ["0000", "0001", "0002"]
    assert lines[1]["objects"] == [] and lines[1]["primitives"] == []
    assert any("table" in w and "support plane" in w for w in lines[1]["warnings"]), lines[1]["warnings"]
    assert "warnings" not in lines[0] and "warnings" not in lines[2]
    if not track:  # (a track is reported from its second agreeing view)
        assert accepted(lines[0], "mug") and accepted(lines[2])
    err = capsys.readouterr().err
    assert "warning: frame 0001" in err and "1 frame(s) with a warning" in err
    assert cli.main(["recognize", str(seq), "--out", str(out), "--on-error", "stop", *extra]) == 2
    assert "support plane" in capsys.readouterr().err
    # the same from Python: an empty result with the reason, or an error when asked for
    wall = mereo.io.read(str(seq / "0001_depth.png"))
    r = mereo.recognize(wall)
    assert r["objects"] == [] and "support plane" in r["warnings"][0]
    with pytest.raises(mereo.NodeError, match="node 'table'.*support plane"):
        mereo.recognize(wall, on_error="stop")


def test_a_list_of_files_is_one_sequence_with_sequence(tmp_path):
    """--sequence: separate inputs are the frames of one sequence and are tracked (each reported
    object carries its track id); without it they are recognized one by one."""
    files = ["synthetic:3", "synthetic:3", "synthetic:3"]  # the same view three times, with its pose
    out = tmp_path / "r.jsonl"
    assert cli.main(["recognize", *files, "--sequence", "--out", str(out)]) == 0
    tracked = [json.loads(s) for s in out.read_text().splitlines()]
    assert any(o.get("track") is not None for r in tracked[1:] for o in r["objects"])
    assert cli.main(["recognize", *files, "--out", str(out)]) == 0
    alone = [json.loads(s) for s in out.read_text().splitlines()]
    assert all("track" not in o for r in alone for o in r["objects"])


def test_lying_cans_and_jars_are_recognized_lying():
    """Containers lying on their side (the renderer's lying_containers): the closed ones (can,
    jar) may rest upright or lying (rest_tilt_deg), and the result says which (pose)."""
    from mereo import evaluate as ev

    so = mereo.synthetic.SceneOptions()
    so.lying_containers = True
    seeds = [f"synthetic:{s}" for s in range(3100, 3108)]
    results = mereo.recognize_all([mereo.io.read(s, scene=so) for s in seeds])
    e = ev.evaluate(results, ev.load_truths(seeds, options=so))
    lying = {k: (v.found, v.eligible) for k, v in e.kinds.items() if k.endswith("/lying")}
    found = sum(f for f, _ in lying.values())
    total = sum(n for _, n in lying.values())
    assert total >= 8 and found >= 0.8 * total, lying
    poses = [o.get("pose") for r in results for o in r["objects"] if o["accepted"] and o["model"] in ("can", "jar")]
    assert "lying" in poses and "upright" in poses


def test_tapered_cups_are_recognized_by_the_shipped_graph():
    """The shipped graph searches for cones and has the tapered_cup model: the renderer's
    tapered cups are recognized as such."""
    from mereo import evaluate as ev

    so = mereo.synthetic.SceneOptions()
    so.tapered_cups = True
    seeds = [f"synthetic:{s}" for s in range(3200, 3208)]
    results = mereo.recognize_all([mereo.io.read(s, scene=so) for s in seeds])
    e = ev.evaluate(results, ev.load_truths(seeds, options=so))
    cups = e.models["tapered_cup"]
    assert cups.eligible >= 6 and cups.recall >= 0.7 and cups.precision >= 0.9, (cups.found, cups.eligible, cups.correct, cups.results)


def _rendered_freeform(seeds, depth_model="kinect"):
    """The shipped graph's results on rendered frames (Kinect-like unless told) with varied
    handles, lying containers, free-form distractors and tapered cups (as eval_cameras renders
    them), and their evaluation against the ground truth."""
    so = mereo.synthetic.SceneOptions()
    so.depth_model, so.handle_shapes = depth_model, "varied"
    so.lying_containers = so.freeform_distractors = so.tapered_cups = True
    specs = [f"synthetic:{s}" for s in seeds]
    results = mereo.recognize_all([mereo.io.read(s, scene=so) for s in specs])
    return results, ev.evaluate(results, ev.load_truths(specs, options=so))


def test_cylinders_fitted_to_bananas_bend_and_are_no_containers():
    """Rendered Kinect-like frames 6002, 6004 and 6021 (tuning seeds of issue 18): a can or jar was
    accepted on a banana (a cylinder of 32-38 mm through its curve). Its normals bend along the
    axis beyond their noise (Segment.bend 3-9 / m; true bodies 0), so the container models reject it; the
    frames' true containers stay found."""
    _, e = _rendered_freeform((6002, 6004, 6021))
    on_bananas = [m for m in e.mistakes if "on the banana" in m]
    assert not on_bananas, on_bananas
    found = sum(s.found for s in e.models.values())
    assert found >= 10, (found, e.mistakes)


def test_cylinders_fitted_to_rounded_boxes_are_out_of_round_and_no_containers():
    """Rendered Kinect-like frames 4418, 4426 and 4463 (held out: the threshold was set on seeds
    5000-5049 and 7000-7049): a can or jar was accepted on a rounded box (a soap or phone box)
    whose rounded edges and flat faces a cylinder fits within 2 mm. Its points' distances from
    that cylinder make a pattern around the axis beyond their noise (Segment.out_of_round 0.04-0.07;
    round bodies 0), so the container models reject it; the frames' true objects stay found."""
    _, e = _rendered_freeform((4418, 4426, 4463))
    on_boxes = [m for m in e.mistakes if "on the rounded_box" in m]
    assert not on_boxes, on_boxes
    found = sum(s.found for s in e.models.values())
    assert found >= 13, (found, e.mistakes)  # 14 of 15 today


def test_blobs_seen_from_above_are_no_bowls():
    """Rendered Kinect-like frames 6002, 6020, 6035 and 6041 (tuning seeds of issue 18): a sphere
    fitted to a blob was a round bowl. A bowl opens upwards: its wall is seen below its sphere's
    centre (the sphere's `cap`, along the support's normal: rise -0.6 to -0.1 on the true bowls of
    seeds 6000-6049), a blob's surface above it (0.55-0.87). The frames' true bowls stay found."""
    _, e = _rendered_freeform((6002, 6020, 6035, 6041))
    on_blobs = [m for m in e.mistakes if "on the blob" in m]
    assert not on_blobs, on_blobs
    bowls = e.models.get("bowl")
    assert bowls is None or bowls.found == bowls.eligible, e.mistakes


def test_a_drills_grip_cut_off_at_a_silhouette_is_no_free_form_bottle():
    """Rendered Kinect-like frame 5031: the drill's grip, apart from its housing at a silhouette,
    is a slender region with a narrow top, but it explains only 54% of the region that grows
    from it without the silhouette cut; a free-form object must explain 90% (true bottles,
    rendered and real, explain 97-100%)."""
    results, e = _rendered_freeform((5031,))
    assert not [m for m in e.mistakes if "on the drill" in m], e.mistakes
    grip = [o for o in results[0]["objects"] if o.get("modality") == "free_form" and not o["accepted"]]
    assert grip and "explains" in grip[0].get("rejected", ""), [(o["model"], o.get("rejected")) for o in grip]


def test_a_ring_wider_than_its_body_is_tall_leaves_the_colour_image_asked():
    """Rendered stereo frame 4490 (held out: the rule was set on seeds 7003 and 7045): at 0.9 m the
    depth of mug 5's band handle gives a torus of a ring wider than the body is tall, which no
    model takes; the colour image, asked too, shows the handle, and the mug is found with it (it
    was a cup while a depth ring of any size kept the colour image from being asked)."""
    results, e = _rendered_freeform((4490,), depth_model="stereo")
    assert not [m for m in e.mistakes if "mug" in m], e.mistakes
    assert e.models["mug"].found == 2, e.mistakes


def test_a_box_face_does_not_end_the_search_for_upright_bodies():
    """Rendered stereo frames 9019, 8033 and 4522 (tuning seeds of issue 18): a box beside the mug
    offers the upright search circles through its faces round after round; each refits wider than
    any body and fails, and six failed rounds in a row ended the search before the mug was tried.
    A face that refits flatter than any body is now seeded no more as a whole
    (features/upright.cpp), not strip by strip. Each frame's mug is found."""
    _, e = _rendered_freeform((9019, 8033, 4522), depth_model="stereo")
    missed = [m for m in e.mistakes if "mug" in m and "is missed" in m]
    assert not missed, e.mistakes
    assert e.models["mug"].found >= 3, e.mistakes


def test_a_ring_near_a_bodys_end_is_no_handle():
    """Rendered stereo frames 4489, 4410, 8034 and 9031 (tuning seeds of issue 18): a ring fitted
    near the upper or lower end of a body (a tapered cup's flaring rim, a jar's foot) made a mug of
    it. A handle's centre lies 12 mm or more inside both ends of its body (the mug's `intersects`
    constraint, `inset`): no mug is reported where there is none."""
    _, e = _rendered_freeform((4489, 4410, 8034, 9031), depth_model="stereo")
    mug = e.models.get("mug", ev.ModelStats())
    assert mug.results == mug.correct, e.mistakes


def test_a_ring_hugging_a_bodys_wall_is_no_handle():
    """Rendered stereo frames 4504 and 9016 (tuning seeds of issue 18): a ring fitted to a body's
    own wall (a tapered cup's flaring side) or a colour silhouette pressed against it reached only
    9-16 mm past the wall, and made a mug of a cup. A handle stands out of its wall by 18 mm or more
    (the mug's `protrudes` constraint; mugs' handles 2-4 cm): no mug is reported where there is none."""
    _, e = _rendered_freeform((4504, 9016), depth_model="stereo")
    mug = e.models.get("mug", ev.ModelStats())
    assert mug.results == mug.correct, e.mistakes


def test_a_mug_whose_wall_bends_on_stereo_depth_is_still_a_mug():
    """Rendered stereo frames 3654, 3790, 3888, 4462 and 8018 (tuning seeds of issue 18): the mug's
    body, its radius within 4 mm, had a bend of 4.8-6.5 / m (the stereo depth's ripple), past the
    2 / m that keeps a banana from being a can or jar, and the mug was missed. Vessels with a
    handle accept up to 6 / m (the handle tells them from a banana); those without keep 2 / m, so
    nothing is accepted on these frames' bananas either."""
    _, e = _rendered_freeform((3654, 3790, 3888, 4462, 8018), depth_model="stereo")
    bent = {3654: 9, 3790: 4, 3888: 6, 4462: 5, 8018: 4}  # (the frames' other mugs are not this test's)
    missed = [m for m in e.mistakes for s, i in bent.items() if m.startswith(f"synthetic:{s}#") and f"the mug {i} is missed" in m]
    assert len(missed) <= 1, missed  # none today
    assert not [m for m in e.mistakes if "on the banana" in m], e.mistakes


def _true_body(t):
    """A true object's body: its centre (camera frame) and radius."""
    b = ev._body(t["parts"]) or ev._body(t["parts"], "cone") or ev._body(t["parts"], "sphere")
    cam = b["camera"]
    return np.asarray(cam.get("point", cam.get("center"))), cam["radius"]


def _relations(result, kind):
    return [(r["subject"], r["object"]) for r in result.get("relations", []) if r["relation"] == kind]


def test_relations_say_what_each_object_stands_on_against_the_truth():
    """Rendered Kinect-like frames 3400-3405 (used for nothing else): every accepted object that is
    a true object stands on the table ("on" the support plane; the renderer stacks nothing), two
    objects reported next to each other have true bodies at most 12 cm apart, and one reported in
    front of another is nearer the camera."""
    specs = [f"synthetic:{s}" for s in range(3400, 3406)]
    results = mereo.recognize_all([mereo.io.read(s) for s in specs])
    checked = 0
    for result, truth in zip(results, ev.load_truths(specs)):
        objects = [o for o in truth["objects"] if o["model"] not in ("floor", "wall", "table", "other")]
        true_of = {}
        for o in accepted(result):
            body = ev.body_part(o)
            t, _ = ev._match(body, objects, 0.02, 0.01) if body and body["class"] in ("cylinder", "cone", "sphere") else (None, 0)
            if t is not None:
                true_of[o["id"]] = t
        on = dict(_relations(result, "on"))
        for i in true_of:
            assert on.get(i) == "support_plane", (result["source"], i, result["relations"])
            checked += 1
        for a, b in _relations(result, "next_to"):
            if a in true_of and b in true_of:
                (pa, ra), (pb, rb) = (_true_body(true_of[x]) for x in (a, b))
                assert np.linalg.norm(pa - pb) - ra - rb <= 0.12, (result["source"], a, b)
        for a, b in _relations(result, "in_front_of"):
            if a in true_of and b in true_of:
                assert _true_body(true_of[a])[0][2] < _true_body(true_of[b])[0][2], (result["source"], a, b)
    assert checked >= 15, checked


def test_real_objects_stand_on_the_desk(real):
    """PoseCNN frames 000003 and 000004 (YCB objects on a desk; labels.json): every accepted object
    is on the support plane, and the two of each frame are next to each other."""
    for fid in ("000003", "000004"):
        frame = mereo.io.read(str(real / "posecnn" / f"{fid}-depth.png"),
                              intrinsics="1066.778,1067.487,312.9869,241.3109", depth_scale=10000.0)
        result = mereo.recognize(frame)
        ids = [o["id"] for o in accepted(result)]
        assert len(ids) >= 2, (fid, [o["model"] for o in accepted(result)])
        on = dict(_relations(result, "on"))
        assert all(on.get(i) == "support_plane" for i in ids), (fid, result["relations"])
        assert tuple(sorted(ids[:2])) in _relations(result, "next_to"), (fid, result["relations"])


def test_a_mug_whose_foot_is_hidden_keeps_its_handle():
    """bench_tracking's seed 727, frames 3-6 (Kinect-like): a jar in front hides the mug's lower
    half, the body is fitted 46-59 mm tall around the upper part, and the handle's centre lies below
    that part's middle. A handle's centre must lie 12 mm inside its body's ends (`inset`); the lower
    end is taken at the table where the seen one lies 25 mm or more above it (the foot hidden), so
    the mug is still a mug. With the seen end alone it was a cup in all four frames."""
    so = mereo.synthetic.SceneOptions()
    so.ambiguous_distractors = True
    seq = mereo.synthetic.render_sequence(727, 30, so)
    results = mereo.recognize_all([seq[k].frame for k in range(3, 7)])
    for k, r in zip(range(3, 7), results):
        truth = [o for o in json.loads(seq[k].truth_json())["objects"] if o["model"] == "mug"][0]
        centre = np.array(truth["parts"][0]["camera"]["point"])
        mugs = [o for o in accepted(r, "mug") if np.linalg.norm(np.array(o["parts"]["body"]["point"]) - centre) < 0.04]
        assert len(mugs) == 1, (k, [(o["model"], o["accepted"]) for o in r["objects"]])
        body = mugs[0]["parts"]["body"]
        assert body["height"] < 0.07, body  # the short body this test is about
