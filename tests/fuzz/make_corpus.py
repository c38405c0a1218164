#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpus, tests/fuzz/corpus/<target>/: small valid inputs.

  pcd       a 5x4 organized cloud in ascii, binary and binary_compressed (x y z, colour, labels)
  png_pair  5x4 colour/depth pairs in fuzz_png_pair's layout (flags, two lengths, the images,
            the intrinsics text): 16-bit and 8-bit PNG depth, NYU's PGM, a PPM colour image
  model     the shipped model file (graphs/models/tabletop.yaml), whole and one concept each
  graph     the shipped graphs (graphs/*.yaml)
  python    fuzz_python.py's: the pcd, model and graph seeds behind its reader byte (0, 1, 2)

Standard library only (PNG through zlib, LZF as literal runs); the output is deterministic.
Run it after changing the shipped models or graphs: python3 tests/fuzz/make_corpus.py
"""
import pathlib
import re
import struct
import zlib

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = pathlib.Path(__file__).resolve().parent / "corpus"
W, H = 5, 4
FX = FY = 5.0
CX, CY = 2.0, 1.5


def points():
    """The cloud of a tilted plane seen by a pinhole camera: (x, y, z, rgb, label) per pixel."""
    for v in range(H):
        for u in range(W):
            z = 1.0 + 0.05 * u + 0.02 * v
            x, y = (u - CX) / FX * z, (v - CY) / FY * z
            rgb = (40 * u) << 16 | (60 * v) << 8 | 200
            yield x, y, z, rgb, 1 + (u + v) % 3


def pcd_header(fields, sizes, types, data):
    return (
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
        f"FIELDS {' '.join(fields)}\nSIZE {' '.join(map(str, sizes))}\nTYPE {' '.join(types)}\n"
        f"COUNT {' '.join('1' * len(fields))}\nWIDTH {W}\nHEIGHT {H}\nVIEWPOINT 0 0 0 1 0 0 0\n"
        f"POINTS {W * H}\nDATA {data}\n"
    ).encode()


def lzf_literals(data):
    """LZF as literal runs only (control byte n - 1, then n <= 32 bytes): valid, not smaller."""
    out = bytearray()
    for i in range(0, len(data), 32):
        chunk = data[i : i + 32]
        out += bytes([len(chunk) - 1]) + chunk
    return bytes(out)


def pcd_seeds():
    pts = list(points())
    ascii_body = "".join(f"{x:.6f} {y:.6f} {z:.6f} {c}\n" for x, y, z, c, _ in pts)
    yield "ascii_xyz_rgb.pcd", pcd_header("x y z rgb".split(), [4] * 4, "F F F U".split(), "ascii") + ascii_body.encode()
    binary = b"".join(struct.pack("<fffI", x, y, z, c) for x, y, z, c, _ in pts)
    yield "binary_xyz_rgb.pcd", pcd_header("x y z rgb".split(), [4] * 4, "F F F F".split(), "binary") + binary
    # binary_compressed stores the fields one after another (all x, all y, ...)
    soa = b"".join(struct.pack("<f", p[k]) for k in range(3) for p in pts)
    soa += b"".join(struct.pack("<I", 0xFF000000 | p[3]) for p in pts)
    soa += b"".join(struct.pack("<I", p[4]) for p in pts)
    packed = lzf_literals(soa)
    header = pcd_header("x y z rgba label".split(), [4] * 5, "F F F U U".split(), "binary_compressed")
    yield "compressed_xyz_rgba_label.pcd", header + struct.pack("<II", len(packed), len(soa)) + packed


def png(width, height, bit_depth, colour_type, rows):
    """A PNG file; `rows` are the raw scanlines (big-endian samples), filter 0 each."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\0" + r for r in rows)
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def pair(flags, colour, depth, intrinsics=b""):
    return bytes([flags]) + struct.pack("<HH", len(colour), len(depth)) + colour + depth + intrinsics


def png_pair_seeds():
    pts = list(points())
    rgb_rows = [b"".join(bytes([c >> 16 & 255, c >> 8 & 255, c & 255]) for *_, c, _ in pts[v * W : (v + 1) * W]) for v in range(H)]
    colour = png(W, H, 8, 2, rgb_rows)
    mm = [[round(p[2] * 1000) for p in pts[v * W : (v + 1) * W]] for v in range(H)]
    depth16 = png(W, H, 16, 0, [struct.pack(f">{W}H", *r) for r in mm])
    depth8 = png(W, H, 8, 0, [bytes(min(255, d // 8) for d in r) for r in mm])
    json_k = b'{"fx": 5, "fy": 5, "cx": 2, "cy": 1.5, "depth_scale": 1000}\n'
    matrix_k = b"5 0 2\n0 5 1.5\n0 0 1\n"
    # NYU's raw Kinect values: a 16-bit PGM whose samples are little-endian, 2047 = none
    nyu = [[min(2046, round(1092.5 - 351.3 / p[2])) for p in pts[v * W : (v + 1) * W]] for v in range(H)]
    pgm = f"P5\n{W} {H}\n65535\n".encode() + b"".join(struct.pack(f"<{W}H", *r) for r in nyu)
    ppm = f"P6\n{W} {H}\n255\n".encode() + b"".join(rgb_rows)
    yield "png16_option_intrinsics", pair(0, colour, depth16)
    yield "png16_intrinsics_json", pair(0, colour, depth16, json_k)
    yield "png8_camera_matrix", pair(8, colour, depth8, matrix_k)
    yield "sun3d_png16", pair(1, colour, depth16)
    yield "nyu_pgm_ppm", pair(2 | 4 | 0x20, ppm, pgm)


def model_seeds():
    text = (ROOT / "graphs/models/tabletop.yaml").read_text()
    yield "tabletop.yaml", text
    body = text[text.index("concepts:") :]
    for block in re.split(r"\n(?=  - name: )", body)[1:]:
        name = re.match(r"  - name: (\w+)", block).group(1)
        yield f"{name}.yaml", "concepts:\n" + block.rstrip() + "\n"
    for f in ("model_typo.yaml", "model_unknown_class.yaml"):
        yield f, (ROOT / "tests/data" / f).read_text()


def graph_seeds():
    for f in sorted((ROOT / "graphs").glob("*.yaml")):
        yield f.name, f.read_text()
    yield "dangling.yaml", (ROOT / "tests/data/dangling.yaml").read_text()


def main():
    for target, seeds in (("pcd", pcd_seeds), ("png_pair", png_pair_seeds), ("model", model_seeds), ("graph", graph_seeds)):
        folder = OUT / target
        folder.mkdir(parents=True, exist_ok=True)
        for old in folder.iterdir():
            old.unlink()
        for name, content in seeds():
            (folder / name).write_bytes(content if isinstance(content, bytes) else content.encode())
    python = OUT / "python"
    python.mkdir(exist_ok=True)
    for old in python.iterdir():
        old.unlink()
    for byte, target in enumerate(("pcd", "model", "graph")):
        for seed in sorted((OUT / target).iterdir()):
            (python / f"{target}_{seed.name}").write_bytes(bytes([byte]) + seed.read_bytes())
    print(f"make_corpus: wrote {sum(1 for _ in OUT.rglob('*') if _.is_file())} seeds to {OUT}")


if __name__ == "__main__":
    main()
