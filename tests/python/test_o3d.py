"""Open3D interop (mereo.o3d, issue 23): organized clouds and normals round-trip exactly, frames
from an RGBDImage or an organized point cloud recognize what the original frame does, primitives
become meshes on their parts; without Open3D the module says which extra to install."""
from __future__ import annotations

import sys

import numpy as np
import pytest

import mereo
import mereo.o3d


def test_without_open3d_the_error_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "open3d", None)  # (import open3d then raises ImportError)
    with pytest.raises(ImportError, match=r"mereo\[open3d\]"):
        mereo.o3d.to_pointcloud(np.zeros((2, 2, 3), np.float32))


@pytest.fixture(scope="module")
def o3d():
    return pytest.importorskip("open3d", reason="Open3D is not installed (pip install mereo[open3d])")


@pytest.fixture(scope="module")
def frame():
    return mereo.io.read("synthetic:3")


def _accepted(result):
    return sorted(o["model"] for o in result["objects"] if o["accepted"] and o["model"] != "unknown")


def test_an_organized_cloud_with_normals_and_colours_round_trips_exactly(o3d, frame):
    cloud = mereo.extension.back_project(frame)
    normals = mereo.extension.estimate_normals(cloud)
    pcd = mereo.o3d.to_pointcloud(cloud, normals, frame.color)
    assert isinstance(pcd, o3d.t.geometry.PointCloud) and len(pcd.point.positions) == cloud.shape[0] * cloud.shape[1]
    back, back_normals, back_colors = mereo.o3d.cloud_from_pointcloud(pcd, *cloud.shape[:2])
    np.testing.assert_array_equal(back, cloud)  # NaN where no depth, in the same places
    np.testing.assert_array_equal(back_normals, normals)
    np.testing.assert_array_equal(back_colors, frame.color)
    # the legacy cloud too
    legacy, legacy_normals, _ = mereo.o3d.cloud_from_pointcloud(pcd.to_legacy(), *cloud.shape[:2])
    np.testing.assert_array_equal(legacy, cloud)
    np.testing.assert_array_equal(legacy_normals, normals)
    with pytest.raises(mereo.InputError, match="not organized"):
        mereo.o3d.cloud_from_pointcloud(pcd, 10, 10)


def test_frames_from_open3d_recognize_what_the_original_does(o3d, frame):
    want = _accepted(mereo.recognize(frame))
    assert "mug" in want
    h, w = frame.depth.shape
    k = frame.intrinsics
    # an RGBDImage as Open3D makes it from a colour image and 16-bit millimetres
    depth_mm = np.where(np.isfinite(frame.depth), np.round(frame.depth * 1000), 0).astype(np.uint16)
    rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
        o3d.geometry.Image(np.ascontiguousarray(frame.color)), o3d.geometry.Image(depth_mm),
        depth_scale=1000.0, depth_trunc=10.0, convert_rgb_to_intensity=False)
    intrinsic = o3d.camera.PinholeCameraIntrinsic(w, h, k.fx, k.fy, k.cx, k.cy)
    f = mereo.o3d.frame_from_rgbd(rgbd, intrinsic)
    assert f.depth.shape == (h, w) and np.nanmax(np.abs(f.depth - frame.depth)) <= 0.0006
    assert _accepted(mereo.recognize(f)) == want
    # an organized tensor point cloud: intrinsics fitted to its points
    pcd = mereo.o3d.to_pointcloud(mereo.extension.back_project(frame), colors=frame.color)
    g = mereo.o3d.frame_from_pointcloud(pcd, h, w)
    assert abs(g.intrinsics.fx - k.fx) < 0.01 * k.fx and abs(g.intrinsics.cx - k.cx) < 1.0
    assert _accepted(mereo.recognize(g)) == want
    with pytest.raises(mereo.InputError, match="intrinsic"):
        mereo.o3d.frame_from_rgbd(rgbd, o3d.camera.PinholeCameraIntrinsic(w // 2, h // 2, k.fx, k.fy, k.cx, k.cy))


def test_primitives_become_meshes_on_their_parts(o3d, frame):
    result = mereo.recognize(frame)
    meshes = mereo.o3d.primitive_meshes(result)
    parts = [p for o in result["objects"] if o["accepted"] and "parts" in o for p in o["parts"].values()
             if p["class"] in ("cylinder", "cone", "sphere", "torus")]
    assert len(meshes) == len(parts) >= 2
    for m, p in zip(meshes, parts):
        v = np.asarray(m.vertices)
        if p["class"] == "cylinder":  # every vertex on the wall or the end discs
            a = np.asarray(p["axis"]) / np.linalg.norm(p["axis"])
            d = v - np.asarray(p["point"])
            along = d @ a
            radial = np.linalg.norm(d - np.outer(along, a), axis=1)
            assert np.all(radial <= p["radius"] + 1e-6) and np.all(np.abs(along) <= p["height"] / 2 + 1e-6)
            assert np.isclose(radial.max(), p["radius"], rtol=1e-3)
        if p["class"] == "torus":
            c = np.asarray(p["center"])
            assert np.linalg.norm(v - c, axis=1).max() == pytest.approx(p["major_radius"] + p["minor_radius"], rel=1e-2)
