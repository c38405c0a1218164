"""Frames reach Python as NumPy arrays that share the C++ memory; readers give clear errors."""
import json
import subprocess
import sys

import numpy as np
import pytest

import mereo
from conftest import ROOT


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
    small.intrinsics = mereo.Intrinsics(30, 30, 15.5, 11.5)
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


def _seven_scenes(tmp_path, f):
    """A 7-Scenes/3DMatch folder of one frame: seq/frame-000000.{color,depth}.png and .pose.txt,
    camera-intrinsics.txt beside seq/."""
    seq = tmp_path / "seq-01"
    seq.mkdir()
    mereo.io.write_png_pair(seq, "x", f)
    (seq / "x_rgb.png").rename(seq / "frame-000000.color.png")
    (seq / "x_depth.png").rename(seq / "frame-000000.depth.png")
    (seq / "intrinsics.json").unlink()
    K = f.intrinsics
    (tmp_path / "camera-intrinsics.txt").write_text(f"{K.fx} 0 {K.cx}\n0 {K.fy} {K.cy}\n0 0 1\n")
    np.savetxt(seq / "frame-000000.pose.txt", np.asarray(f.pose))
    return seq


def test_seven_scenes_layout_and_nvlabs_camera_params(tmp_path):
    f = mereo.synthetic.render(3).frame
    seq = _seven_scenes(tmp_path, f)
    (g,) = [mereo.io.open(seq)[i] for i in range(len(mereo.io.open(seq)))]
    assert g.id == "frame-000000"
    assert g.intrinsics.fx == pytest.approx(f.intrinsics.fx) and g.intrinsics.cy == pytest.approx(f.intrinsics.cy)
    assert np.allclose(g.pose, f.pose, atol=1e-9) and not g.gravity_aligned  # a SLAM world: not trusted as up
    assert np.nanmax(np.abs(g.depth - f.depth)) < 0.001  # millimetres
    # NVlabs' camera_params.json (x_offset, y_offset, depth_scale) beside NAME-color.png/NAME-depth.png
    nv = tmp_path / "nv"
    nv.mkdir()
    mereo.io.write_png_pair(nv, "cup", f, 4000.0)
    (nv / "cup_rgb.png").rename(nv / "cup-color.png")
    (nv / "cup_depth.png").rename(nv / "cup-depth.png")
    (nv / "intrinsics.json").unlink()
    K = f.intrinsics
    (nv / "camera_params.json").write_text(json.dumps(
        {"fx": K.fx, "fy": K.fy, "x_offset": K.cx, "y_offset": K.cy, "depth_scale": 4000.0}))
    h = mereo.io.read(nv / "cup-depth.png")
    assert h.intrinsics.cx == pytest.approx(K.cx) and np.nanmax(np.abs(h.depth - f.depth)) < 0.001
    assert h.gravity_aligned and h.pose is None
    # a pose file that is no rigid transform is named
    (seq / "frame-000000.pose.txt").write_text("1 2 3\n")
    with pytest.raises(mereo.InputError, match=r"frame-000000.pose.txt: expected a 4x4"):
        mereo.io.read(seq)


