"""nmm.study on a LocalCluster of 2 workers: 8 incline variants (friction angles) and a
variant with a bad key."""

import json
import math

import pandas as pd
import pytest

import nmm
import nmm.study
from conftest import cli
from incline import closed_form, incline_toml, slip

THETA = 30.0
PHIS = [10.0, 14.0, 18.0, 22.0, 26.0, 32.0, 36.0, 40.0]



def variants():
    v = {f"phi{int(p):02d}": {"interface.0.friction_angle": p} for p in PHIS}
    v["badkey"] = {"interface.0.friction_angel": 20.0}
    return v


def test_study_of_incline_variants(tmp_path, client, nmm_cli):
    base = nmm.Model.from_toml(incline_toml(theta=THETA))
    out = tmp_path / "study"
    df = nmm.study.run(variants(), client=client, out=out, base=base)
    assert list(df.index) == list(variants())
    assert df.index.name == "name"
    # the bad key is reported in its row, with the file format's one-line message
    bad = df.loc["badkey"]
    assert bad["status"] == "error"
    assert "unknown key `friction_angel`" in bad["error"] and "(<string>, line" in bad["error"]
    good = df.drop(index="badkey")
    assert (good["status"] == "ok").all(), good[["status", "error"]]
    assert good["error"].isna().all()
    assert (good["steps"] == 1000).all()
    for c in ("c.ux", "c.uy", "c.vx", "c.vy"):
        assert {f"{c}.min", f"{c}.max", f"{c}.final"} <= set(df.columns)
    # the overridden values are columns, after the base columns and before the monitors'
    assert "interface.0.friction_angle" in df.columns
    assert list(good["interface.0.friction_angle"]) == list(PHIS)
    cols = list(df.columns)
    assert cols.index("interface.0.friction_angle") < cols.index("c.ux.min")
    assert cols.index("hash") < cols.index("interface.0.friction_angle")
    # each final slip against the closed form ½ g (sin θ − cos θ tan φ) t²
    for name, phi in zip(good.index, PHIS):
        h = nmm.read_history(out / name / "history.csv")
        assert len(h) == 1000
        s = slip(h["c.ux"].iloc[-1], h["c.uy"].iloc[-1], THETA)
        assert math.isclose(s, slip(good.loc[name, "c.ux.final"], good.loc[name, "c.uy.final"], THETA))
        exact = closed_form(h["time"].iloc[-1], THETA, phi)
        if phi < THETA:
            assert abs(s - exact) < 0.02 * exact, (name, s, exact)
        else:
            assert abs(s) < 1e-3, (name, s)
        # the row's min and max are the history's
        assert good.loc[name, "c.ux.max"] == h["c.ux"].max()
        assert good.loc[name, "c.uy.min"] == h["c.uy"].min()
    # one variant's history.csv is `nmm run`'s, byte for byte
    path = tmp_path / "phi18.toml"
    path.write_text(base.with_overrides({"interface.0.friction_angle": 18.0}).to_toml())
    p = cli(nmm_cli, "run", path, "--out", tmp_path / "cli18", "--no-vtk")
    assert p.returncode == 0, p.stderr
    assert (out / "phi18" / "history.csv").read_bytes() == (tmp_path / "cli18" / "history.csv").read_bytes()
    saved = pd.read_csv(out / "study.csv", index_col="name")
    assert list(saved.index) == list(df.index)

    # a second run of the same study skips all 8 (the bad one is reported again)
    stamps = {n: (out / n / "history.csv").stat().st_mtime_ns for n in good.index}
    again = nmm.study.run(variants(), client=client, out=out, base=base)
    assert (again.drop(index="badkey")["status"] == "skipped").all(), again["status"]
    assert again.loc["badkey", "status"] == "error"
    assert {n: (out / n / "history.csv").stat().st_mtime_ns for n in good.index} == stamps
    cols = [c for c in df.columns if c.startswith("c.") or c in ("steps", "iterations", "cuts")]
    pd.testing.assert_frame_equal(again.loc[good.index, cols], good[cols], check_dtype=False)

    # a changed model reruns only that run; incomplete outputs rerun too
    changed = variants()
    changed["phi10"] = {"interface.0.friction_angle": 10.0, "analysis.steps": 500}
    (out / "phi14" / "study.json").unlink()
    third = nmm.study.run(changed, client=client, out=out, base=base)
    assert third.loc["phi10", "status"] == "ok" and third.loc["phi10", "steps"] == 500
    assert third.loc["phi14", "status"] == "ok"
    assert (third.drop(index=["phi10", "phi14", "badkey"])["status"] == "skipped").all()


