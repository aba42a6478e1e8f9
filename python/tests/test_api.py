"""The package's API against the command line: models, errors, check, run."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pandas as pd
import pytest

import nmm
from conftest import cli
from incline import incline_toml

EXAMPLE = "examples/direct_shear.toml"


def test_load_and_check_match_the_cli(repo, nmm_cli, monkeypatch):
    monkeypatch.chdir(repo)
    m = nmm.Model.load(EXAMPLE)
    assert m.source == EXAMPLE
    got = nmm.check(m)
    p = cli(nmm_cli, "check", "--json", EXAMPLE)
    assert p.returncode == 0, p.stderr
    want = json.loads(p.stdout)
    assert list(got) == list(want)
    assert got == want
    for key in ("blocks", "cracks", "physical_covers", "manifold_elements", "unknowns",
                "block_area_total", "smallest_block_area"):
        assert key in got


def test_check_of_a_cut_model_matches_the_cli(repo, nmm_cli, monkeypatch):
    monkeypatch.chdir(repo)
    got = nmm.check(nmm.Model.load("examples/jointed_slope.toml"))
    want = json.loads(cli(nmm_cli, "check", "--json", "examples/jointed_slope.toml").stdout)
    assert got == want and got["cut_blocks"] >= 1


def test_from_toml_errors_name_string_source():
    text = incline_toml().replace("steps = 1000", "steps = 1000\nstep = 3")
    with pytest.raises(nmm.ModelError) as e:
        nmm.Model.from_toml(text)
    msg = str(e.value)
    assert "unknown key `step`" in msg and "(<string>, line 6)" in msg, msg
    assert "\n" not in msg
    # a TOML syntax error too
    with pytest.raises(nmm.ModelError, match="<string>"):
        nmm.Model.from_toml("[analysis\n")
    assert issubclass(nmm.ModelError, ValueError)


def test_load_errors_are_the_clis_line(tmp_path, nmm_cli):
    bad = tmp_path / "bad.toml"
    bad.write_text(incline_toml().replace("poisson = 0.25", "poisson = 0.5"))
    with pytest.raises(nmm.ModelError) as e:
        nmm.Model.load(str(bad))
    p = cli(nmm_cli, "check", bad)
    assert p.returncode != 0
    assert p.stderr.strip() == f"error: {e.value}"
    p = cli(nmm_cli, "run", bad, "--out", tmp_path / "o")
    assert p.stderr.strip() == f"error: {e.value}"


def test_relative_files_resolve_against_base_dir(tmp_path):
    (tmp_path / "motion.csv").write_text("t,ax\n0,0\n0.01,0.5\n1,0.5\n")
    text = incline_toml(steps=10) + '\n[base_motion]\nfile = "motion.csv"\n'
    with pytest.raises(nmm.ModelError, match="motion.csv"):
        nmm.Model.from_toml(text, base_dir=str(tmp_path / "elsewhere"))
    m = nmm.Model.from_toml(text, base_dir=str(tmp_path))
    assert [Path(f).name for f in m.files()] == ["motion.csv"]
    assert nmm.run(m).summary["status"] == "finished"


def test_set_goes_through_the_same_validation():
    m = nmm.Model.from_toml(incline_toml())
    m.set("analysis.steps", 20).set("interface.0.friction_angle", 25.0)
    assert m.get("analysis.steps") == 20
    assert m.get(("interface", 0, "friction_angle")) == 25.0
    m.set("material.rock.young", 2.0e9)  # an entry by its name
    assert m.get("material.rock.young") == 2.0e9
    # a dict is an inline table; a top-level dict a table
    m.set("material.rock.damping", {"ratio": 0.05, "frequencies": [1.0, 10.0]})
    assert m.get("material.rock.damping.ratio") == 0.05
    m.set("base_motion", {"table": [[0.0, 0.0, 0.0], [1.0, 0.1, 0.0]]})
    assert "[base_motion]" in m.to_toml()
    with pytest.raises(nmm.ModelError, match="damping"):
        m.set("material.rock.damping", {"ratio": -1.0, "frequencies": [1.0, 10.0]})
    m.set("base_motion", None).set("material.rock.damping", None)
    before = m.to_toml()
    # the file format's own error, naming the key and line; the model is unchanged
    with pytest.raises(nmm.ModelError, match=r"friction_angle.*\[0, 90\)"):
        m.set("interface.0.friction_angle", 95.0)
    with pytest.raises(nmm.ModelError, match="expected a number"):
        m.set("analysis.dt", "fast")
    with pytest.raises(nmm.ModelError, match="unknown key `dtt`"):
        m.set("analysis.dtt", 1e-3)
    with pytest.raises(KeyError):
        m.set("block.nosuch.fixed", True)
    assert m.to_toml() == before
    # the rest of the text keeps its comments and lines
    assert m.to_toml().splitlines()[0].startswith("# A block on a plane")


def test_with_overrides_is_a_new_model_validated_once():
    base = nmm.Model.from_toml(incline_toml())
    # dt and steps changed together: each alone would be fine too, but order must not matter
    m = base.with_overrides({"analysis.dt": 2e-3, "analysis.steps": 5, "cover.size": 0.125})
    assert base.get("analysis.steps") == 1000 and m.get("analysis.steps") == 5
    with pytest.raises(nmm.ModelError, match="unknown key `frction_angle`"):
        base.with_overrides({"interface.0.frction_angle": 10})


def test_build_a_model_from_python():
    d = nmm.Model.from_toml(incline_toml()).to_dict()
    m = nmm.Model.from_dict(d)
    assert m.source == "<dict>"
    assert nmm.check(m)["blocks"] == 2
    # add a block, a monitor, an interface; remove them again
    m.add("block", {"name": "cap", "material": "rock",
                    "vertices": [[10.0, 10.0], [10.5, 10.0], [10.5, 10.25], [10.0, 10.25]]})
    m.add("monitor", {"name": "cap", "point": [10.25, 10.1]})
    assert nmm.check(m)["blocks"] == 3
    assert m.monitor_columns[-4:] == ["cap.ux", "cap.uy", "cap.vx", "cap.vy"]
    with pytest.raises(nmm.ModelError, match='unknown block "nope"'):
        m.add("interface", {"blocks": ["cap", "nope"], "friction_angle": 30.0,
                            "normal_penalty": 1e9, "shear_penalty": 1e9})
    with pytest.raises(nmm.ModelError, match=r"monitor.*cap"):
        m.remove("block", "cap")  # the monitor still names a point on it
    m.remove("monitor", "cap").remove("block", "cap")
    assert nmm.check(m)["blocks"] == 2
    with pytest.raises(nmm.ModelError, match="<dict>"):
        nmm.Model.from_dict({**d, "analysis": {**d["analysis"], "mode": "quasi"}})


def test_pickle_round_trip():
    import pickle

    m = nmm.Model.from_toml(incline_toml(steps=7))
    m2 = pickle.loads(pickle.dumps(m))
    assert m2.to_toml() == m.to_toml() and m2.get("analysis.steps") == 7


def test_run_history_is_the_clis_history_csv(tmp_path, nmm_cli):
    path = tmp_path / "incline.toml"
    path.write_text(incline_toml(steps=300))
    p = cli(nmm_cli, "run", path, "--out", tmp_path / "cli")
    assert p.returncode == 0, p.stderr
    r = nmm.run(nmm.Model.load(str(path)), out=tmp_path / "py")
    assert r.out == tmp_path / "py"
    assert (tmp_path / "py" / "history.csv").read_bytes() == (tmp_path / "cli" / "history.csv").read_bytes()
    assert (tmp_path / "py" / "blocks.pvd").exists()  # VTK frames with out=, as nmm run
    header = (tmp_path / "cli" / "history.csv").read_text().splitlines()[0].split(",")
    assert list(r.history.columns) == header
    # every number of the DataFrame is the CSV's, exactly
    import csv

    with open(tmp_path / "cli" / "history.csv") as f:
        rows = list(csv.reader(f))[1:]
    assert len(rows) == len(r.history)
    for i, row in enumerate(rows):
        assert [float(x) for x in row] == [float(v) for v in r.history.iloc[i]]
    s = r.summary
    assert s["status"] == "finished" and s["steps"] == 300
    for k in ("steps", "cuts", "iterations", "timings"):
        assert k in s
    assert s["iterations"]["total"] == int(r.history["iterations"].sum())


def test_run_without_out_leaves_nothing(tmp_path):
    import tempfile

    before = set(os.listdir(tempfile.gettempdir()))
    r = nmm.run(incline_toml(steps=50))
    assert r.out is None and len(r.history) == 50
    assert not [d for d in set(os.listdir(tempfile.gettempdir())) - before if d.startswith("nmm-run-")]


def test_run_error_is_raised_and_outputs_kept(repo, tmp_path, nmm_cli):
    m = nmm.Model.load(str(repo / EXAMPLE)).with_overrides(
        {"analysis.max_iterations": 1, "analysis.max_step_cuts": 2})
    with pytest.raises(nmm.RunError, match="did not converge after 2 time-step cuts") as e:
        nmm.run(m, out=tmp_path / "o")
    assert "\n" not in str(e.value)
    assert e.value.summary["status"] == "failed"
    assert list(e.value.history.columns)[-3:] == ["iterations", "solves", "cuts"]
    assert (tmp_path / "o" / "history.csv").exists()
    # the CLI's line for the same model names the same error
    path = tmp_path / "m.toml"
    path.write_text(m.to_toml())
    p = cli(nmm_cli, "run", path, "--out", tmp_path / "o")
    assert p.stderr.strip() == f"error: {path}: {e.value}"


def test_threads_and_progress_arguments():
    seen = []
    r = nmm.run(incline_toml(steps=400), progress=lambda s, n, t: seen.append((s, n, t)), threads=1)
    assert seen and seen[-1][:2] == (400, 400)
    assert [s for s, _, _ in seen] == sorted(s for s, _, _ in seen)
    assert len(r.history) == 400
    assert r.summary["threads"] == 1
    r2 = nmm.run(incline_toml(steps=400), threads=2)
    assert r2.summary["threads"] == 2
    # the same numbers whatever the thread count
    pd.testing.assert_frame_equal(r.history, r2.history, check_exact=True)
    with pytest.raises(ValueError):
        nmm.run(incline_toml(steps=5), threads=0)


def test_the_gil_is_released_while_a_run_computes():
    m = nmm.Model.from_toml(incline_toml(steps=6000))
    done = threading.Event()
    box = {}

    def work():
        box["t0"] = time.perf_counter()
        box["r"] = nmm.run(m)
        box["t1"] = time.perf_counter()
        done.set()

    th = threading.Thread(target=work)
    ticks = []
    th.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        x = 0
        for i in range(20000):  # pure-Python work: needs the GIL
            x += i
    th.join()
    during = [t for t in ticks if box["t0"] < t < box["t1"]]
    span = box["t1"] - box["t0"]
    assert span > 0.5, span
    gaps = [b - a for a, b in zip(during, during[1:])]
    # Python ran all along the run, never held off for long (with the GIL held by the run,
    # there would be no tick during it at all)
    assert len(during) > 20 and max(gaps) < min(0.5, span / 3), (len(during), max(gaps or [0]), span)


def test_ctrl_c_stops_the_run_cleanly_keeping_outputs(tmp_path):
    model = tmp_path / "long.toml"
    model.write_text(incline_toml(steps=200000))
    out = tmp_path / "out"
    script = textwrap.dedent(f"""
        import sys, nmm
        try:
            nmm.run(nmm.Model.load({str(model)!r}), out={str(out)!r}, vtk=False)
        except nmm.Interrupted as e:
            r = e.result
            print("interrupted", r.summary["status"], r.summary["steps"], len(r.history))
            sys.exit(130)
        print("finished")
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    hist = out / "history.csv"
    t0 = time.time()
    while time.time() - t0 < 60:
        if hist.exists() and hist.read_text().count("\n") > 50:
            break
        time.sleep(0.05)
    p.send_signal(signal.SIGINT)
    stdout, _ = p.communicate(timeout=60)
    assert p.returncode == 130, stdout
    word, status, steps, rows = stdout.split()
    assert (word, status) == ("interrupted", "interrupted")
    assert 50 < int(steps) < 200000 and int(rows) == int(steps)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["steps"] == int(steps)
    assert hist.read_text().count("\n") == int(steps) + 1


