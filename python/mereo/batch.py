"""Many frames on a Dask cluster (dask.distributed): one process, a local cluster or a remote one.

    import mereo.batch
    from dask.distributed import Client, LocalCluster

    client = Client(LocalCluster(n_workers=2, threads_per_worker=1))
    results = mereo.batch.recognize(["synthetic:1", ["a.pcd", "b.pcd"], "tum_folder"], client=client)

A sequence (a folder, a TUM folder, synthetic:SEED with frames > 1, or a list of files declared
one sequence) is one task, recognized in order with tracking inside it; single frames (and with
tracking=False every frame) are grouped into chunks (`chunk` frames; by default two chunks per
worker, at most 8 frames each), each frame recognized on its own.
Results come back as tasks finish and are handed on (written, passed to `on_result`) in input
order within each sequence; every result carries its "input" (the index of its input) and
"index" (its place in that input), the key that makes a rerun append nothing twice. A worker that
dies mid-task is replaced by the cluster and its task rerun (Dask retries it): what was handed on
before stays, nothing is handed on twice. `done` (keys already written, e.g. by an interrupted run:
`keys_in(path, repair=True)`) skips those frames.

Without a client everything runs in this process (the same tasks, in order): the results are the
same as on a cluster, timings aside.
"""
from __future__ import annotations

import json
import sys
import uuid
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

__all__ = ["recognize", "plan", "keys_in", "Task"]


class Task(dict):
    """One unit of work: {"units": [(input index, its sources, frame indices)], "tracked": bool}."""


def _portable(options: dict) -> dict:
    """mereo.io.open's options as plain values a worker can be sent (SceneOptions as a dict)."""
    from . import options_of, synthetic

    out = dict(options)
    if isinstance(out.get("scene"), synthetic.SceneOptions):
        out["scene"] = {o["name"]: getattr(out["scene"], o["name"]) for o in options_of("SceneOptions")}
    return out


def _open(sources: Sequence[str], options: dict):
    from . import io, synthetic

    if isinstance(options.get("scene"), dict):
        options = dict(options, scene=synthetic.SceneOptions(**options["scene"]))
    return io.open(list(sources), **options)