def test_study_entries_of_every_kind_on_its_own_cluster(tmp_path, capsys):
    """Models given as nmm.Model, TOML text and a path; no client: a LocalCluster is
    started for the study. A failing run records its error and the others complete."""
    path = tmp_path / "m.toml"
    path.write_text(incline_toml(steps=30))
    failing = nmm.Model.load(str(path)).with_overrides(
        {"analysis.max_iterations": 1, "analysis.max_step_cuts": 0, "analysis.dt": 0.5})
    models = {
        "model": nmm.Model.from_toml(incline_toml(steps=20)),
        "text": incline_toml(steps=10),
        "path": str(path),
        "fails": failing,
        "bad/name": incline_toml(steps=10),
    }
    df = nmm.study.run(models, out=tmp_path / "s", n_workers=2, progress=True)
    assert df.loc["model", "steps"] == 20 and df.loc["text", "steps"] == 10
    assert df.loc["path", "steps"] == 30
    assert (df.loc[["model", "text", "path"], "status"] == "ok").all()
    assert df.loc["fails", "status"] == "error"
    assert "did not converge" in df.loc["fails", "error"]
    assert df.loc["bad/name", "status"] == "error" and "folder name" in df.loc["bad/name", "error"]
    mark = json.loads((tmp_path / "s" / "path" / "study.json").read_text())
    assert mark["hash"] == df.loc["path", "hash"] == nmm.study.model_hash(nmm.Model.load(str(path)))
    assert not (tmp_path / "s" / "fails" / "study.json").exists()
    # progress: one line per run that went to the cluster (the bad name never did)
    lines = [l for l in capsys.readouterr().err.splitlines() if l.startswith("[")]
    assert len(lines) == 4 and lines[-1].startswith("[4/4] ")
    assert any(" fails error " in l and "did not converge" in l for l in lines)


def test_hash_ignores_layout_but_not_content():
    a = nmm.Model.from_toml(incline_toml())
    b = nmm.Model.from_toml("# another comment\n" + incline_toml().replace(" = ", "="))
    assert nmm.study.model_hash(a) == nmm.study.model_hash(b)
    c = a.copy().set("interface.0.friction_angle", 20.5)
    assert nmm.study.model_hash(a) != nmm.study.model_hash(c)
    assert nmm.study.model_hash(a) != nmm.study.model_hash(a, vtk=True)


def test_the_notebook_style_example_runs(repo, tmp_path):
    """examples/study.py: a small study and its plot."""
    pytest.importorskip("matplotlib")
    import os
    import subprocess
    import sys

    env = {**os.environ, "NMM_STUDY_OUT": str(tmp_path / "ex")}
    p = subprocess.run([sys.executable, str(repo / "examples" / "study.py")], env=env,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "ex" / "study.png").stat().st_size > 10000
    table = pd.read_csv(tmp_path / "ex" / "study.csv", index_col="name")
    assert len(table) == 7 and (table["status"] == "ok").all()


def test_a_dataframe_of_overrides_on_a_scheduler_address(tmp_path, client):
    base = nmm.Model.from_toml(incline_toml(steps=40))
    design = pd.DataFrame(
        {"interface.0.friction_angle": [15.0, 25.0], "analysis.steps": [30, None]},
        index=["a", "b"],
    )
    # the client may be given as what Client() takes: here the scheduler's address
    df = nmm.study.run(design, base=base, out=tmp_path / "d", client=client.scheduler.address)
    assert list(df["status"]) == ["ok", "ok"]
    assert list(df["steps"]) == [30, 40]  # an empty cell keeps the base's value
    assert df.loc["a", "hash"] == nmm.study.model_hash(
        base.with_overrides({"interface.0.friction_angle": 15, "analysis.steps": 30}))


