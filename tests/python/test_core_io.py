"""Frames reach Python as NumPy arrays that share the C++ memory; readers give clear errors."""
import json
import subprocess
import sys

import numpy as np
import pytest

import mereo


def test_pcd_cloud_is_a_view_of_the_cpp_buffer(real):
    frame = mereo.io.read(real / "pcl" / "table_scene_mug_stereo_textured.pcd")
    cloud = frame.cloud
    assert cloud.shape == (480, 640, 3) and cloud.dtype == np.float32
    # The array's memory is the C++ object's buffer: same address, and writes show through.
    assert cloud.__array_interface__["data"][0] == frame._buffer_address("cloud")
    again = frame.cloud
    assert np.shares_memory(cloud, again)
    i = np.argwhere(np.isfinite(cloud[..., 2]))[0]
    cloud[i[0], i[1], 2] = 123.0
    assert again[i[0], i[1], 2] == 123.0
    # The view keeps the buffer alive after the frame is gone.
    del frame, again
    assert cloud[i[0], i[1], 2] == 123.0
    assert np.isnan(cloud).any()


def test_images_are_views_too():
    frame = mereo.io.read("synthetic:1")
    for name in ("color", "depth", "cloud"):
        arr = getattr(frame, name)
        assert arr.__array_interface__["data"][0] == frame._buffer_address(name), name
    assert frame.color.shape == (480, 640, 3) and frame.color.dtype == np.uint8
    assert frame.depth.shape == (480, 640) and frame.depth.dtype == np.float32
    assert frame.pose.shape == (4, 4)
    # back_project agrees with the pinhole model.
    K = frame.intrinsics
    v, u = 100, 200
    z = frame.depth[v, u]
    assert np.isfinite(z)
    np.testing.assert_allclose(frame.cloud[v, u], [(u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z], rtol=1e-6)


def test_png_pair_round_trip_and_size_mismatch(tmp_path):
    frame = mereo.io.read("synthetic:2")
    mereo.io.write_png_pair(tmp_path, "0001", frame, depth_scale=5000)
    back = mereo.io.read(tmp_path)
    assert back.intrinsics == frame.intrinsics
    ok = np.isfinite(frame.depth) & (frame.depth < 13)
    np.testing.assert_allclose(back.depth[ok], frame.depth[ok], atol=1.01 / 10000)
    np.testing.assert_array_equal(back.color, frame.color)
    # A depth image of another size beside the colour image: one error naming the file.
    small = mereo.Frame()
    small.depth = np.ones((24, 32), np.float32)
    small.color = np.zeros((24, 32, 3), np.uint8)
    mereo.io.write_png_pair(tmp_path / "small", "0001", small)
    (tmp_path / "0001_depth.png").write_bytes((tmp_path / "small" / "0001_depth.png").read_bytes())
    with pytest.raises(mereo.InputError, match=r"0001_depth.png.*32x24"):
        mereo.io.read(tmp_path / "0001_depth.png")


def test_errors_name_the_file(tmp_path):
    with pytest.raises(mereo.InputError, match="nothing.pcd: no such"):
        mereo.io.read(tmp_path / "nothing.pcd")
    bad = tmp_path / "bad.pcd"
    bad.write_bytes(b"VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 640\nHEIGHT 480\nDATA binary\n\x00\x01")
    with pytest.raises(mereo.InputError, match="bad.pcd: truncated"):
        mereo.io.read(bad)
    assert issubclass(mereo.InputError, ValueError)


def test_synthetic_sequence_has_poses_and_ground_truth():
    seq = mereo.io.open("synthetic:4", frames=3)
    assert len(seq) == 3 and seq.ids == ["0000", "0001", "0002"]
    poses = [seq[i].pose for i in range(3)]
    assert not np.allclose(poses[0], poses[1])
    sf = mereo.synthetic.render(4)
    truth = json.loads(sf.truth_json())
    models = {o["model"] for o in truth["objects"]}
    assert {"table", "floor"} <= models
    assert sf.truth.objects.shape == (480, 640) and sf.truth.normals.shape == (480, 640, 3)
    np.testing.assert_array_equal(sf.frame.depth, seq[0].depth)  # same seed, same frame


def run_cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "mereo.cli", *map(str, args)], capture_output=True, text=True, cwd=cwd)


def test_cli_render_writes_frames_and_truth(tmp_path):
    r = run_cli("render", "synthetic:5", "--frames", "2", "--out", tmp_path, "--preview")
    assert r.returncode == 0, r.stderr
    for name in ("0000_rgb.png", "0001_depth.png", "0001_truth.json", "0000_normals.npy", "0000_preview.png",
                 "intrinsics.json"):
        assert (tmp_path / name).is_file(), name
    seq = mereo.io.open(tmp_path)
    assert len(seq) == 2
    normals = np.load(tmp_path / "0000_normals.npy")
    n = normals[np.isfinite(normals[..., 0])]
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)


def test_cli_bad_input_is_one_line_and_nonzero(tmp_path):
    r = run_cli("info", tmp_path / "missing.pcd")
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0 and "missing.pcd" in r.stderr
    r = run_cli("render", "synthetic:x", "--out", tmp_path)
    assert r.returncode == 2 and "synthetic:x" in r.stderr


def test_cli_info_on_real_frames(real):
    r = run_cli("info", real / "pcl-mosd" / "test34.pcd", real / "posecnn" / "000001-depth.png",
                "--intrinsics", "1066.778,1067.487,312.9869,241.3109", "--depth-scale", "10000")
    assert r.returncode == 0, r.stderr
    assert "test34: 640x480" in r.stdout and "labels" in r.stdout
    assert "000001: 640x480" in r.stdout
