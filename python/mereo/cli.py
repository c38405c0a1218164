"""The `mereo` command line.

  mereo demo [--seed N] [--out DIR]           render the default scene, show what is in it
  mereo render synthetic:SEED [--frames N] --out DIR [SCENE FLAGS]   frames plus ground truth
               (scene flags: --depth-model stereo, --handle-shapes varied, --lying-containers,
                --freeform-distractors, --tapered-cups, --distractors...: `mereo render -h`)
  mereo info INPUT...                          what the inputs hold (size, depth range, camera)
  mereo recognize INPUT... [--models NAME_OR_FILE...] [--goal NAME] [--out FILE.jsonl]
                  [--overlay DIR] [--graph FILE] [--intrinsics ...] [--depth-scale S]
                  [--workers N | --scheduler ADDRESS] [--resume]
                                               recognized objects, one JSON line per frame
  mereo evaluate RESULTS.jsonl GROUND_TRUTH...  precision, recall and errors per model, results
                                               on free-form distractors per frame

Bad input prints one line (`mereo: error: ...`) and exits with status 2.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from . import _mereo, io, synthetic
from .preview import save_preview


def _progress(iterable, total, desc):
    """A progress bar on stderr for sequences (tqdm), silent for one item."""
    if total <= 1:
        return iterable
    from tqdm import tqdm

    return tqdm(iterable, total=total, desc=desc, unit="frame", file=sys.stderr)


# SceneOptions' options that have flags of their own (--no-noise, --distractors, --leaning-distractors)
_OWN_SCENE_FLAGS = {"noise", "distractors", "ambiguous_distractors"}


def _scene_option_flags():
    """The command line's scene flags, from SceneOptions' description (declared once, in C++):
    a flag for each yes/no option (--lying-containers) and each choice (--depth-model stereo)."""
    from . import options_of

    return [o for o in options_of("SceneOptions")
            if o["type"] in ("bool", "str") and o["name"] not in _OWN_SCENE_FLAGS]


def _scene_flags(q, noise: bool = True) -> None:
    """synthetic:SEED: the scene's flags."""
    if noise:
        q.add_argument("--no-noise", action="store_true", help="clean depth (no depth model's noise)")
    _distractor_flags(q)
    for o in _scene_option_flags():
        flag = "--" + o["name"].replace("_", "-")
        if o["type"] == "bool":
            q.add_argument(flag if not o["default"] else "--no-" + flag[2:], dest=o["name"], default=o["default"],
                           action="store_false" if o["default"] else "store_true", help=f"synthetic:SEED: {o['doc']}")
        else:
            q.add_argument(flag, dest=o["name"], choices=o["choices"], default=o["default"],
                           help=f"synthetic:SEED: {o['doc']} (default {o['default']})")


def _scene_options(args) -> synthetic.SceneOptions:
    o = synthetic.SceneOptions()
    o.noise = not getattr(args, "no_noise", False)
    o.distractors = args.distractors == "beside"
    o.ambiguous_distractors = args.distractors == "leaning"
    for f in _scene_option_flags():
        setattr(o, f["name"], getattr(args, f["name"]))
    return o


def _parse_seed(text: str) -> int:
    if not text.startswith("synthetic:") or not text[len("synthetic:"):].isdigit():
        raise _mereo.InputError(f"{text}: expected synthetic:SEED with SEED a non-negative integer")
    return int(text[len("synthetic:"):])


def _seed(text: str) -> int:
    """--seed: a non-negative whole number (argparse names the option on a ValueError)."""
    if not text.isdigit():
        raise ValueError(text)
    return int(text)


def _write_synthetic(sf, out: Path, name: str) -> None:
    """Colour/depth pair, clean depth, labels, normals and the ground-truth JSON of one frame."""
    io.write_png_pair(out, name, sf.frame, 5000.0)
    np.save(out / f"{name}_normals.npy", sf.truth.normals)
    np.save(out / f"{name}_objects.npy", sf.truth.objects)
    np.save(out / f"{name}_parts.npy", sf.truth.parts)
    np.save(out / f"{name}_clean_depth.npy", sf.truth.depth)
    (out / f"{name}_truth.json").write_text(sf.truth_json())


def _summarize_truth(sf) -> list[str]:
    truth = json.loads(sf.truth_json())
    lines = []
    for obj in truth["objects"]:
        if obj["model"] in ("floor", "wall"):
            continue
        parts = ", ".join(
            f'{p["role"]} ({p["class"]}, {p["visible_pixels"]} px)' for p in obj["parts"] if p["visible_pixels"] > 0
        )
        lines.append(f'  {obj["id"]:>2} {obj["model"]:<10} {obj["visible_pixels"]:>7} px  {parts}')
    return lines


