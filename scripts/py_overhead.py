"""Measures the Python package's cost against the command line (docs/python.md, "Cost"):
the import time of `nmm`, and the wall time of a run from Python (nmm.run) against
`nmm run --no-vtk` of the same model, median of N alternated repetitions.

    target/pyenv/bin/python scripts/py_overhead.py [--reps 7] [--nmm target/release/nmm]
"""

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def import_time(reps):
    code = "import time; t = time.perf_counter(); import nmm; print(time.perf_counter() - t)"
    code_pd = code.replace("import nmm;", "import nmm, pandas;")
    a = [float(subprocess.check_output([sys.executable, "-c", code])) for _ in range(reps)]
    b = [float(subprocess.check_output([sys.executable, "-c", code_pd])) for _ in range(reps)]
    return statistics.median(a), statistics.median(b)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--nmm", default=str(ROOT / "target" / "release" / "nmm"))
    args = ap.parse_args()
    import nmm

    imp, imp_pd = import_time(args.reps)
    print(f"import nmm: {imp * 1e3:.1f} ms (median of {args.reps}); import nmm + pandas: {imp_pd * 1e3:.1f} ms")
    text = (ROOT / "examples" / "incline.toml").read_text()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for steps in (5, 1000):
            path = tmp / f"incline{steps}.toml"
            path.write_text(text.replace("steps = 1000", f"steps = {steps}"))
            cli, py, py_load, cli_in, py_in = [], [], [], [], []
            for i in range(args.reps):
                t = time.perf_counter()
                subprocess.run([args.nmm, "run", str(path), "--out", str(tmp / "cli"), "--no-vtk", "--quiet"],
                               check=True, capture_output=True)
                cli.append(time.perf_counter() - t)
                summary = json.loads((tmp / "cli" / "summary.json").read_text())
                cli_in.append(cli[-1] - summary["timings"]["total"])
                t = time.perf_counter()
                m = nmm.Model.load(str(path))
                t1 = time.perf_counter()
                r = nmm.run(m, out=tmp / "py", vtk=False)
                t2 = time.perf_counter()
                py_load.append(t2 - t)
                py.append(t2 - t1)
                assert len(r.history) == steps
                py_in.append(py[-1] - r.summary["timings"]["total"])
            c, p, pl = (statistics.median(x) for x in (cli, py, py_load))
            print(f"{steps:5d} steps: nmm run (whole process) {c * 1e3:7.1f} ms; nmm.run {p * 1e3:7.1f} ms "
                  f"(+ Model.load: {pl * 1e3:7.1f} ms); difference {(pl - c) * 1e3:+7.1f} ms")
            print(f"       outside the library's own run time (summary timings.total): nmm run "
                  f"{statistics.median(cli_in) * 1e3:6.1f} ms (process start, model read, exit); "
                  f"nmm.run {statistics.median(py_in) * 1e3:6.1f} ms (thread, history.csv into pandas, summary)")


if __name__ == "__main__":
    main()
