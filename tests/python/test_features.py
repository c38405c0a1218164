"""The feature layer from Python: segments with parameters and inlier pixels, the label image,
the detect_primitives node feeding match_models."""
import json

import numpy as np
import pytest

import mereo


@pytest.fixture(scope="module")
def clean():
    o = mereo.synthetic.SceneOptions()
    o.noise = False
    return mereo.synthetic.render(2, o)


def test_detect_primitives_returns_segments_with_masks(clean):
    cloud = mereo.extension.back_project(clean.frame)
    normals = mereo.extension.estimate_normals(cloud)
    segs = mereo.features.detect_primitives(cloud, normals, color=clean.frame.color)
    assert segs and segs[0].cls == "plane"  # the table, largest first
    assert all(a.inliers >= b.inliers for a, b in zip(segs, segs[1:]))
    labels = mereo.features.label_image(segs, 480, 640)
    assert labels.shape == (480, 640) and labels.dtype == np.int32
    for k, s in enumerate(segs):
        assert s.pixels.dtype == np.int32 and len(s.pixels) == s.inliers
        assert (labels.ravel()[s.pixels] == k).all()
    # the mug bodies of the ground truth are among the cylinders, radius within 2 mm
    objects = json.loads(clean.truth_json())["objects"]
    truth = [p["camera"]["radius"] for o in objects if o["model"] == "mug" for p in o["parts"] if p["role"] == "body"]
    cyl = [s for s in segs if s.cls == "cylinder"]
    assert truth
    for radius in truth:
        assert min(abs(s.radius - radius) for s in cyl) < 0.002
    with pytest.raises(ValueError):
        mereo.features.detect_primitives(cloud, normals[:10])


def test_bodies_are_measured_on_the_unfiltered_depth():
    """A filtered cloud segments; the unfiltered points measure: the mug bodies' radii come out
    closer to the truth than when fitted to the filtered (flattened) points."""
    sf = mereo.synthetic.render(903)
    filtered = mereo.signal.filter_depth(sf.frame, radius=1)
    cloud = mereo.extension.back_project(filtered)
    normals = mereo.extension.estimate_normals(cloud)
    raw = mereo.extension.back_project(sf.frame)
    objects = json.loads(sf.truth_json())["objects"]
    truth = [p["camera"]["radius"] for o in objects if o["model"] in ("mug", "jar", "can")
             for p in o["parts"] if p["role"] == "body" and p["visible_pixels"] >= 1000]
    assert len(truth) >= 2

    def errors(segs):
        cyl = [s.radius for s in segs if s.cls == "cylinder"]
        return np.array([min(cyl, key=lambda r: abs(r - t)) - t for t in truth])

    on_filtered = errors(mereo.features.detect_primitives(cloud, normals))
    on_raw = errors(mereo.features.detect_primitives(cloud, normals, unfiltered=raw))
    assert np.abs(on_raw).max() < 0.001
    assert np.abs(on_raw).mean() < np.abs(on_filtered).mean()
    with pytest.raises(ValueError, match="unfiltered"):
        mereo.features.detect_primitives(cloud, normals, unfiltered=raw[:10])


def test_primitives_to_objects_in_a_graph(clean):
    g = mereo.Graph()
    src = g.add("frame_source", "source")
    cloud = g.add("back_project", "cloud")
    normals = g.add("estimate_normals", "normals")
    prims = g.add(mereo.nodes.detect_primitives(), "primitives")
    models = g.add(mereo.nodes.models(models="jar, mug, bowl"), "models")
    objects = g.add(mereo.nodes.match_models(), "objects")
    g.connect(src.frame, cloud.frame)
    g.connect(cloud.cloud, normals.cloud)
    g.connect(cloud.cloud, prims.cloud)
    g.connect(normals.normals, prims.normals)
    g.connect(src.frame, prims.frame)
    g.connect(prims.segments, objects.segments)
    g.connect(models.models, objects.models)
    g.connect(src.frame, objects.frame)
    (r,) = g.run([clean.frame], keep=["primitives.segments", "objects.lattice"])
    segs = r["outputs"]["primitives.segments"]
    lattice = r["outputs"]["objects.lattice"]
    assert len(segs) > 3
    assert {h.concept for h in lattice.hypotheses} & {"jar", "bowl", "mug"}


def test_cones_go_through_the_shape_table():
    """A class of the shape table (the cone) needs nothing of its own in Python: detected when
    asked for, its parameters by their JSON names, a Segment again from a result's dict."""
    assert "cone" in mereo.knowledge.primitive_classes()
    o = mereo.synthetic.SceneOptions()
    o.tapered_cups = True
    sf = mereo.synthetic.render(1130, o)
    cloud = mereo.extension.back_project(sf.frame)
    normals = mereo.extension.estimate_normals(cloud)
    roi = mereo.extension.find_support_plane(cloud, normals).roi
    segs = mereo.features.detect_primitives(cloud, normals, roi=roi, classes=["plane", "cylinder", "cone"])
    cones = [s for s in segs if s.cls == "cone"]
    assert cones, [s.cls for s in segs]
    c = cones[0]
    assert {"point", "axis", "radius", "half_angle_deg", "height", "radius_narrow", "radius_wide"} <= set(c.params)
    assert 2.5 <= c.half_angle_deg <= 15 and c.radius_narrow < c.radius_wide
    again = mereo.knowledge.Segment.from_dict({"class": "cone", **c.params})
    assert again.radius == pytest.approx(c.radius) and again.half_angle_deg == pytest.approx(c.half_angle_deg)
    with pytest.raises(ValueError, match="has no field"):
        mereo.knowledge.Segment("cone", major_radius=0.02)