def test_a_failing_progress_callback_stops_the_run_and_is_raised(tmp_path):
    def cb(step, total, t):
        if step > 0:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        nmm.run(incline_toml(steps=100000), out=tmp_path / "o", progress=cb, vtk=False)
    # the run stopped cleanly: summary.json says so, and history.csv has its rows
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["status"] == "interrupted" and 0 < summary["steps"] < 100000


def test_stop_all_stops_runs_on_other_threads(tmp_path):
    from nmm import _nmm

    box = {}

    def work():
        try:
            box["r"] = nmm.run(incline_toml(steps=100000), out=tmp_path / "o", vtk=False)
        except nmm.Interrupted as e:
            box["interrupted"] = e.result

    th = threading.Thread(target=work)
    th.start()
    hist = tmp_path / "o" / "history.csv"
    t0 = time.time()
    while time.time() - t0 < 60 and not (hist.exists() and hist.read_text().count("\n") > 20):
        time.sleep(0.02)
    assert _nmm.stop_all() == 1
    th.join(60)
    assert not th.is_alive()
    # the stopped run raises Interrupted on its own thread, with the partial result
    assert "r" not in box
    assert box["interrupted"].summary["status"] == "interrupted"
    assert len(box["interrupted"].history) == box["interrupted"].summary["steps"]
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["status"] == "interrupted"


