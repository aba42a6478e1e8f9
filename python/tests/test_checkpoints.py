"""Checkpoints from Python: `nmm.run(..., checkpoint_every=N)`, `nmm.resume(OUT)` and
`nmm.run(..., start_from=CKPT)`, against the command line's `nmm resume` and `nmm run --from`
(byte-identical history.csv), and their errors."""

import json

import nmm
import pytest
from conftest import cli
from incline import incline_toml

STAGED = incline_toml(steps=20) + (
    '\n[[stage]]\nname = "settle"\nmode = "static"\ndt = 0.01\nsteps = 5\n'
    '\n[[stage]]\nname = "slide"\nsteps = 40\n'
)


def test_an_interrupted_run_resumed_from_python_is_the_whole_run(tmp_path):
    model = tmp_path / "long.toml"
    model.write_text(STAGED.replace("steps = 40", "steps = 3000"))
    whole = nmm.run(nmm.Model.load(model), out=tmp_path / "whole", vtk=False)
    assert len(whole.history) == 3005

    def stop(step, total, t):
        if step > 0:
            raise KeyboardInterrupt

    out = tmp_path / "cut"
    with pytest.raises(KeyboardInterrupt):
        nmm.run(nmm.Model.load(model), out=out, vtk=False, progress=stop, checkpoint_every=7)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted" and 0 < summary["steps"] < 3005
    assert any((out / "checkpoints").iterdir())
    r = nmm.resume(out)
    assert r.summary["status"] == "finished" and r.summary["steps"] == 3005
    assert len(r.history) == 3005
    assert (out / "history.csv").read_bytes() == (tmp_path / "whole" / "history.csv").read_bytes()


def test_resume_matches_the_cli_and_refuses_a_folder_without_checkpoint(tmp_path, nmm_cli):
    model = tmp_path / "staged.toml"
    model.write_text(STAGED)
    # the settle stage's end writes a checkpoint; cut the run there by hand: both resume it
    for name in ("py", "cli"):
        nmm.run(nmm.Model.load(model), out=tmp_path / name, vtk=False)
        ck = sorted((tmp_path / name / "checkpoints").iterdir())
        assert ck, "a staged run writes a checkpoint at each stage's end"
    r = nmm.resume(tmp_path / "py", threads=1)
    p = cli(nmm_cli, "resume", tmp_path / "cli", "--threads", "1")
    assert p.returncode == 0, p.stderr
    assert len(r.history) == 45
    assert (tmp_path / "py" / "history.csv").read_bytes() == (
        tmp_path / "cli" / "history.csv"
    ).read_bytes()
    with pytest.raises(ValueError, match="no checkpoint to resume from"):
        nmm.resume(tmp_path / "nothing-here")


def test_a_branch_from_a_checkpoint_matches_the_cli(tmp_path, nmm_cli):
    model = tmp_path / "staged.toml"
    model.write_text(STAGED)
    nmm.run(nmm.Model.load(model), out=tmp_path / "base", vtk=False)
    settle_end = tmp_path / "base" / "checkpoints" / nmm_checkpoint_name(5)
    assert settle_end.exists(), sorted((tmp_path / "base" / "checkpoints").iterdir())
    # the branch: the same settled state, then a longer slide stage
    branch = STAGED.replace('name = "slide"\nsteps = 40', 'name = "slide"\nsteps = 60')
    bpath = tmp_path / "branch.toml"
    bpath.write_text(branch)
    r = nmm.run(nmm.Model.load(bpath), out=tmp_path / "b_py", vtk=False, start_from=settle_end)
    assert list(r.history["step"])[0] == 6 and len(r.history) == 60
    assert set(r.history["stage"]) == {"slide"}
    p = cli(nmm_cli, "run", bpath, "--out", tmp_path / "b_cli", "--no-vtk", "--from", settle_end)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "b_py" / "history.csv").read_bytes() == (
        tmp_path / "b_cli" / "history.csv"
    ).read_bytes()
    # the slide stage's rows of the base run are the branch's first 40
    base = (tmp_path / "base" / "history.csv").read_text().splitlines()
    mine = (tmp_path / "b_py" / "history.csv").read_text().splitlines()
    assert mine[1:41] == base[6:46]
    # a model whose saved state differs (another material) cannot start from it
    other = branch.replace("young = 1.0e9", "young = 2.0e9")
    with pytest.raises(ValueError, match="cannot start from"):
        nmm.run(other, vtk=False, start_from=settle_end)
    with pytest.raises(ValueError, match="checkpoint_every"):
        nmm.run(STAGED, vtk=False, checkpoint_every=-1)


def nmm_checkpoint_name(step):
    return f"step_{step:08}.ckpt"
