"""The scripts that draw the documentation's figures from benchmark output."""
import json
import subprocess
import sys
from pathlib import Path

from PIL import Image

ROOT = Path(__file__).resolve().parents[2]


def growth_row(objects, width, height, ms):
    return {"objects": objects, "width": width, "height": height, "fps": 1000.0 / ms, "median_ms": ms,
            "same_results": 4, "stage_median_ms": {"filter": 0.1 * ms, "normals": 0.05 * ms, "table": 0.2 * ms,
                                                  "primitives": 0.5 * ms}}


def test_growth_plot_draws_the_benchmarks_figures(tmp_path):
    j = {"bench": "pipeline_growth", "frames_per_point": 4, "in_flight": 4,
         "objects": [growth_row(n, 640, 480, 50.0 + 20 * n) for n in (1, 2, 5)],
         "size": [growth_row(0, w, h, w / 4) for w, h in ((320, 240), (640, 480))]}
    out = tmp_path / "growth.txt"
    out.write_text("bench_pipeline --growth: ...\ntable lines\n" + json.dumps(j) + "\n")
    png = tmp_path / "growth.png"
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "growth_plot.py"), str(out), "--out", str(png)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert Image.open(png).size[0] > 500


def test_growth_plot_says_when_the_output_has_no_figures(tmp_path):
    out = tmp_path / "other.txt"
    out.write_text('{"bench": "pipeline"}\n')
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "growth_plot.py"), str(out)], capture_output=True,
                       text=True)
    assert r.returncode != 0 and "no JSON line of bench_pipeline --growth" in r.stderr
