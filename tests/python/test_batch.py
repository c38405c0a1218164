"""mereo.batch on a Dask cluster (issue 23): the same results as one process, a worker killed mid-run,
--resume after an interrupted run, and results as a DataFrame and Parquet."""
from __future__ import annotations

import json
import os
import signal
import threading

import pytest

import mereo
from mereo import batch, cli

distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed (pip install mereo[dask])")

SEQUENCES = [f"synthetic:{s}" for s in (11, 12, 13, 14)]  # 4 orbits of 10 frames: 40 frames


def _strip(r: dict) -> dict:
    return {k: v for k, v in r.items() if k != "timing_ms"}


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as c:
        with distributed.Client(c) as client:
            yield c, client


@pytest.fixture(scope="module")
def one_process():
    return batch.recognize(SEQUENCES, frames=10, progress=False)


def test_a_local_cluster_gives_the_results_of_one_process(cluster, one_process):
    _, client = cluster
    many = batch.recognize(SEQUENCES, client=client, frames=10, progress=False)
    assert [(r["input"], r["index"]) for r in many] == [(k, i) for k in range(4) for i in range(10)]
    assert [_strip(r) for r in many] == [_strip(r) for r in one_process]
    # each sequence is tracked inside its task: an object keeps its track id (and its model) from
    # frame to frame, as recognize_all over that sequence alone gives them
    tracks = 0
    for k, source in enumerate(SEQUENCES):
        mine = [r for r in many if r["input"] == k]
        alone = mereo.recognize_all(mereo.io.open([source], frames=10),
                                    graph=mereo.recognition.tabletop_graph(tracking=True), mode="deterministic")
        assert [[o.get("track") for o in r["objects"]] for r in mine] == [[o.get("track") for o in r["objects"]] for r in alone]
        model_of: dict[int, str] = {}
        for r in mine:
            for o in r["objects"]:
                if o["accepted"] and o.get("track") is not None:
                    assert model_of.setdefault(o["track"], o["model"]) == o["model"], (source, o["track"])
        tracks += len(model_of)
    assert tracks >= 8


def test_a_worker_killed_mid_batch_is_replaced_and_every_frame_comes_once(cluster):
    _, client = cluster
    got: list[tuple[int, int]] = []
    killed = threading.Event()

    def kill_a_busy_worker():
        # once a task runs, the process of a worker that has one dies (its nanny starts another)
        for _ in range(600):
            busy = [w for w, keys in client.processing().items() if keys]
            if busy:
                pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
                os.kill(pid, signal.SIGKILL)
                killed.set()
                return
            threading.Event().wait(0.05)

    threading.Thread(target=kill_a_busy_worker, daemon=True).start()
    inputs = [f"synthetic:{s}" for s in range(20, 28)]  # 8 orbits of 3 frames
    batch.recognize(inputs, client=client, frames=3, progress=False, on_result=lambda r: got.append((r["input"], r["index"])))
    assert killed.is_set()
    expected = [(k, i) for k in range(8) for i in range(3)]
    assert sorted(got) == expected  # every frame exactly once
    client.wait_for_workers(2, timeout=60)


def test_resume_after_an_interrupted_run_writes_the_file_of_an_uninterrupted_one(tmp_path):
    inputs = ["synthetic:4", "synthetic:5", "synthetic:6", "synthetic:7"]
    whole, cut = tmp_path / "whole.jsonl", tmp_path / "cut.jsonl"
    assert cli.main(["recognize", *inputs, "--resume", "--out", str(whole)]) == 0
    lines = whole.read_text().splitlines(keepends=True)
    assert len(lines) == 4
    cut.write_text("".join(lines[:2]) + lines[2][: len(lines[2]) // 2])  # killed while writing line 3
    assert cli.main(["recognize", *inputs, "--resume", "--out", str(cut)]) == 0
    again = [_strip(json.loads(s)) for s in cut.read_text().splitlines()]
    assert again == [_strip(json.loads(s)) for s in lines]
    # a run that had finished: nothing is appended
    assert cli.main(["recognize", *inputs, "--resume", "--out", str(cut)]) == 0
    assert len(cut.read_text().splitlines()) == 4


def test_results_as_a_dataframe_and_parquet(tmp_path, one_process):
    pd = pytest.importorskip("pandas", reason="pandas is not installed (pip install mereo[dask])")
    from mereo import results

    df = results.to_dataframe(one_process)
    assert len(df) == sum(len(r["objects"]) for r in one_process)
    mugs = df[(df["model"] == "mug") & df["accepted"]]
    assert len(mugs) > 0 and mugs["body.radius"].between(0.02, 0.07).all()
    assert mugs["handle.major_radius"].notna().all() and {"body.point[0]", "track", "input", "index"} <= set(df.columns)
    lines = tmp_path / "r.jsonl"
    lines.write_text("".join(json.dumps(r) + "\n" for r in one_process))
    pytest.importorskip("pyarrow", reason="pyarrow is not installed (pip install mereo[dask])")
    results.to_parquet(lines, tmp_path / "r.parquet")
    back = pd.read_parquet(tmp_path / "r.parquet")
    same = lambda d: d.astype(object).where(d.notna(), None)  # noqa: E731 (a missing bool: None or NaN)
    pd.testing.assert_frame_equal(same(back), same(results.to_dataframe(lines)), check_dtype=False)


def test_the_plan_tracks_sequences_whole_and_chunks_the_rest():
    """A sequence is one tracked task; single frames, and every frame without tracking, are chunked
    (by default two chunks per worker); a list of inputs is one sequence."""
    tasks = batch.plan(["synthetic:1", "synthetic:2", "synthetic:3"], workers=1, chunk=None)
    assert [t["tracked"] for t in tasks] == [False, False] and [len(t["units"]) for t in tasks] == [2, 1]
    tasks = batch.plan(["synthetic:1", "synthetic:2"], open_options={"frames": 5}, workers=2, chunk=None)
    assert [(t["tracked"], t["units"][0][2]) for t in tasks] == [(True, [0, 1, 2, 3, 4])] * 2
    tasks = batch.plan(["synthetic:1"], open_options={"frames": 8}, workers=2, chunk=None, tracking=False)
    assert [t["units"][0][2] for t in tasks] == [[0, 1], [2, 3], [4, 5], [6, 7]]


def test_a_missing_input_is_one_clear_error_before_any_task(tmp_path, capsys):
    assert cli.main(["recognize", "synthetic:4", str(tmp_path / "missing.pcd"), "--workers", "1"]) == 2
    assert "missing.pcd" in capsys.readouterr().err