def _open_shares(seeds, depth_model):
    """(truth model, share of the body's end pixels that look into it) of every outer cylinder
    found on a rendered body whose end was seen (>= 20 decided pixels)."""
    import mereo
    from mereo import evaluate as ev

    so = mereo.synthetic.SceneOptions()
    so.depth_model = depth_model
    g = mereo.recognition.tabletop_graph()
    out = []
    for seed in seeds:
        frame = mereo.io.read(f"synthetic:{seed}", scene=so)
        truth = ev.load_truths([f"synthetic:{seed}"], options=so)[0]
        segs = g.run([frame], keep=["primitives.segments"])[0]["outputs"]["primitives.segments"]
        for s in segs:
            if s.cls != "cylinder" or s.inward or s.end_closed + s.end_open < 20:
                continue
            p = np.asarray(s.point)
            for o in truth["objects"]:
                for part in o["parts"]:
                    c = part["camera"]
                    if part["role"] != "body" or part["class"] != "cylinder":
                        continue
                    a, d = np.asarray(c["axis"]), p - np.asarray(c["point"])
                    if np.linalg.norm(d - a * d.dot(a)) < 0.01:
                        out.append((o["model"], s.end_open / (s.end_closed + s.end_open)))
    return out


@pytest.mark.parametrize("depth_model", ["kinect", "stereo"])
def test_the_end_of_a_body_facing_the_camera_is_seen_open_or_closed(depth_model):
    """Rendered mugs are open, jars, cans and bottles closed: the share of a body's end pixels that
    look into it tells them apart (the models' open_end / closed_end attributes)."""
    shares = _open_shares(range(20, 40), depth_model)
    open_ = [s for m, s in shares if m in ("mug", "cup")]
    closed = [s for m, s in shares if m in ("jar", "can", "bottle")]
    assert len(open_) >= 10 and len(closed) >= 10, (len(open_), len(closed))
    # open vessels at least 0.8 of it open (a lid covers its disc: the rim and the top of the inner
    # wall, near the radius, are no lid; counted as one, open mugs read 0.52-0.73 at the 10th
    # percentile), closed ones at most 0.3 (the stereo model's fattened edges lift a few bodies'
    # visible extent over their lid: on stereo 0.82-0.89 of them at most 0.3 over RANSAC seeds 0-3,
    # mean 0.84, with either of the two generators the search has had)
    assert np.mean(np.array(open_) >= 0.8) >= 0.9 and np.mean(np.array(closed) <= 0.3) >= 0.8, (
        sorted(open_), sorted(closed))


def test_an_upright_body_in_wavy_stereo_depth_takes_its_whole_wall():
    """Rendered stereo frames 6000-6019 (tuning seeds of issue 18): the bottom-up search leaves an
    upright body a patch of its wall where the wavy depth turns the normals (features/upright.cpp,
    grow_upright). Grown into the free pixels that fit it with the normals held loosely, the
    segment on an upright mug, can or jar holds a median 0.69 of the body's visible pixels (0.46
    without the growth); the pixels it holds are the body's, not the table's or a neighbour's."""
    from mereo import evaluate as ev

    so = mereo.synthetic.SceneOptions()
    so.depth_model, so.handle_shapes = "stereo", "varied"
    so.lying_containers = so.freeform_distractors = so.tapered_cups = True
    shares, purity = [], []
    for seed in range(6000, 6020):
        sf = mereo.synthetic.render(seed, so)
        labels = np.asarray(sf.truth.objects).ravel()
        truth = ev.load_truths([f"synthetic:{seed}"], options=so)[0]
        segs = mereo.recognition.tabletop_graph().run([sf.frame], keep=["primitives.segments"])[0]["outputs"][
            "primitives.segments"]
        for o in truth["objects"]:
            body = [p for p in o["parts"] if p["role"] == "body" and "point" in p.get("camera", {})]
            if o["model"] not in ("mug", "can", "jar") or not body or body[0]["visible_pixels"] < 500:
                continue
            c = body[0]["camera"]
            p0, a0 = np.asarray(c["point"]), np.asarray(c["axis"]) / np.linalg.norm(c["axis"])
            if abs(a0[1]) < 0.8:  # upright (the camera's y is near the vertical in these scenes)
                continue
            best = (0.0, 1.0)
            for s in segs:
                if s.cls not in ("cylinder", "cone") or s.inward:
                    continue
                d = np.asarray(s.params["point"]) - p0
                if np.linalg.norm(d - a0 * d.dot(a0)) < 0.02:
                    own = np.count_nonzero(labels[np.asarray(s.pixels)] == o["id"])
                    best = max(best, (own / body[0]["visible_pixels"], own / len(s.pixels)))
            shares.append(best[0]), purity.append(best[1])
    assert len(shares) >= 12, len(shares)
    assert np.median(shares) >= 0.6, sorted(np.round(shares, 2))
    assert np.median(purity) >= 0.95, sorted(np.round(purity, 2))
