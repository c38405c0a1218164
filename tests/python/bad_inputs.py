"""Bad input and what mereo says about it: one table for the regression tests (test_bad_input.py)
and the documentation (scripts/bad_input_table.py writes docs/bad_input.md from it).

Each case writes its input files into a folder beside two valid frames (`good.pcd`, a PCD file of
synthetic:0, and `pair/a_rgb.png` + `pair/a_depth.png` + `pair/intrinsics.json`, the same frame
as a PNG pair) and says how mereo is called: inputs and options, given alike to `mereo
recognize`, the Python API and `mereo-run`. `message` is a regular expression the one line must
match. A case with `result=True` is valid but extreme data: it gives a result (objects or an
empty result whose warning says why), never an error.
"""
from __future__ import annotations

import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np


@dataclass
class Case:
    name: str
    what: str  # the bad input, in words
    make: Callable[[Path], list[str]]  # writes the files into a folder; returns the inputs
    message: str  # regular expression the one-line error (or the result's warning) matches
    options: dict = field(default_factory=dict)  # intrinsics, depth_scale, models (a file), graph (a file)
    result: bool = False  # valid but extreme: a result, not an error
    objects: bool = False  # (with result) the frame's objects are still found
    front_ends: tuple = ("cli", "python", "mereo-run")


# ---- writing the inputs ---------------------------------------------------------------------


def _pcd_header(width, height, data="binary", **over):
    h = {"VERSION": "0.7", "FIELDS": "x y z rgb", "SIZE": "4 4 4 4", "TYPE": "F F F U", "COUNT": "1 1 1 1",
         "WIDTH": str(width), "HEIGHT": str(height), "VIEWPOINT": "0 0 0 1 0 0 0",
         "POINTS": str(width * height), "DATA": data}
    h.update(over)
    return "".join(f"{k} {v}\n" for k, v in h.items() if v is not None).encode()


def _good_cloud(d: Path):
    """The valid frame's points and colour (from good.pcd, written by make_base)."""
    import mereo

    f = mereo.io.read(str(d.parent / "base" / "good.pcd"))
    return np.array(f.cloud, dtype=np.float32), np.array(f.color)


def binary_pcd(path: Path, xyz: np.ndarray, rgb: np.ndarray, **header) -> list[str]:
    H, W = xyz.shape[:2]
    rec = np.zeros((H, W), dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("c", "<u4")])
    rec["x"], rec["y"], rec["z"] = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    rec["c"] = (255 << 24) | (rgb[..., 0].astype(np.uint32) << 16) | (rgb[..., 1].astype(np.uint32) << 8) | rgb[..., 2]
    path.write_bytes(_pcd_header(W, H, **header) + rec.tobytes())
    return [str(path)]


def ascii_pcd(path: Path, width=4, height=3, **header) -> list[str]:
    body = "".join(f"{(u - 2) * 0.01} {(v - 1) * 0.01} 1.0 4278190335\n" for v in range(height) for u in range(width))
    path.write_bytes(_pcd_header(width, height, data="ascii", **header) + body.encode())
    return [str(path)]


def _pcd(**header):
    def make(d: Path):
        xyz, rgb = _good_cloud(d)
        return binary_pcd(d / "bad.pcd", xyz, rgb, **header)
    return make


def _ascii(**header):
    return lambda d: ascii_pcd(d / "bad.pcd", **header)


def _scaled(rows: slice):
    def make(d: Path):
        xyz, rgb = _good_cloud(d)
        xyz[rows] *= np.float32(1e30)  # float32: 1e30 x 1e30 overflows to inf, both are out of range
        return binary_pcd(d / "extreme.pcd", xyz, rgb)
    return make


def _prefixed(prefix: bytes):
    def make(d: Path):
        (d / "bad.pcd").write_bytes(prefix + (d.parent / "base" / "good.pcd").read_bytes())
        return [str(d / "bad.pcd")]
    return make


