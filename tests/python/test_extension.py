"""The extension and signal layers from Python: normals (zero-copy results), the support plane,
the depth filter, and their nodes in a graph."""
import json

import numpy as np
import pytest

import mereo


@pytest.fixture(scope="module")
def scene():
    return mereo.synthetic.render(7)


def test_estimate_normals_returns_a_view_of_the_cpp_result(scene):
    cloud = mereo.extension.back_project(scene.frame)
    for method in ("fast", "covariance"):
        n = mereo.extension.estimate_normals(cloud, method=method)
        assert n.shape == (480, 640, 3) and n.dtype == np.float32
        # no copy: the array does not own its memory, the C++ buffer (held by a capsule) does
        assert not n.flags.owndata and n.base is not None
        ok = np.isfinite(n[..., 0])
        np.testing.assert_allclose(np.linalg.norm(n[ok], axis=1), 1.0, atol=1e-4)
        # towards the camera
        assert (np.einsum("ij,ij->i", n[ok], cloud[ok]) <= 1e-6).all()
        # against the exact normals on the valid pixels
        truth = scene.truth.normals
        both = ok & np.isfinite(truth[..., 0])
        cos = np.abs(np.einsum("ij,ij->i", n[both], truth[both]))
        assert np.median(np.degrees(np.arccos(np.clip(cos, -1, 1)))) < 15
    with pytest.raises(mereo.InputError, match="unknown method 'sobel'"):
        mereo.extension.estimate_normals(cloud, method="sobel")
    with pytest.raises(mereo.InputError, match="window must be odd"):
        mereo.extension.estimate_normals(cloud, window=4)


@pytest.mark.parametrize("depth_model, seeds, tolerance", [("kinect", (7, 8, 9), 0.15), ("stereo", (7, 8, 9), 0.25)])
def test_support_plane_measures_the_depth_noise_of_its_camera(depth_model, seeds, tolerance):
    # plane.noise (the depth error's deviation at 1 m, growing with z^2) against the renderer's
    # own error on the table's farthest quarter: depth minus exact depth over z^2
    for seed in seeds:
        so = mereo.synthetic.SceneOptions()
        so.depth_model = depth_model
        sf = mereo.synthetic.render(seed, so)
        cloud = mereo.extension.back_project(sf.frame)
        plane = mereo.extension.find_support_plane(cloud, mereo.extension.estimate_normals(cloud))
        table = next(o["id"] for o in json.loads(sf.truth_json())["objects"] if o["model"] == "table")
        depth, exact = np.asarray(sf.frame.depth, float), np.asarray(sf.truth.depth, float)
        on = (np.asarray(sf.truth.objects) == table) & (depth > 0) & (exact > 0)
        far = on & (exact >= np.quantile(exact[on], 0.75))
        e = (depth - exact)[far] / exact[far] ** 2
        truth = 1.4826 * np.median(np.abs(e - np.median(e)))
        assert plane.noise == pytest.approx(truth, rel=tolerance), (depth_model, seed)


def test_support_plane_matches_the_ground_truth(scene):
    cloud = mereo.extension.back_project(scene.frame)
    normals = mereo.extension.estimate_normals(cloud)
    plane = mereo.extension.find_support_plane(cloud, normals)
    pose = scene.frame.pose  # camera to world, world z up from the table
    truth = pose[:3, :3].T @ np.array([0.0, 0.0, 1.0])
    assert np.degrees(np.arccos(np.clip(plane.normal @ truth, -1, 1))) < 1.0
    assert plane.polygon.shape[1] == 3 and len(plane.polygon) >= 3
    assert plane.roi.shape == (480, 640) and plane.roi.dtype == np.uint8
    # the objects stand in the ROI, the table top does not
    objects = scene.truth.objects
    assert plane.roi[objects == 0].sum() == 0
    T = plane.world_from_camera
    assert T.shape == (4, 4)
    np.testing.assert_allclose(T[:3, :3] @ plane.normal, [0, 0, 1], atol=1e-9)
    with pytest.raises(mereo.InputError, match="support plane"):
        mereo.extension.find_support_plane(np.full((48, 64, 3), np.nan, np.float32),
                                           np.full((48, 64, 3), np.nan, np.float32))


def test_filter_depth_keeps_holes_and_reduces_noise(scene):
    depth = scene.frame.depth
    out = mereo.signal.filter_depth(depth)
    assert out.shape == depth.shape and out.dtype == np.float32
    assert np.array_equal(np.isnan(out), np.isnan(depth) | (depth <= 0))
    clean = scene.truth.depth
    ok = np.isfinite(depth) & np.isfinite(clean)
    assert np.sqrt(np.mean((out[ok] - clean[ok]) ** 2)) < np.sqrt(np.mean((depth[ok] - clean[ok]) ** 2))
    f = mereo.signal.filter_depth(scene.frame)
    np.testing.assert_array_equal(f.depth, out)


def test_extension_nodes_in_a_graph(scene):
    g = mereo.Graph()
    src = g.add("frame_source", "source")
    smooth = g.add(mereo.nodes.filter_depth(), "smooth")
    cloud = g.add("back_project", "cloud")
    normals = g.add(mereo.nodes.estimate_normals(method="covariance"), "normals")
    table = g.add("support_plane", "table")
    g.connect(src.frame, smooth.frame)
    g.connect(smooth.frame, cloud.frame)
    g.connect(cloud.cloud, normals.cloud)
    g.connect(cloud.cloud, table.cloud)
    g.connect(normals.normals, table.normals)
    g.connect(src.frame, table.frame)
    g.verify()
    (r,) = g.run([scene.frame], keep=["table.plane", "table.roi", "normals.normals"])
    plane = r["outputs"]["table.plane"]
    assert isinstance(plane, mereo.extension.SupportPlane)
    assert r["outputs"]["table.roi"].shape == (480, 640)
    assert r["outputs"]["normals.normals"].shape == (480, 640, 3)
    with pytest.raises(mereo.GraphError, match="option 'window' = 1 is outside its range"):
        mereo.nodes.estimate_normals(window=1)


def test_demo_runs_the_extension_layer_against_the_truth(tmp_path):
    """The README's main command: the default scene, its ground truth, normals and table plane."""
    import re
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "mereo.cli", "demo", "--out", str(tmp_path)],
                         capture_output=True, text=True, check=True).stdout
    tilt = float(re.search(r"support plane: \d+ table points, normal ([0-9.]+) deg", out).group(1))
    assert tilt < 1.0
    # the default scene's Kinect-like depth: about 2 mm at 1 m (its true error 1.8-2.0 on seeds 7-9)
    noise = float(re.search(r"the depth's noise measured on it ([0-9.]+) mm at 1 m", out).group(1))
    assert 1.0 < noise < 3.0
    share = float(re.search(r"normals \(fast\): ([0-9.]+)% of valid pixels", out).group(1))
    assert share > 95
    assert (tmp_path / "extension.png").stat().st_size > 10000
    assert (tmp_path / "preview.png").is_file()