def test_real_seven_scenes_and_nvlabs_frames_are_read_and_runs_complete(real, tmp_path):
    seq = mereo.io.open(real / "nvblox-3dmatch" / "seq-01")
    assert len(seq) == 5
    f = seq[0]
    assert f.intrinsics.fx == pytest.approx(570.342205) and f.pose is not None and not f.gravity_aligned
    g = mereo.io.read(real / "nv-6dof-graspnet" / "red_mug-depth.png")
    assert g.intrinsics.fx == pytest.approx(616.3652954) and 0.3 < np.nanmedian(g.depth) < 0.6
    # the hand-held sequence (its world not gravity-aligned) runs to its end: each frame names its
    # support surface or says why there is none
    out = tmp_path / "r.jsonl"
    r = subprocess.run([sys.executable, "-m", "mereo.cli", "recognize", str(real / "nvblox-3dmatch" / "seq-01"),
                        "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    lines = [json.loads(s) for s in out.read_text().splitlines()]
    assert len(lines) == 5
    for line in lines:
        assert line.get("support_plane") or line.get("warnings"), line["frame"]
        assert line["source"].endswith(line["frame"] + ".depth.png")
        assert "camera_pose" in line or line.get("warnings")


def test_sun3d_and_nyu_depth_formats(real):
    """SUN3D stores depth bit-rotated and NYU Depth v2 raw Kinect values little-endian in a PGM;
    the files cannot tell, so depth_format says which. Read as plain units they are nonsense (a
    median of 21 m and 54 m); decoded, SUN's matches its SOURCE.md (1,057-9,870 mm, median 2,723)."""
    K = "525,525,319.5,239.5"
    sun = mereo.io.read(real / "open3d" / "SUN_depth.png", intrinsics=K, depth_format="sun3d")
    z = sun.depth[np.isfinite(sun.depth)]
    assert z.min() == pytest.approx(1.057, abs=1e-6) and z.max() == pytest.approx(9.870, abs=1e-6)
    assert np.median(z) == pytest.approx(2.723, abs=1e-6)
    plain = mereo.io.read(real / "open3d" / "SUN_depth.png", intrinsics=K)
    assert np.nanmedian(plain.depth) > 15
    nyu = mereo.io.read(real / "open3d" / "NYU_depth.pgm", intrinsics=K, depth_format="nyu-raw")
    z = nyu.depth[np.isfinite(nyu.depth)]
    assert 0.85 < z.size / nyu.depth.size < 0.97 and 0.5 < z.min() and z.max() < 10 and 2 < np.median(z) < 5
    with pytest.raises(mereo.InputError, match="depth format 'kinect' is not one of"):
        mereo.io.read(real / "open3d" / "SUN_depth.png", intrinsics=K, depth_format="kinect")
    # the corridor's floor is its support (the real-sensor issue: every run names its support or says why not)
    r = mereo.recognize(sun)
    assert r.get("support_plane") or r.get("warnings"), r


def test_depth_from_a_second_camera_is_registered_to_the_colour_camera(real, tmp_path):
    """An intrinsics file with a "depth_camera" (NYU's Kinect: data/cameras/nyu_depth_v2_kinect.json)
    registers the depth to the colour camera as it is read: the frame has the colour camera's
    intrinsics, the depth is where the colour camera sees it (how well: test_register's C++ tests),
    and the run goes on as for any frame; a malformed depth camera is a clear error."""
    cal = ROOT / "data" / "cameras" / "nyu_depth_v2_kinect.json"
    nyu = real / "open3d" / "NYU_depth.pgm"
    one = mereo.io.read(nyu, intrinsics=mereo.io.read_intrinsics(str(cal)), depth_format="nyu-raw")
    reg = mereo.io.read(nyu, intrinsics=cal, depth_format="nyu-raw")
    assert reg.intrinsics.fx == pytest.approx(518.858, abs=1e-3) and reg.depth.shape == reg.color.shape[:2]
    # the depth camera's longer focal length covers less of the colour image
    assert 0.65 < np.isfinite(reg.depth).mean() < np.isfinite(one.depth).mean() - 0.1
    assert np.nanmedian(reg.depth) == pytest.approx(np.nanmedian(one.depth), rel=0.05)
    r = mereo.recognize(reg)
    assert r.get("support_plane") or r.get("warnings")
    bad = json.loads(cal.read_text())
    bad["depth_camera"]["to_color"][0][0] = 2.0
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    with pytest.raises(mereo.InputError, match="not a rigid transform"):
        mereo.io.read(nyu, intrinsics=tmp_path / "bad.json", depth_format="nyu-raw")


def test_register_depth_from_python_matches_reading_with_the_depth_camera(real):
    """mereo.signal.register_depth is the registration io.read applies with a "depth_camera"."""
    cal = ROOT / "data" / "cameras" / "nyu_depth_v2_kinect.json"
    nyu = real / "open3d" / "NYU_depth.pgm"
    one = mereo.io.read(nyu, intrinsics=mereo.io.read_intrinsics(str(cal)), depth_format="nyu-raw")
    reg = mereo.io.read(nyu, intrinsics=cal, depth_format="nyu-raw")
    d = json.loads(cal.read_text())["depth_camera"]
    K = mereo.Intrinsics(d["fx"], d["fy"], d["cx"], d["cy"])
    out = mereo.signal.register_depth(one.depth, K, np.asarray(d["to_color"]), reg.intrinsics, *reg.depth.shape)
    assert np.array_equal(np.isfinite(out), np.isfinite(reg.depth))
    assert np.nanmax(np.abs(out - reg.depth)) == 0
    with pytest.raises(mereo.InputError, match="not a rotation"):
        mereo.signal.register_depth(one.depth, K, 2 * np.eye(4), reg.intrinsics, 480, 640)