def write_png(path: Path, image: np.ndarray) -> None:
    """A grey (H, W) or RGB (H, W, 3) PNG of 8- or 16-bit values (no imaging library needed)."""
    import struct
    import zlib

    grey = image.ndim == 2
    bits = 16 if image.dtype == np.uint16 else 8
    rows = image.astype(">u2" if bits == 16 else "u1").reshape(image.shape[0], -1).view(np.uint8)
    raw = b"".join(b"\0" + row.tobytes() for row in rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    head = struct.pack(">IIBBBBB", image.shape[1], image.shape[0], bits, 0 if grey else 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) + chunk(b"IDAT", zlib.compress(raw)) +
                     chunk(b"IEND", b""))


def _pair(depth=None, intrinsics=None):
    """The valid PNG pair, with its depth image (a function of the metres) or intrinsics.json replaced."""
    def make(d: Path):
        import mereo

        shutil.copytree(d.parent / "base" / "pair", d / "pair")
        if depth is not None:
            metres = np.nan_to_num(mereo.io.read(str(d / "pair" / "a_depth.png")).depth)
            write_png(d / "pair" / "a_depth.png", depth(np.round(metres * 1000).astype(np.uint16)))
        if intrinsics is not None:
            (d / "pair" / "intrinsics.json").write_text(intrinsics)
        return [str(d / "pair" / "a_depth.png")]
    return make


def _tum(groundtruth: str):
    def make(d: Path):
        t = d / "tum"
        shutil.copytree(d.parent / "base" / "pair", t)
        (t / "rgb.txt").write_text("1.0 a_rgb.png\n")
        (t / "depth.txt").write_text("1.0 a_depth.png\n")
        (t / "groundtruth.txt").write_text("# timestamp tx ty tz qx qy qz qw\n" + groundtruth)
        return [str(t)]
    return make


def _file(name: str, data: bytes, inputs=("synthetic:0",)):
    def make(d: Path):
        (d / name).write_bytes(data)
        return list(inputs)
    return make


def _truncated(d: Path):
    xyz, rgb = _good_cloud(d)
    binary_pcd(d / "bad.pcd", xyz, rgb)
    (d / "bad.pcd").write_bytes((d / "bad.pcd").read_bytes()[:5000])
    return [str(d / "bad.pcd")]


def _copy_pair_as(name: str):
    def make(d: Path):
        shutil.copy(d.parent / "base" / "pair" / "a_rgb.png", d / name)
        return [str(d / name)]
    return make


MODEL = b"""concepts:
  - name: saucer
    parent: plate
"""