def test_typed_builders_make_the_incline_of_the_file():
    """The incline built call by call equals the one read from its TOML text."""
    ref = nmm.Model.from_toml(incline_toml(steps=200))
    d = ref.to_dict()
    # a valid start (a placeholder block), then typed calls, each validated as it is made
    b = nmm.Model.from_dict({"analysis": d["analysis"], "cover": d["cover"],
                             "material": [{"name": "tmp", "density": 1.0, "young": 1.0, "poisson": 0.0}],
                             "block": [{"name": "tmp", "material": "tmp", "fixed": True,
                                        "vertices": [[50.0, 50.0], [51.0, 50.0], [51.0, 51.0]]}]})
    b.add_material("rock", density=2000.0, young=1.0e9, poisson=0.25)
    b.add_interface(20.0, normal_penalty=1.0e9, shear_penalty=1.0e9)
    base, slider = d["block"]
    b.add_block("base", "rock", base["vertices"], fixed=True)
    b.add_block("slider", "rock", slider["vertices"])
    b.add_monitor("c", point=d["monitor"][0]["point"])
    b.remove("block", "tmp").remove("material", "tmp")
    assert b.canonical() == ref.canonical()
    assert nmm.run(b).history.equals(nmm.run(ref).history)
    # the typed calls go through the same validation
    with pytest.raises(nmm.ModelError, match="poisson"):
        b.add_material("soft", density=1000.0, young=1.0e6, poisson=0.7)
    with pytest.raises(nmm.ModelError, match=r"unknown key `colour`"):
        b.add_block("c2", "rock", [[10, 10], [11, 10], [11, 11]], colour="red")
    b.set_base_motion(table=[[0.0, 0.0, 0.0], [0.5, 1.0, 0.0]], scale=0.5)
    assert b.get("base_motion.scale") == 0.5
    with pytest.raises(nmm.ModelError, match="either `table` or `file`"):
        b.set_base_motion(table=[[0.0, 0.0, 0.0]], file="x.csv")
    b.add_joint_set("bed", angle=10.0, spacing=0.1, blocks=["slider"])
    assert nmm.check(b)["blocks"] > 2
    b.add_joint("f", [[-10.0, 0.0], [10.0, 20.0]], blocks=["slider"])
    assert nmm.check(b)["joints"] == 2


def test_a_staged_run_has_the_stage_column_as_the_cli(tmp_path, nmm_cli):
    text = incline_toml(steps=20) + (
        '\n[[stage]]\nname = "settle"\nmode = "static"\ndt = 0.01\nsteps = 5\n'
        '\n[[stage]]\nname = "slide"\nsteps = 10\n'
    )
    m = nmm.Model.from_toml(text)
    assert m.history_columns[-4:] == ["iterations", "stage", "solves", "cuts"]
    assert nmm.check(m)["stages"] == ["settle", "slide"]
    r = nmm.run(m, out=tmp_path / "py", vtk=False)
    assert list(r.history.columns) == m.history_columns
    assert list(r.history["stage"].unique()) == ["settle", "slide"] and len(r.history) == 15
    path = tmp_path / "staged.toml"
    path.write_text(text)
    p = cli(nmm_cli, "run", path, "--out", tmp_path / "cli", "--no-vtk")
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "py" / "history.csv").read_bytes() == (tmp_path / "cli" / "history.csv").read_bytes()
