#!/usr/bin/env python3
"""Behaviour before and after a change: the recognition results on a fixed set of frames.

    python tests/compare_results.py run OUT_DIR          # results of the installed mereo
    python tests/compare_results.py diff BEFORE AFTER    # what changed, apart from timings

`run` recognizes, one frame at a time (deterministic mode, the shipped tabletop graph):
  - the renderer's default scenes synthetic:0 ... synthetic:49 (one frame each);
  - one tracked orbit, synthetic:700 with 12 frames (tabletop_tracking.yaml);
  - every frame in ../shared/data/real/ (with the intrinsics and depth scale its SOURCE.md gives;
    a frame that cannot be read or recognized is recorded with its error line),
and writes OUT_DIR/results.jsonl: one line per frame, {"input": ..., "result": ...} or
{"input": ..., "error": ...}.

`diff` compares two such files line by line, ignoring `timing_ms` (and any key named in
--ignore), and exits 1 when anything else differs, listing the first differences per input.
Numbers are compared exactly unless --tolerance is given. Intended differences are named with
--expect INPUT_SUBSTRING: those inputs are listed but do not fail the comparison.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
REAL = ROOT.parent / "shared" / "data" / "real"

# (path relative to REAL, keyword arguments of mereo.io.read/open)
_REAL_INPUTS = [
    ("pcl/table_scene_mug_stereo_textured.pcd", {}),
    ("pcl/milk_cartoon_all_small_clorox.pcd", {}),
    ("pcl/region_growing_rgb_tutorial.pcd", {}),
    ("pcl/office1.pcd", {}),
    *[(f"pcl-mosd/{p}", {}) for p in
      [f"learn{i}.pcd" for i in range(33, 45)] + [f"test{i}.pcd" for i in range(31, 43)]],
    *[(f"pcl-pairwise/capture000{i}.pcd", {}) for i in range(1, 6)],
    *[(f"posecnn/00000{i}-depth.png", {"intrinsics": "1066.778,1067.487,312.9869,241.3109", "depth_scale": 10000.0})
      for i in range(1, 6)],
    *[(f"nv-6dof-graspnet/{n}-depth.png",
       {"intrinsics": "616.3652954101562,616.2029418945312,310.2588195800781,236.5998077392578",
        "depth_scale": 1000.0})
      for n in ["red_mug", "white_mug", "white_bowl", "green_bowl", "cylinder"]],
    ("open3d/TUM_depth.png", {"intrinsics": "525,525,319.5,239.5", "depth_scale": 5000.0}),
    ("open3d/SUN_depth.png", {"intrinsics": "525,525,319.5,239.5", "depth_scale": 1000.0, "depth_format": "sun3d"}),
    ("open3d/NYU_depth.pgm", {"intrinsics": "525,525,319.5,239.5", "depth_format": "nyu-raw"}),
    *[(f"nvblox-3dmatch/seq-01/frame-000{n}.depth.png", {"intrinsics": "570.342,570.342,320,240", "depth_scale": 1000.0})
      for n in ["000", "001", "002", "116", "422"]],
]


def _recognize(read, label: str):
    import mereo

    try:
        frame = read()
        return {"input": label, "result": mereo.recognize(frame)}
    except Exception as e:  # noqa: BLE001 - the error is the behaviour being compared
        return {"input": label, "error": f"{type(e).__name__}: {e}"}


def cmd_run(args) -> int:
    import mereo

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    lines = []
    for seed in range(args.seeds):
        lines.append(_recognize(lambda s=seed: mereo.io.read(f"synthetic:{s}"), f"synthetic:{seed}"))
    # one tracked orbit: the cognitive layer's results frame by frame
    try:
        seq = mereo.io.open("synthetic:700", frames=12)
        graph = mereo.recognition.tabletop_graph(tracking=True)
        for k, r in enumerate(graph.run(seq, mode="deterministic", keep=["result.result"])):
            lines.append({"input": f"synthetic:700/{k}", "result": mereo.recognition._result(r)})
    except Exception as e:  # noqa: BLE001
        lines.append({"input": "synthetic:700", "error": f"{type(e).__name__}: {e}"})
    if REAL.is_dir():
        for rel, kw in _REAL_INPUTS:
            path = REAL / rel
            if not path.exists():
                lines.append({"input": rel, "error": "missing"})
                continue
            lines.append(_recognize(lambda p=path, k=kw: mereo.io.read(str(p), **k), rel))
    else:
        print(f"compare_results: {REAL} not found: real frames skipped", file=sys.stderr)
    with open(out / "results.jsonl", "w") as f:
        for line in lines:
            f.write(json.dumps(line, sort_keys=True) + "\n")
    errors = sum("error" in x for x in lines)
    print(f"compare_results: {len(lines)} frames ({errors} with an error line) -> {out / 'results.jsonl'}")
    return 0


def _strip(x, ignore):
    if isinstance(x, dict):
        return {k: _strip(v, ignore) for k, v in x.items() if k not in ignore}
    if isinstance(x, list):
        return [_strip(v, ignore) for v in x]
    return x


def _differences(a, b, tol, path="", out=None):
    out = [] if out is None else out
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append(f"{path}/{k}: only {'after' if k in b else 'before'}")
            else:
                _differences(a[k], b[k], tol, f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} items before, {len(b)} after")
        for k, (x, y) in enumerate(zip(a, b)):
            _differences(x, y, tol, f"{path}[{k}]", out)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if abs(a - b) > tol * max(1.0, abs(a), abs(b)):
            out.append(f"{path}: {a!r} -> {b!r}")
    elif a != b:
        out.append(f"{path}: {a!r} -> {b!r}")
    return out


def _load(path: Path):
    p = path / "results.jsonl" if path.is_dir() else path
    return {x["input"]: x for x in map(json.loads, p.read_text().splitlines())}


def cmd_diff(args) -> int:
    ignore = {"timing_ms", *args.ignore}
    before, after = _load(Path(args.before)), _load(Path(args.after))
    changed, expected = [], []
    for key in list(before) + [k for k in after if k not in before]:
        if key not in before or key not in after:
            changed.append((key, [f"only {'after' if key in after else 'before'}"]))
            continue
        d = _differences(_strip(before[key], ignore), _strip(after[key], ignore), args.tolerance)
        if d:
            (expected if any(e in key for e in args.expect) else changed).append((key, d))
    for title, items in (("intended differences", expected), ("DIFFERENCES", changed)):
        for key, d in items:
            print(f"{title}: {key}: {len(d)} field(s): " + "; ".join(d[:4]) + (" ..." if len(d) > 4 else ""))
    same = len(before) - len(changed) - len(expected)
    print(f"compare_results: {same} of {len(before)} frames identical apart from timings, "
          f"{len(expected)} intended differences, {len(changed)} unexpected")
    return 1 if changed else 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="recognize the fixed frames with the installed mereo")
    r.add_argument("out")
    r.add_argument("--seeds", type=int, default=50, help="synthetic:0 ... synthetic:SEEDS-1")
    r.set_defaults(run=cmd_run)
    d = sub.add_parser("diff", help="compare two runs, apart from timings")
    d.add_argument("before")
    d.add_argument("after")
    d.add_argument("--tolerance", type=float, default=0.0, help="relative tolerance of numbers (default: exact)")
    d.add_argument("--ignore", action="append", default=[], help="another key to ignore (repeatable)")
    d.add_argument("--expect", action="append", default=[], help="inputs whose difference is intended")
    d.set_defaults(run=cmd_diff)
    args = p.parse_args(argv)
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
