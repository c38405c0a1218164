#!/usr/bin/env python3
"""Writes docs/bad_input.md: what bad input gives what message, by running every case of
tests/python/bad_inputs.py through `mereo recognize` (the same cases the tests check through the
CLI, the Python API and mereo-run).

    .venv/bin/python scripts/bad_input_table.py [--out docs/bad_input.md]
"""
import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python"))

from bad_inputs import CASES, cli_args, make_base  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "bad_input.md"))
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        make_base(root / "base")
        for case in CASES:
            d = root / case.name
            d.mkdir()
            inputs = case.make(d)
            run = subprocess.run([sys.executable, "-m", "mereo.cli", *cli_args(case, inputs, d)], capture_output=True,
                                 text=True, cwd=d, timeout=300)
            lines = [line for line in run.stderr.splitlines() if line.startswith(("mereo: error:", "mereo: warning:"))]
            summary = re.sub(r" in [0-9.]+ s \([0-9.]+ frames/s\)", "", run.stderr.strip().splitlines()[-1])
            said = "; ".join(lines) or f"a result ({summary})"  # (timings left out: they vary)
            said = said.replace(str(d) + "/", "").replace(str(root) + "/", "").replace("|", "\\|")
            rows.append(f"| {case.what} | {run.returncode} | `{said}` |")
            print(f"{case.name}: {run.returncode}", file=sys.stderr)
    text = ("# Bad input and what mereo says\n\n"
            "Each row is a case of `tests/python/bad_inputs.py`, run through `mereo recognize` by\n"
            "`scripts/bad_input_table.py` (which wrote this file); `tests/python/test_bad_input.py` checks the\n"
            "same cases through the command line, the Python API (`mereo.InputError`, `GraphError` or\n"
            "`NodeError` with the same text, or a result's warning) and `mereo-run`. Exit status: 2, the run\n"
            "could not start; 1, a frame could not be read (its warning names the file; the other frames\n"
            "went on); 0, a result (valid but extreme data: points outside any sensor's range, 0.1 mm to\n"
            "1 km, count as missing).\n\n"
            "| input | exit | message |\n|---|---|---|\n" + "\n".join(rows) + "\n")
    Path(args.out).write_text(text)
    print(f"wrote {args.out}: {len(rows)} cases", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