CASES = [
    # PCD files
    Case("pcd_coordinates_1e30", "PCD file whose coordinates are all multiplied by 1e30",
         _scaled(slice(None)), r"support plane: too few valid points.*empty or all NaN", result=True),
    Case("pcd_some_coordinates_1e30", "PCD file whose top 100 rows are multiplied by 1e30 (the table and objects "
         "are below)", _scaled(slice(0, 100)), r"", result=True, objects=True),
    Case("pcd_negative_count_binary", "binary PCD header with `COUNT -1 1 1 1`", _pcd(COUNT="-1 1 1 1"),
         r"bad\.pcd: field 'x' COUNT '-1': expected 1 to 4096"),
    Case("pcd_negative_count_ascii", "ascii PCD header with `COUNT -1 1 1 1`", _ascii(COUNT="-1 1 1 1"),
         r"bad\.pcd: field 'x' COUNT '-1': expected 1 to 4096"),
    Case("pcd_negative_size_binary", "binary PCD header with `SIZE -4 4 4 4`", _pcd(SIZE="-4 4 4 4"),
         r"bad\.pcd: field 'x' SIZE '-4': expected 1, 2, 4 or 8"),
    Case("pcd_negative_size_ascii", "ascii PCD header with `SIZE -4 4 4 4`", _ascii(SIZE="-4 4 4 4"),
         r"bad\.pcd: field 'x' SIZE '-4': expected 1, 2, 4 or 8"),
    Case("pcd_rgb_size_1", "PCD with an `rgb` field of `SIZE 1`", _pcd(SIZE="4 4 4 1"),
         r"bad\.pcd: field rgb has SIZE 1 COUNT 1: a packed colour is SIZE 4, COUNT 1"),
    Case("pcd_header_not_utf8", "PCD header line with bytes that are not UTF-8", _prefixed(b"FOO\xe9 1\n"),
         r"bad\.pcd: not a PCD file \(line 1: 'FOO\\xe9 1' is not a header line"),
    Case("pcd_comment_not_utf8", "PCD comment with Latin-1 text (valid: comments are skipped)",
         _prefixed(b"# caf\xe9\n"), r"", result=True, objects=True),
    Case("pcd_no_data_line", "PCD file without its `DATA` line", _ascii(DATA=None),
         r"bad\.pcd: not a PCD file \(line 10: '-0\.02 -0\.01 1\.0 4278190335' is not a header line, "
         r"and no DATA line came before it\)"),
    Case("pcd_is_a_png", "a PNG image renamed `.pcd`", _copy_pair_as("bad.pcd"),
         r"bad\.pcd: not a PCD file \(line 1: '\\x89PNG' is not a header line"),
    Case("pcd_huge_ascii", "ascii PCD with `WIDTH 100000 HEIGHT 100000`", _ascii(WIDTH="100000", HEIGHT="100000",
         POINTS="10000000000"), r"bad\.pcd: line 6: WIDTH '100000': expected a whole number from 1 to 65536"),
    Case("pcd_size_overflows_32_bits", "ascii PCD whose WIDTH x HEIGHT overflows 32 bits (65536 x 65536)",
         _ascii(WIDTH="65536", HEIGHT="65536", POINTS=None),
         r"bad\.pcd: WIDTH 65536 x HEIGHT 65536 is more than 33554432 points"),
    Case("pcd_truncated", "binary PCD cut short", _truncated, r"bad\.pcd: truncated PCD file"),
    # PNG pairs
    Case("depth_png_8_bit", "8-bit depth PNG", _pair(depth=lambda raw: (raw // 256).astype(np.uint8)),
         r"a_depth\.png: a depth image must have one channel of 16-bit units or 32-bit float metres, "
         r"this one has 1 channel\(s\) of 8-bit values"),
    Case("depth_png_3_channels", "3-channel (colour) depth PNG", _pair(depth=lambda raw: np.dstack([raw] * 3)),
         r"a_depth\.png: a depth image must have one channel .* this one has 3 channel\(s\) of 16-bit values"),
    Case("intrinsics_json_depth_scale_0", "`depth_scale: 0` in intrinsics.json",
         _pair(intrinsics='{"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "depth_scale": 0}'),
         r"intrinsics\.json: field 'depth_scale': depth scale 0 is not a finite positive number"),
    Case("intrinsics_json_depth_scale_negative", "`depth_scale: -1000` in intrinsics.json",
         _pair(intrinsics='{"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "depth_scale": -1000}'),
         r"intrinsics\.json: field 'depth_scale': depth scale -1000 is not a finite positive number"),
    Case("tum_zero_quaternion", "TUM `groundtruth.txt` with a zero quaternion", _tum("1.0 0 0 0 0 0 0 0\n"),
         r"groundtruth\.txt:2: the quaternion 0 0 0 0 has norm 0 \(expected a unit quaternion, within 0\.01\)"),
    # options
    Case("depth_scale_tiny", "`--depth-scale 1e-30` (every depth beyond any sensor's range)",
         _pair(), r"support plane: too few valid points", options={"depth_scale": 1e-30}, result=True),
    Case("depth_scale_inf", "`--depth-scale inf`", _pair(), r"depth scale inf is not a finite positive number",
         options={"depth_scale": float("inf")}),
    Case("depth_scale_negative", "`--depth-scale -1000`", _pair(),
         r"depth scale -1000 is not a finite positive number", options={"depth_scale": -1000.0}),
    Case("depth_scale_nan", "`--depth-scale nan`", _pair(), r"depth scale nan is not a finite positive number",
         options={"depth_scale": float("nan")}),
    Case("intrinsics_1e300", "`--intrinsics 1e300,1e300,319.5,239.5`", _pair(),
         r"fx 1e\+300 is not a focal length in pixels \(expected 0 < fx <= 100000\)",
         options={"intrinsics": "1e300,1e300,319.5,239.5"}),
    Case("intrinsics_centre_outside", "`--intrinsics 525,525,5000,239.5` (centre outside the image)", _pair(),
         r"a_depth\.png: intrinsics: the principal point \(5000, 239\.5\) is outside the 640x480 image",
         options={"intrinsics": "525,525,5000,239.5"}),
    # model and graph files
    Case("model_defined_twice", "a concept defined twice in one model file",
         _file("twice.yaml", MODEL + b"  - name: saucer\n    parent: plate\n"),
         r"twice\.yaml:4:5: concept 'saucer' is defined twice in this file \(first at .*twice\.yaml:2:5\)",
         options={"models": "twice.yaml"}, front_ends=("cli", "python")),
    Case("model_key_not_scalar", "a model file whose key is not a scalar (`[a, b]: 1`)",
         _file("key.yaml", b"concepts:\n  - name: saucer\n    [a, b]: 1\n"),
         r"key\.yaml:3:5: field '\(a key in a concept\)': expected a text, got a list",
         options={"models": "key.yaml"}, front_ends=("cli", "python")),
    Case("model_not_utf8", "a model file with Latin-1 text",
         _file("latin.yaml", b"concepts:\n  - name: saucer\n    description: caf\xe9 au lait\n    parent: caf\xe9\n"),
         r"latin\.yaml:2:5: field 'parent': unknown concept 'caf\\xe9'", options={"models": "latin.yaml"},
         front_ends=("cli", "python")),
    Case("graph_not_utf8", "a graph file with Latin-1 text",
         _file("latin_graph.yaml", b"nodes:\n  - {name: source, kind: frame_s\xe9urce}\n"),
         r"latin_graph\.yaml:2: .*frame_s\\xe9urce", options={"graph": "latin_graph.yaml"}),
    Case("graph_without_result", "`--graph` whose graph has no `result` node",
         _file("noresult.yaml", b"nodes:\n  - {name: source, kind: frame_source}\n"),
         r"noresult\.yaml: the graph has no node 'result' with an output 'result'",
         options={"graph": "noresult.yaml"}, front_ends=("cli", "python")),
]


def make_base(base: Path) -> None:
    """The valid frame both ways: base/good.pcd and base/pair/a_{rgb,depth}.png + intrinsics.json."""
    import mereo

    base.mkdir(parents=True, exist_ok=True)
    f = mereo.io.read("synthetic:0")
    mereo.io.write_pcd(str(base / "good.pcd"), f)
    mereo.io.write_png_pair(str(base / "pair"), "a", f, 1000.0)


def cli_args(case: Case, inputs: list[str], folder: Path) -> list[str]:
    """`mereo recognize` arguments for the case (files named in options live in `folder`)."""
    o = case.options
    args = ["recognize", *inputs]
    if "intrinsics" in o:
        args += ["--intrinsics", o["intrinsics"]]
    if "depth_scale" in o:
        args += ["--depth-scale", repr(o["depth_scale"])]
    if "models" in o:
        args += ["--models", str(folder / o["models"])]
    if "graph" in o:
        args += ["--graph", str(folder / o["graph"])]
    return args


def one_line(text: str, pattern: str) -> str | None:
    """The line of `text` that matches `pattern`, if any."""
    for line in text.splitlines():
        if re.search(pattern, line):
            return line
    return None
