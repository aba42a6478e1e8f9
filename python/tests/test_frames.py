"""Seeing a model and a run from Python: Model.blocks() (the blocks as cut), Result.frames and
Result.frame(k) (the run's VTK frames, read by the library's reader), nmm.plot."""

import json
import math
import re
import sys

import numpy as np
import pandas as pd
import pytest

import nmm
from conftest import cli
from incline import closed_form, incline_toml, slip

THETA, PHI = 30.0, 20.0


def shoelace(p):
    p = np.asarray(p, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def centroid(p):
    x, y = p[:, 0], p[:, 1]
    c = x * np.roll(y, -1) - np.roll(x, -1) * y
    return np.array([((x + np.roll(x, -1)) * c).sum(), ((y + np.roll(y, -1)) * c).sum()]) / (3 * c.sum())


def test_blocks_of_an_uncut_model():
    m = nmm.Model.from_toml(incline_toml(steps=5))
    b = m.blocks()
    assert isinstance(b, pd.DataFrame)
    assert list(b.index) == [0, 1] and b.index.name == "id"
    assert list(b["name"]) == ["base", "slider"]
    assert list(b["material"]) == ["rock", "rock"]
    assert list(b["fixed"]) == [True, False]
    assert list(b["parent"]) == [None, None]
    assert [p.shape for p in b["polygon"]] == [(4, 2), (4, 2)]
    # 4 m × 0.5 m and 0.5 m × 0.25 m, rotated
    assert b["area"].tolist() == pytest.approx([2.0, 0.125], rel=1e-12)
    for poly, area in zip(b["polygon"], b["area"]):
        assert shoelace(poly) == pytest.approx(area, rel=1e-12)  # counter-clockwise
    assert all((j == -1).all() for j in b["joints"])


def test_blocks_of_a_jointed_model_are_the_pieces_as_cut(repo, nmm_cli, monkeypatch):
    monkeypatch.chdir(repo)
    path = "examples/jointed_slope.toml"
    m = nmm.Model.load(path)
    b = m.blocks()
    want = json.loads(cli(nmm_cli, "check", "--json", path).stdout)
    assert len(b) == want["blocks"] > 100
    assert int(b["fixed"].sum()) == want["fixed_blocks"]
    assert b["area"].sum() == pytest.approx(want["block_area_total"], rel=1e-12)
    assert b["area"].min() == want["smallest_block_area"]
    assert b.loc[b["area"].idxmin(), "name"] == want["smallest_block"]
    cut = b[b["parent"].notna()]
    assert cut["parent"].nunique() == want["cut_blocks"] >= 1
    # pieces are named NAME.k after the block they were cut from
    for name, parent in zip(cut["name"], cut["parent"]):
        assert re.fullmatch(re.escape(parent) + r"\.\d+", name), (name, parent)
    # the pieces of each block fill it: their areas add up to the block as drawn
    for parent, pieces in cut.groupby("parent"):
        drawn = abs(shoelace(m.get(("block", parent, "vertices"))))
        assert pieces["area"].sum() == pytest.approx(drawn, rel=1e-9), parent
        for poly, area in zip(pieces["polygon"], pieces["area"]):
            assert poly.ndim == 2 and poly.shape[1] == 2 and poly.dtype == np.float64
            assert shoelace(poly) == pytest.approx(area, rel=1e-9)
    # faces made by joints name the joint (ids into the joint sets, then the joints)
    joints = b.attrs["joints"]
    ids = np.concatenate(list(b["joints"]))
    assert ids.max() < len(joints) and (ids >= 0).any()
    assert all(len(j) == len(p) for j, p in zip(b["joints"], b["polygon"]))


@pytest.fixture(scope="module")
def incline_run(tmp_path_factory):
    """200 steps of the incline (θ = 30°, φ = 20°: it slides), a frame every 50 steps."""
    out = tmp_path_factory.mktemp("incline") / "run"
    text = incline_toml(THETA, PHI, steps=200).replace("steps = 200", "steps = 200\noutput_every = 50")
    m = nmm.Model.from_toml(text)
    return m, nmm.run(m, out=out)


def test_frames_are_the_runs_vtk_frames(incline_run):
    m, r = incline_run
    frames = r.frames
    pvd = (r.out / "blocks.pvd").read_text()
    vtus = sorted((r.out / "vtk").glob("blocks_*.vtu"))
    assert len(frames) == pvd.count("<DataSet ") == len(vtus) == 5  # steps 0, 50, …, 200
    assert frames.steps == [0, 50, 100, 150, 200]
    assert frames.times == pytest.approx([0.0, 0.05, 0.1, 0.15, 0.2], abs=1e-15)
    assert [f.name for f in frames.files] == [v.name for v in vtus]
    seen = [f.step for f in frames]  # iteration
    assert seen == frames.steps
    assert [f.step for f in frames[1:3]] == [50, 100]
    assert r.frame().step == r.frame(-1).step == frames[4].step == 200
    assert frames.nearest(0.11).step == 100
    with pytest.raises(IndexError, match="no frame 5"):
        frames[5]
    # a run folder read back later
    again = nmm.Result.load(r.out)
    assert again.history.equals(r.history) and again.summary == r.summary
    assert len(again.frames) == 5


def test_frame_arrays_and_the_slide_against_history_and_closed_form(incline_run):
    m, r = incline_run
    check = nmm.check(m)
    f0 = r.frame(0)
    assert f0.step == 0 and f0.time == 0.0
    n = len(f0.elements)
    assert n == len(f0.polygons) == check["manifold_elements"]
    assert f0.points.shape == f0.displacement.shape == f0.velocity.shape
    assert f0.points.shape[1] == 2
    assert list(f0.elements.columns) == ["block", "name", "ux", "uy", "u", "sxx", "syy", "sxy", "szz"]
    assert set(f0.elements["name"]) == {"base", "slider"}
    assert not f0.displacement.any()
    assert len(f0.contacts) == 0 and "state" in f0.contacts.columns  # no contact frame at step 0
    # the deformed outlines at step 0 are the blocks as cut
    blocks = m.blocks()
    assert list(f0.blocks["name"]) == list(blocks["name"])
    for poly, area in zip(f0.blocks["polygon"], blocks["area"]):
        assert shoelace(poly) == pytest.approx(area, rel=1e-9)

    last = r.frame(-1)
    e = last.elements
    slider = e[e["name"] == "slider"]
    base = e[e["name"] == "base"]
    assert (base[["ux", "uy"]].abs().to_numpy() < 1e-12).all()  # fixed
    # the slider moves as one body: its elements' mean displacement is the monitor's
    h = r.history.set_index("step").loc[last.step]
    assert slider["ux"].mean() == pytest.approx(h["c.ux"], rel=1e-3)
    assert slider["uy"].mean() == pytest.approx(h["c.uy"], rel=1e-3)
    s = slip(slider["ux"].mean(), slider["uy"].mean(), THETA)
    exact = closed_form(last.time, THETA, PHI)
    assert abs(s - exact) < 0.02 * exact, (s, exact)
    assert e["u"].to_numpy() == pytest.approx(last.field("u"))
    assert e["u"].max() == pytest.approx(math.hypot(h["c.ux"], h["c.uy"]), rel=1e-3)
    # the slider's outline moved with it
    moved = last.blocks.loc[1, "polygon"]
    assert shoelace(moved) == pytest.approx(0.125, rel=1e-4)
    # its centroid moved by the monitor's displacement (the monitor is at its centre)
    moved_by = centroid(moved) - centroid(blocks.loc[1, "polygon"])
    assert moved_by == pytest.approx([h["c.ux"], h["c.uy"]], rel=1e-3)
    # the weight is carried by contacts sliding on the base
    c = last.contacts
    assert len(c) > 0
    assert set(c["state"]) <= {0, 1, 2} and (c["state"] == 2).any()
    assert set(c["vertex_block"]) | set(c["edge_block"]) <= {0, 1}
    assert (c["normal_force"] >= 0).all()
    assert (c.loc[c["state"] > 0, "normal_force"].sum()) > 0


def test_frames_need_the_vtk_output(tmp_path):
    text = incline_toml(steps=5)
    with pytest.raises(ValueError, match="folder is gone"):
        nmm.run(text).frames
    r = nmm.run(text, out=tmp_path / "novtk", vtk=False)
    with pytest.raises(ValueError, match="no blocks.pvd"):
        r.frame(0)
    with pytest.raises(FileNotFoundError):
        nmm.Result.load(tmp_path / "nothing")


# ---------------------------------------------------------------- nmm.plot (matplotlib)


def _cells(fig):
    from matplotlib.collections import PolyCollection

    return [c for c in fig.axes[0].collections if isinstance(c, PolyCollection)][0]


def test_plot_of_a_run_changes_with_field_and_frame(incline_run, tmp_path):
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    _, r = incline_run
    fig = nmm.plot(r)  # the last frame, |u|
    assert isinstance(fig, Figure)
    cells = _cells(fig)
    last = r.frame(-1)
    assert len(cells.get_paths()) == len(last.elements)
    u_last = np.asarray(cells.get_array())
    # |u| in mm (below 1 cm) or m, as `nmm plot`
    unit = "mm" if last.field("u").max() < 0.01 else "m"
    factor = 1e-3 if unit == "mm" else 1.0
    assert u_last == pytest.approx(last.field("u") / factor)
    labels = [a.get_ylabel() for a in fig.axes[1:]]
    assert labels == [f"|u| ({unit})"], labels
    title = fig.axes[0].get_title()
    assert "step 200" in title and "t = 0.2 s" in title
    sxx = np.asarray(_cells(nmm.plot(r, field="sxx")).get_array())
    assert not np.allclose(sxx, u_last), "the field changes the colours"
    u_first = np.asarray(_cells(nmm.plot(r, frame=1)).get_array())
    assert not np.allclose(u_first, u_last), "the frame changes the colours"
    assert np.array_equal(np.asarray(_cells(nmm.plot(r, time=0.06)).get_array()), u_first)
    # a path, a Frame and out=
    png = tmp_path / "frame.png"
    fig2 = nmm.plot(str(r.out), out=png, field="uy")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.array_equal(_cells(fig2).get_array(), _cells(nmm.plot(last, field="uy")).get_array())
    with pytest.raises(ValueError, match="unknown field"):
        nmm.plot(r, field="sxz")
    plt.close("all")


def test_plot_of_a_model_draws_the_blocks_as_cut(repo, monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(repo)
    m = nmm.Model.load("examples/jointed_slope.toml")
    fig = nmm.plot(m)
    blocks = m.blocks()
    assert len(_cells(fig).get_paths()) == len(blocks)
    texts = {t.get_text() for t in fig.axes[0].texts}
    assert set(blocks["name"]) <= texts
    assert "blocks as cut" in fig.axes[0].get_title()
    with pytest.raises(ValueError, match="frame"):
        nmm.plot(m, frame=0)
    plt.close("all")


def test_plot_without_matplotlib_says_how_to_install_it(monkeypatch):
    for name in list(sys.modules):
        if name == "matplotlib" or name.startswith("matplotlib."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"pip install matplotlib"):
        nmm.plot(nmm.Model.from_toml(incline_toml(steps=5)))
