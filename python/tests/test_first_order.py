"""First-order covers (issue 16) from Python and in a study: `cover.order` is a model key
like any other; the incline at order 1 slides as the closed form, and a study's order-1 run
writes `nmm.run`'s history byte for byte."""

import pytest

import nmm
import nmm.study
from incline import closed_form, incline_toml, slip

THETA, PHI = 30.0, 20.0



def base():
    m = nmm.Model.from_toml(incline_toml(theta=THETA, phi=PHI, steps=300))
    m.set("cover.size", 0.25)
    return m


def test_order_one_from_python_and_in_a_study(tmp_path, client):
    m0 = base()
    m1 = m0.with_overrides({"cover.order": 1})
    # 6 unknowns per cover instead of 2 (less the dependent ones removed per block)
    n0, n1 = nmm.check(m0)["unknowns"], nmm.check(m1)["unknowns"]
    assert 2 * n0 < n1 <= 3 * n0, (n0, n1)
    with pytest.raises(nmm.ModelError, match="order"):
        m0.with_overrides({"cover.order": 2})
    r = nmm.run(m1, out=tmp_path / "o1", threads=1)
    h = r.history
    assert len(h) == 300
    # slip against ½ g (sin θ − cos θ tan φ) t²: the same 2% as the order-0 study test
    s = slip(h["c.ux"].iloc[-1], h["c.uy"].iloc[-1], THETA)
    exact = closed_form(h["time"].iloc[-1], THETA, PHI)
    assert abs(s - exact) < 0.02 * exact, (s, exact)
    df = nmm.study.run({"o0": {"cover.order": 0}, "o1": {"cover.order": 1}},
                       client=client, out=tmp_path / "study", base=m0)
    assert (df["status"] == "ok").all(), df[["status", "error"]]
    assert list(df["cover.order"]) == [0, 1]
    assert (tmp_path / "study" / "o1" / "history.csv").read_bytes() == \
        (tmp_path / "o1" / "history.csv").read_bytes()
    # order 0 and order 1 are different discretisations of the same slide
    h0 = nmm.read_history(tmp_path / "study" / "o0" / "history.csv")
    s0 = slip(h0["c.ux"].iloc[-1], h0["c.uy"].iloc[-1], THETA)
    assert abs(s0 - exact) < 0.02 * exact