def test_ctrl_c_stops_a_study_and_its_runs(tmp_path):
    """Ctrl-C during a study on its own (in-process) cluster: KeyboardInterrupt, the runs
    stop cleanly after their current step, and a later study runs them again."""
    import os
    import signal
    import subprocess
    import sys
    import textwrap
    import time

    out = tmp_path / "s"
    script = textwrap.dedent(f"""
        import sys, time
        sys.path.insert(0, {str(os.path.dirname(__file__))!r})
        from incline import incline_toml
        import nmm, nmm.study
        base = nmm.Model.from_toml(incline_toml(steps=200000))
        try:
            nmm.study.run({{"a": {{"interface.0.friction_angle": 10.0}},
                            "b": {{"interface.0.friction_angle": 40.0}}}},
                          base=base, out={str(out)!r}, n_workers=2)
        except KeyboardInterrupt:
            print("interrupted")
            sys.exit(130)
        print("finished")
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    hist = [out / n / "history.csv" for n in ("a", "b")]
    t0 = time.time()
    while time.time() - t0 < 120:
        if all(h.exists() and h.read_text().count("\n") > 50 for h in hist):
            break
        time.sleep(0.05)
    p.send_signal(signal.SIGINT)
    stdout, _ = p.communicate(timeout=120)
    assert p.returncode == 130 and stdout.strip() == "interrupted", stdout
    for n in ("a", "b"):
        s = json.loads((out / n / "summary.json").read_text())
        assert s["status"] == "interrupted" and s["steps"] < 200000
        assert not (out / n / "study.json").exists()


def test_a_study_survives_a_dead_worker(tmp_path):
    """A worker process killed (SIGKILL) in the middle of a long run: the study still
    returns a row for every run — the killed one an error row whose one-line message names
    it, the others complete — instead of raising. allowed-failures = 0: dask does not run
    the task again on another worker (with retries the row would be a re-run instead)."""
    import os
    import signal
    import threading
    import time

    dask = pytest.importorskip("dask")
    distributed = pytest.importorskip("distributed")
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
        client = distributed.Client(cluster)
        try:
            models = {
                # held by friction (40° > 30°): the long run goes on until it is killed
                "long": incline_toml(theta=THETA, phi=40.0, steps=5_000_000),
                "a": incline_toml(theta=THETA, phi=40.0, steps=100),
                "b": incline_toml(theta=THETA, phi=10.0, steps=100),
            }
            out = tmp_path / "study"
            result = {}

            def study():
                try:
                    result["df"] = nmm.study.run(models, client=client, out=out)
                except BaseException as e:  # noqa: BLE001 - reported by the assertion below
                    result["error"] = e

            t = threading.Thread(target=study, daemon=True)
            t.start()
            # wait until the short runs are done and the long one is running on a worker
            deadline = time.monotonic() + 120
            victim = None
            while victim is None:
                assert time.monotonic() < deadline, "the long run never started"
                assert t.is_alive(), result
                done = all((out / n / "summary.json").exists() for n in ("a", "b"))
                if done:
                    for addr, keys in client.processing().items():
                        if any("nmm-run-long" in str(k) for k in keys):
                            victim = addr
                time.sleep(0.2)
            time.sleep(1.0)  # well inside the run
            pids = client.run(os.getpid)
            os.kill(pids[victim], signal.SIGKILL)
            t.join(120)
            assert not t.is_alive(), "the study did not return after its worker died"
            assert "error" not in result, result.get("error")
            df = result["df"]
            assert list(df.index) == ["long", "a", "b"]
            assert df.loc["a", "status"] == "ok" and df.loc["b", "status"] == "ok", df
            assert df.loc["long", "status"] == "error", df
            msg = df.loc["long", "error"]
            assert "KilledWorker" in msg and "long" in msg and "\n" not in msg, msg
            # the table on disk says the same
            on_disk = pd.read_csv(out / "study.csv", index_col="name")
            assert on_disk.loc["long", "status"] == "error"
        finally:
            client.close()
            cluster.close()