def _demo_extension(sf, out: Path) -> None:
    """The extension layer on the demo frame: estimated normals and the support plane, against
    the exact ground truth, and a picture (colour | estimated normals | region above the table)."""
    from . import extension

    f = sf.frame
    cloud = extension.back_project(f)
    normals = extension.estimate_normals(cloud, method="fast")
    ok = np.isfinite(normals[..., 0]) & np.isfinite(sf.truth.normals[..., 0])
    cos = np.abs(np.einsum("ij,ij->i", normals[ok], sf.truth.normals[ok]))
    err = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    share = ok.sum() / max(1, np.isfinite(cloud[..., 2]).sum())
    print(f"normals (fast): {share:.1%} of valid pixels, median error {np.median(err):.1f} deg against the exact normals")
    plane = extension.find_support_plane(cloud, normals)
    up = np.asarray(f.pose)[:3, :3].T @ np.array([0.0, 0.0, 1.0])
    tilt = np.degrees(np.arccos(np.clip(plane.normal @ up, -1.0, 1.0)))
    print(f"support plane: {plane.inlier_count} table points, normal {tilt:.2f} deg from the truth, "
          f"{int(plane.roi.sum())} pixels above it (the region searched for objects); the depth's noise "
          f"measured on it {1000 * plane.noise:.1f} mm at 1 m (growing with the distance squared)")
    roi = plane.roi.astype(bool)[..., None]
    shown = np.where(roi, f.color, f.color // 3).astype(np.uint8)
    path = out / "extension.png"
    io.write_image(str(path), io.hstack([f.color, io.colorize_normals(normals), shown]))
    print(f"wrote {path} (colour | estimated normals | above the table)")


def cmd_demo(args) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    o = _scene_options(args)
    sf = synthetic.render(args.seed, o)
    f = sf.frame
    print(f"mereo {_mereo.__version__}: synthetic:{args.seed}, {f.shape[1]}x{f.shape[0]}, camera {f.intrinsics}")
    valid = np.isfinite(f.depth)
    model = "Kinect-like" if o.depth_model == "kinect" else "active-stereo"
    print(f"depth: {valid.mean():.1%} valid, {np.nanmin(f.depth):.2f}-{np.nanmax(f.depth):.2f} m ({model} noise {'on' if o.noise else 'off'})")
    print("objects in the scene (ground truth, visible pixels):")
    print("\n".join(_summarize_truth(sf)))
    _write_synthetic(sf, out, "0000")
    preview = save_preview(out / "preview.png", f, sf.truth)
    print(f"wrote {out}/0000_rgb.png, 0000_depth.png, 0000_truth.json and {preview} (colour | depth | normals | objects)")
    _demo_extension(sf, out)
    _demo_recognition(sf, out)
    return 0


def _demo_recognition(sf, out: Path) -> None:
    """The main job on the demo frame: the tabletop pipeline, what it found against the ground
    truth, and the overlay."""
    from . import recognition

    result = recognition.recognize(sf.frame)
    (out / "0000_result.json").write_text(json.dumps(result))
    found = [o for o in result["objects"] if o["accepted"]]
    print(f"recognized ({result['timing_ms']['total']:.0f} ms, graphs/tabletop.yaml):")
    for o in found:
        b = o["parts"].get("body", next(iter(o["parts"].values())))
        where = b.get("point", b.get("center"))
        size = b.get("radius", 0.0) * 1000
        extra = f", handle ring {o['parts']['handle']['major_radius'] * 1000:.0f} mm" if "handle" in o["parts"] else ""
        print(f"  {o['model']:<7} score {o['score']:.2f}  body r={size:.1f} mm at "
              f"({where[0]:+.3f}, {where[1]:+.3f}, {where[2]:.3f}) m{extra}")
    if not found:
        print("  nothing")
    path = out / "overlay.png"
    io.write_image(path, recognition.draw_result(sf.frame, result))
    print(f"wrote {path} (the recognized objects drawn) and {out}/0000_result.json (one line of `mereo recognize`)")


def cmd_render(args) -> int:
    seed = _parse_seed(args.input)
    if args.frames < 1:
        raise _mereo.InputError(f"--frames {args.frames}: must be at least 1")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    o = _scene_options(args)
    scene = synthetic.generate_scene(seed, o)
    for i in _progress(range(args.frames), args.frames, "render"):
        sf = synthetic.render_view(scene, i, o)
        name = f"{i:04d}"
        _write_synthetic(sf, out, name)
        if args.preview:
            save_preview(out / f"{name}_preview.png", sf.frame, sf.truth)
    print(f"wrote {args.frames} frame(s) of synthetic:{seed} ({o}) with ground truth to {out}")
    return 0


def cmd_info(args) -> int:
    seq = io.open(args.inputs, intrinsics=args.intrinsics, depth_scale=args.depth_scale, depth_format=args.depth_format)
    for i in _progress(range(len(seq)), len(seq), "info"):
        f = seq[i]
        z = f.depth[np.isfinite(f.depth)]
        rng = f"{z.min():.3f}-{np.median(z):.3f}-{z.max():.3f} m" if z.size else "no valid depth"
        extra = " labels" if f.labels is not None else ""
        print(f"{f.id}: {f.shape[1]}x{f.shape[0]}, {z.size / f.depth.size:.1%} valid, depth min/median/max {rng}, "
              f"camera {f.intrinsics}{extra}  ({f.source})")
        if args.preview:
            save_preview(Path(args.preview) / f"{f.id}_preview.png", f)
    return 0


def _models_arg(values):
    """--models: concept names and/or YAML model files (the files' concepts join the shipped ones)."""
    names, files = [], []
    for v in values or []:
        for item in str(v).split(","):
            item = item.strip()
            if not item:
                continue
            if item.endswith((".yaml", ".yml")) or Path(item).is_file():
                if not Path(item).is_file():
                    raise FileNotFoundError(f"{item}: model file not found")
                files.append(item)
            else:
                names.append(item)
    if len(files) > 1:
        raise _mereo.InputError("--models: give at most one model file")
    return names, (files[0] if files else "")


class _Tally:
    """What a recognize run found, for its summary line: frames, accepted objects per model, frames
    with a warning."""

    def __init__(self):
        self.frames = self.warned = 0
        self.counts: dict[str, int] = {}

    def add(self, res: dict) -> None:
        self.frames += 1
        self.warned += bool(res.get("warnings"))
        for o in res["objects"]:
            if o["accepted"]:
                self.counts[o["model"]] = self.counts.get(o["model"], 0) + 1

    def found(self) -> str:
        text = ", ".join(f"{n} {k}" for n, k in sorted(self.counts.items())) or "nothing"
        return text + (f"; {self.warned} frame(s) with a warning" if self.warned else "")


def _recognize_batch(args, names) -> int:
    """--workers N, --scheduler ADDRESS, --resume: mereo.batch (one task per sequence, single frames
    in chunks) on a local Dask cluster, a remote one, or here; JSON lines written as tasks finish."""
    import time

    from . import batch

    if args.overlay or args.graph or args.odometry:
        raise _mereo.InputError("--overlay, --graph and --odometry are not available with --workers, --scheduler or --resume")
    if args.resume and not args.out:
        raise _mereo.InputError("--resume needs --out FILE (the results it goes on from)")
    inputs = [list(args.inputs)] if args.sequence else list(args.inputs)
    open_options = dict(intrinsics=args.intrinsics, depth_scale=args.depth_scale, depth_format=args.depth_format,
                        frames=args.frames, scene=_scene_options(args))
    batch.plan(inputs, open_options=open_options)  # a missing or bad input: one error before any cluster starts
    # keep the whole lines of the interrupted run; go on after them
    done = batch.keys_in(args.out, repair=True) if args.resume else frozenset()
    out = open(args.out, "a" if args.resume else "w") if args.out else sys.stdout
    tally = _Tally()
    client = cluster = None
    t0 = time.perf_counter()
    try:
        if args.workers or args.scheduler:
            from dask.distributed import Client, LocalCluster

            if args.scheduler:
                client = Client(args.scheduler)
            else:
                cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
                client = Client(cluster)

        def on_result(res):
            out.write(json.dumps(res) + "\n")
            out.flush()
            tally.add(res)

        batch.recognize(inputs, client, models=names or None, goal=args.goal, tracking=not args.no_track,
                        on_result=on_result, done=done, on_error=args.on_error, **open_options)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
        if args.out:
            out.close()
    wall = time.perf_counter() - t0
    where = f"{args.workers} local worker(s)" if args.workers else (args.scheduler or "this process")
    print(f"mereo recognize: {tally.frames} frame(s) in {wall:.2f} s on {where}"
          + (f" ({len(done)} already in {args.out})" if done else "") + f": {tally.found()}"
          + (f"; results in {args.out}" if args.out else ""), file=sys.stderr)
    return 0


def cmd_recognize(args) -> int:
    import time

    from . import recognition

    names, models_file = _models_arg(args.models)
    if args.workers or args.scheduler or args.resume:
        if models_file:
            raise _mereo.InputError("--models FILE is not available with --workers, --scheduler or --resume")
        return _recognize_batch(args, names)
    if models_file and not names:
        from .knowledge import load_models

        before = set(load_models().names())
        names = [n for n in load_models(models_file).names() if n not in before]
    seq = io.open(args.inputs, intrinsics=args.intrinsics, depth_scale=args.depth_scale,
                  depth_format=args.depth_format, frames=args.frames, scene=_scene_options(args))
    # one input that is a sequence (a folder, a TUM folder, synthetic:SEED --frames N) is tracked
    # (graphs/tabletop_tracking.yaml: "track" ids, false hypotheses dropped); separate inputs are not
    # (--sequence: the inputs, e.g. a list of .pcd files, are one sequence and tracked too)
    track = (len(args.inputs) == 1 or args.sequence) and len(seq) > 1 and not args.no_track and not args.graph
    graph = recognition.tabletop_graph(names or None, goal=args.goal, models_file=models_file,
                                       graph=args.graph, tracking=track, odometry=args.odometry)
    out = open(args.out, "w") if args.out else sys.stdout
    overlay = Path(args.overlay) if args.overlay else None
    if overlay:
        overlay.mkdir(parents=True, exist_ok=True)
    tally = _Tally()
    unread = 0
    bar = _progress(None, len(seq), "recognize") if len(seq) > 1 else None
    t0 = time.perf_counter()

    def on_result(r):
        nonlocal unread
        res = recognition._result(r, args.on_error)
        if res.get("warnings") and not res.get("source") and r["index"] < len(seq):
            res["source"] = seq.sources[r["index"]]  # (a frame that failed: where it came from)
            res["frame"] = res["frame"] or seq.ids[r["index"]]
        out.write(json.dumps(res) + "\n")
        if r["error"] and r["error_node"] == "frame_source":
            unread += 1  # the frame could not be read: the run goes on, the exit status says so
        if res.get("warnings"):
            message = f"mereo: warning: frame {res['frame']}: " + "; ".join(res["warnings"])
            (bar.write(message, file=sys.stderr) if bar is not None else print(message, file=sys.stderr))
        frame = r["outputs"].get("source.frame") if overlay is not None else None
        if frame is not None:  # (a frame that failed has no overlay)
            name = f"{tally.frames:04d}_{frame.id}" if len(seq) > 1 else frame.id or "frame"
            io.write_image(overlay / f"{name}_overlay.png", recognition.draw_result(frame, res))
        tally.add(res)
        if bar is not None:
            bar.update(1)

    keep = ["result.result"] + (["source.frame"] if overlay else [])
    graph.run(seq, mode=args.mode, keep=keep, on_result=on_result, on_error=args.on_error)
    if bar is not None:
        bar.close()
    if args.out:
        out.close()
    wall = time.perf_counter() - t0
    found = tally.found() + (f", {unread} of them could not be read" if unread else "")
    print(f"mereo recognize: {tally.frames} frame(s) in {wall:.2f} s ({tally.frames / wall:.1f} frames/s): {found}"
          + (f"; results in {args.out}" if args.out else "") + (f"; overlays in {overlay}" if overlay else ""),
          file=sys.stderr)
    return 1 if unread else 0


def cmd_evaluate(args) -> int:
    from . import evaluate as ev

    try:
        results = ev.load_results(args.results)
        truths = ev.load_truths(args.truth, _scene_options(args))
        e = ev.evaluate(results, truths)
    except ValueError as err:
        raise _mereo.InputError(str(err)) from None
    print(ev.format_table(e))
    if args.mistakes:
        print("\n".join(e.mistakes))
    if args.json:
        Path(args.json).write_text(json.dumps(e.summary(), indent=1))
    return 0


def _distractor_flags(q) -> None:
    """synthetic:SEED: handle-like distractors beside jars (never a mug's handle) or leaning on them
    (from some views they pass for one: what the tracking must drop)."""
    q.add_argument("--distractors", action="store_const", const="beside",
                   help="synthetic:SEED: handle-like tori beside some jars")
    q.add_argument("--leaning-distractors", dest="distractors", action="store_const", const="leaning",
                   help="synthetic:SEED: rings leaning on some jars (a mug's handle from some views)")


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="mereo", description="Recognize objects in RGB-D images by their parts.")
    p.add_argument("--version", action="version", version=f"mereo {_mereo.__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    scene_flags = _scene_flags

    d = sub.add_parser("demo", help="render the default scene and show what is in it")
    d.add_argument("--seed", type=_seed, default=0, help="the scene's seed, a non-negative whole number")
    d.add_argument("--out", default="out/demo")
    scene_flags(d)
    d.set_defaults(run=cmd_demo)

    r = sub.add_parser("render", help="write synthetic frames and their ground truth")
    r.add_argument("input", help="synthetic:SEED")
    r.add_argument("--frames", type=int, default=1, help="frames (the camera orbits the table)")
    r.add_argument("--out", required=True)
    r.add_argument("--preview", action="store_true", help="also write NAME_preview.png per frame")
    scene_flags(r)
    r.set_defaults(run=cmd_render)

    i = sub.add_parser("info", help="describe inputs: .pcd, PNG pairs, folders, TUM folders, synthetic:SEED")
    i.add_argument("inputs", nargs="+")
    i.add_argument("--intrinsics", help="fx,fy,cx,cy or a JSON file")
    i.add_argument("--depth-scale", type=float, default=0.0, help="depth units per metre")
    i.add_argument("--depth-format", choices=["units", "sun3d", "nyu-raw"], default="units",
                   help="16-bit depth as plain units (default), SUN3D's bit-rotated millimetres or NYU's raw Kinect values")
    i.add_argument("--preview", metavar="DIR", help="write a colour | depth picture per frame")
    i.set_defaults(run=cmd_info)

    g = sub.add_parser("recognize", help="recognize objects: one JSON line per frame (DESIGN.md's contract)")
    g.add_argument("inputs", nargs="+", help=".pcd files, PNG-pair folders, TUM folders, synthetic:SEED")
    g.add_argument("--graph", help="a pipeline file, or a shipped one by name (room: furniture in rooms; "
                   "default: the shipped graphs/tabletop.yaml)")
    g.add_argument("--models", nargs="+", metavar="NAME_OR_FILE", help="concepts to look for, or a YAML model file")
    g.add_argument("--goal", help="one concept to look for; it drives the top-down search (e.g. mug)")
    g.add_argument("--intrinsics", help="fx,fy,cx,cy or a JSON file")
    g.add_argument("--depth-scale", type=float, default=0.0, help="depth units per metre")
    g.add_argument("--depth-format", choices=["units", "sun3d", "nyu-raw"], default="units",
                   help="16-bit depth as plain units (default), SUN3D's bit-rotated millimetres or NYU's raw Kinect values")
    g.add_argument("--frames", type=int, default=1, help="frames of a synthetic:SEED orbit")
    g.add_argument("--out", help="write the JSON lines here (default: standard output)")
    g.add_argument("--overlay", metavar="DIR", help="write each frame with the recognized objects drawn")
    g.add_argument("--mode", choices=["parallel", "deterministic"], default="parallel")
    g.add_argument("--no-track", action="store_true", help="a sequence: recognize each frame on its own")
    g.add_argument("--sequence", action="store_true",
                   help="the inputs (e.g. a list of .pcd files) are the frames of one sequence: tracked")
    g.add_argument("--on-error", choices=["skip", "stop"], default="skip",
                   help="a frame where a node finds nothing usable (no support surface...): an empty result "
                        "with warnings and the run goes on (skip, the default), or stop with an error")
    g.add_argument("--odometry", action="store_true",
                   help="a sequence: estimate the camera poses (RGB-D odometry) even where the input has them")
    g.add_argument("--workers", type=int, default=0, metavar="N",
                   help="run on a local Dask cluster of N worker processes (one task per sequence)")
    g.add_argument("--scheduler", metavar="ADDRESS", help="run on an existing Dask cluster (tcp://host:8786)")
    g.add_argument("--resume", action="store_true",
                   help="go on from an interrupted run: skip the frames --out already holds, append the rest")
    _scene_flags(g, noise=False)
    g.set_defaults(run=cmd_recognize)

    e = sub.add_parser("evaluate", help="precision, recall and errors against the renderer's ground truth")
    e.add_argument("results", help="a JSON Lines file of mereo recognize")
    e.add_argument("truth", nargs="+", help="NNNN_truth.json files, folders of them, or synthetic:SEED[:FRAMES]")
    e.add_argument("--mistakes", action="store_true", help="also list every false and missed object")
    e.add_argument("--json", help="write the figures as JSON here")
    _scene_flags(e)
    e.set_defaults(run=cmd_evaluate)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except (_mereo.InputError, _mereo.GraphError, _mereo.NodeError, FileNotFoundError, NotADirectoryError,
            PermissionError) as e:
        print(f"mereo: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