def plan(inputs: Sequence, *, chunk: int | None = 8, open_options: dict | None = None, workers: int = 1,
         tracking: bool = True) -> list[Task]:
    """The tasks for `inputs` (see the module's text): each tracked sequence one task, the other
    frames (single-frame inputs; every frame when tracking is off) in chunks of `chunk` (None: as
    many as give each of `workers` two chunks, at most 8). A task is {"units": [(input, sources,
    frame indices)], "tracked": bool}. Opening an input reads its file list (not its frames): a
    missing input raises here, before any task runs."""
    opts = dict(open_options or {})
    tasks: list[Task] = []
    singles: list[tuple[int, list[str], int]] = []
    for k, item in enumerate(inputs):
        sources = [str(s) for s in item] if isinstance(item, (list, tuple)) else [str(item)]
        n = len(_open(sources, opts))
        if tracking and n > 1:
            tasks.append(Task(units=[(k, sources, list(range(n)))], tracked=True))
        else:
            singles += [(k, sources, i) for i in range(n)]
    if chunk is None:
        chunk = min(8, -(-len(singles) // (2 * max(1, workers))))
    chunk = max(1, chunk)
    for c in range(0, len(singles), chunk):
        units: list[tuple[int, list[str], list[int]]] = []
        for k, sources, i in singles[c:c + chunk]:
            if units and units[-1][0] == k:
                units[-1][2].append(i)
            else:
                units.append((k, sources, [i]))
        tasks.append(Task(units=units, tracked=False))
    return tasks


def _run_task(task: Task, graph_options: dict, open_options: dict, done: frozenset, on_error: str) -> list[dict]:
    """Runs one task in a worker (or here): its results, keyed by "input" and "index"."""
    from . import recognition

    out: list[dict] = []
    for k, sources, indices in task["units"]:
        todo = [i for i in indices if (k, i) not in done]
        if not todo:
            continue
        seq = _open(sources, open_options)
        g = recognition.tabletop_graph(graph_options.get("models"), goal=graph_options.get("goal"),
                                       tracking=task["tracked"])
        # a tracked sequence is recognized whole (its tracks need every frame); the frames already
        # written are not handed on again
        run = indices if task["tracked"] else todo
        results = recognition.recognize_all([seq[i] for i in run], graph=g,
                                            mode=graph_options.get("mode", "deterministic"), on_error=on_error)
        for i, r in zip(run, results):
            if (k, i) in done:
                continue
            if not r.get("source"):
                r["source"], r["frame"] = seq.sources[i], r.get("frame") or seq.ids[i]
            r["input"], r["index"] = k, i
            out.append(r)
    return out


def keys_in(path: str | Path, repair: bool = False) -> frozenset:
    """The (input, index) keys of the results a JSON Lines file already holds (for resuming): its
    whole lines up to the first that is not JSON (the last, cut short by an interrupted run). With
    `repair`, the file is cut to those lines, each ending in a newline, so that a run appending to
    it goes on after a whole line."""
    p = Path(path)
    if not p.exists():
        return frozenset()
    keys, good = set(), []
    for line in p.read_text().splitlines(keepends=True):
        try:
            r = json.loads(line)
        except json.JSONDecodeError:
            break
        good.append(line if line.endswith("\n") else line + "\n")
        if "input" in r and "index" in r:
            keys.add((int(r["input"]), int(r["index"])))
    if repair:
        p.write_text("".join(good))
    return frozenset(keys)


def recognize(inputs: Sequence, client=None, *, models: Sequence[str] | str | None = None, goal: str | None = None,
              tracking: bool = True, mode: str = "deterministic", chunk: int | None = None,
              on_result: Callable | None = None,
              done: Iterable = (), on_error: str = "skip", progress: bool = True, retries: int = 3,
              **open_options) -> list[dict] | None:
    """Recognizes the frames of `inputs` (see the module's text) on `client`'s cluster, or here
    without one. Returns the results (sequence by sequence, in order within each), or hands each
    to `on_result` as its task completes (then returns None). `open_options` go to mereo.io.open
    (intrinsics, depth_scale, frames, scene...)."""
    graph_options = dict(models=models, goal=goal, tracking=tracking, mode=mode)
    open_options = _portable(open_options)
    done = frozenset((int(a), int(b)) for a, b in done)
    workers = len(client.scheduler_info().get("workers", {})) if client is not None else 1
    tasks = plan(inputs, chunk=chunk, open_options=open_options, workers=workers, tracking=tracking)
    total = sum(1 for t in tasks for k, _, indices in t["units"] for i in indices if (k, i) not in done)
    collected: list[dict] = []
    emit = on_result or collected.append
    bar = None
    if progress and total > 1:
        from tqdm import tqdm

        bar = tqdm(total=max(total, 0), desc="recognize", unit="frame", file=sys.stderr)

    def hand_on(results):
        for r in results:
            emit(r)
        if bar is not None:
            bar.update(len(results))

    try:
        if client is None:
            for t in tasks:
                hand_on(_run_task(t, graph_options, open_options, done, on_error))
        else:
            from dask.distributed import as_completed

            run = uuid.uuid4().hex  # (a key per task of this call: none is taken for another call's)
            futures = [client.submit(_run_task, t, graph_options, open_options, done, on_error, pure=False,
                                     retries=retries, key=f"mereo-{run}-{n}")
                       for n, t in enumerate(tasks)]
            for f in as_completed(futures):  # task by task as they finish, each in frame order
                hand_on(f.result())
    finally:
        if bar is not None:
            bar.close()
    return None if on_result else sorted(collected, key=lambda r: (r["input"], r["index"]))
