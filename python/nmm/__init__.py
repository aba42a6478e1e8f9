"""nmm — the Numerical Manifold Method for 2-D deformable blocks in contact, from Python.

    import nmm
    model = nmm.Model.load("examples/direct_shear.toml")
    print(nmm.check(model))                 # the keys of `nmm check --json`
    result = nmm.run(model, out="out/ds")   # as `nmm run MODEL --out out/ds`
    result.history                          # pandas DataFrame: the history.csv columns
    result.summary                          # summary.json as a dict
    result.frame(-1).elements               # the last VTK frame: DataFrame per element
    nmm.plot(result, field="sxx")           # a matplotlib Figure (nmm[plot])

A model is validated by the library itself (the same code as the command line): a model
the file format refuses raises :class:`ModelError` with the same one-line message. Changes
made from Python (:meth:`Model.set`, :meth:`Model.with_overrides`, :meth:`Model.add`,
:meth:`Model.remove`) edit the model's TOML text and validate it again.

Parameter studies on dask.distributed: :func:`nmm.study.run`.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable, Optional, Union

from ._nmm import Model, ModelError, RunError, version
from . import _nmm
from ._frames import Frame, Frames
from ._plot import plot

__all__ = [
    "Model",
    "ModelError",
    "RunError",
    "Interrupted",
    "Result",
    "Frame",
    "Frames",
    "check",
    "plot",
    "run",
    "resume",
    "read_history",
    "as_model",
    "study",
    "__version__",
]

__version__ = version()


class Result:
    """A finished run: ``history`` (DataFrame of history.csv), ``summary`` (summary.json
    as a dict: steps, cuts, iterations, timings, …) and ``out`` (the output folder, or None
    when the run wrote into a temporary folder that is gone); with VTK output, ``frames``
    (the frames of blocks.pvd) and ``frame(k)``. ``Result.load(dir)`` reads a run folder
    written by ``nmm run`` or :func:`run`."""

    def __init__(self, history, summary: dict, out: Optional[Path]):
        self.history = history
        self.summary = summary
        self.out = out
        self._frames = None

    @classmethod
    def load(cls, out: Union[str, os.PathLike]) -> "Result":
        """The result of the run in the folder ``out`` (its history.csv and summary.json)."""
        import json

        out = Path(out)
        if not (out / "history.csv").is_file():
            raise FileNotFoundError(f"{out}: no history.csv (not a run folder)")
        summary_file = out / "summary.json"
        summary = json.loads(summary_file.read_text()) if summary_file.is_file() else {}
        return cls(read_history(out / "history.csv"), summary, out)

    @property
    def frames(self) -> "Frames":
        """The frames of the run's blocks.pvd (:class:`Frames`: ``len``, indexing,
        iteration, ``times``, ``steps``); ValueError when the run wrote no VTK output
        (``vtk=False``, ``--no-vtk``) or its folder is gone."""
        if self._frames is None:
            if self.out is None:
                raise ValueError(
                    "this run's folder is gone (run without out=): run it with out=DIR to keep its frames"
                )
            self._frames = Frames(self.out)
        return self._frames

    def frame(self, k: int = -1) -> "Frame":
        """Frame ``k`` of blocks.pvd (from 0, negative from the end; default the last): the
        deformed blocks, their fields and the contacts of that step (:class:`Frame`)."""
        return self.frames[k]

    def __repr__(self) -> str:
        return (
            f"nmm.Result(status={self.summary.get('status')!r}, steps={self.summary.get('steps')}, "
            f"rows={len(self.history)}, out={str(self.out) if self.out else None!r})"
        )


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`run`: the run stopped cleanly after its current step, as the
    command line's does, and kept its outputs; ``result`` holds what it did."""

    def __init__(self, result: Result):
        super().__init__(f"interrupted at step {result.summary.get('steps')}")
        self.result = result


def read_history(path: Union[str, os.PathLike]):
    """history.csv as a DataFrame with exactly its columns (numbers read back exactly)."""
    import pandas as pd

    # pandas ≥ 3 reads floats exactly by default (and deprecates the option)
    exact = {"float_precision": "round_trip"} if int(pd.__version__.split(".")[0]) < 3 else {}
    return pd.read_csv(path, **exact)


def as_model(model: Any, base_dir: Union[str, os.PathLike, None] = None) -> Model:
    """An :class:`Model` from a Model, a path to a model file, or TOML text."""
    if isinstance(model, Model):
        return model
    if isinstance(model, os.PathLike):
        return Model.load(os.fspath(model))
    if isinstance(model, str):
        if "\n" not in model and (model.strip().endswith(".toml") or os.path.isfile(model)):
            return Model.load(model)
        return Model.from_toml(model, os.fspath(base_dir) if base_dir is not None else ".")
    raise TypeError(f"expected an nmm.Model, a path or TOML text, got {type(model).__name__}")


def check(model: Any) -> dict:
    """What ``nmm check --json`` prints for the model, as a dict (``blocks``, ``cracks``,
    ``physical_covers``, ``manifold_elements``, ``unknowns``, ``block_area_total``,
    ``smallest_block_area``, …; the same keys, from the same library function).
    ``model``: an :class:`Model`, a path or TOML text."""
    return _nmm.check(as_model(model))


class _TextProgress:
    """A one-line progress report on sys.stderr: step, simulated time, wall time."""

    def __init__(self):
        import time

        self._time = time
        self._start = time.monotonic()
        self._last = -1.0

    def __call__(self, step: int, total: int, t: float) -> None:
        now = self._time.monotonic()
        if step < total and now - self._last < 0.2:
            return
        self._last = now
        end = "\n" if step >= total else ""
        sys.stderr.write(
            f"\rstep {step}/{total}  t = {t:.4g} s  [{now - self._start:.1f} s]{end}"
        )
        sys.stderr.flush()


def run(
    model: Any,
    out: Union[str, os.PathLike, None] = None,
    progress: Union[bool, Callable[[int, int, float], None]] = False,
    threads: Optional[int] = None,
    vtk: Optional[bool] = None,
    checkpoint_every: int = 0,
    start_from: Union[str, os.PathLike, None] = None,
) -> Result:
    """Run a model as ``nmm run MODEL --out OUT`` does and return its :class:`Result`.

    ``model``: an :class:`Model`, a model file's path or TOML text. ``out``: the output
    folder (created if missing); None runs into a temporary folder that is removed after
    history.csv and summary.json are read (``Result.out`` is then None). ``vtk``: write the
    VTK frames (default: True with ``out``, as ``nmm run``; False without). ``progress``:
    True for a one-line report on stderr, or a callable ``f(step, total_steps, time)``
    called about every 0.1 s from the calling thread. ``threads``: the threads the run
    computes on (None: ``NMM_THREADS``, else the cores the process may use), as
    ``nmm run --threads``; the results are the same, bit for bit, whatever the count.
    ``checkpoint_every``: also write a checkpoint every N steps (``--checkpoint-every``;
    checkpoints are written at the end of each stage and on Ctrl-C anyway), so that
    :func:`resume` can continue the run. ``start_from``: a checkpoint file of another run
    (``OUT/checkpoints/step_NNNNNNNN.ckpt``) to start from, as ``nmm run --from``: the model
    may change what a branch may change (loads, analysis keys, stages after the checkpoint);
    a model that differs in what defines the saved state raises ``ValueError``.

    The GIL is released while the run computes. Ctrl-C stops the run cleanly after its
    current step, outputs kept, and raises :class:`Interrupted` (a KeyboardInterrupt) with
    the partial result. A model that cannot be discretised raises :class:`ModelError`; a run
    that stops on an error raises :class:`RunError` (outputs so far kept; its ``history``,
    ``summary`` and ``out`` attributes hold them).
    """
    model = as_model(model)
    if threads is not None and (not isinstance(threads, int) or threads < 1):
        raise ValueError(f"threads: expected None or an integer ≥ 1, got {threads!r}")
    if not isinstance(checkpoint_every, int) or checkpoint_every < 0:
        raise ValueError(
            f"checkpoint_every: expected an integer ≥ 0, got {checkpoint_every!r}"
        )
    callback = _progress_callback(progress)
    tmp = None
    if out is None:
        tmp = tempfile.mkdtemp(prefix="nmm-run-")
        dest = Path(tmp)
        vtk = bool(vtk)
    else:
        dest = Path(out)
        vtk = True if vtk is None else bool(vtk)
    try:
        try:
            summary, interrupted = _nmm.run_into(
                model,
                os.fspath(dest),
                vtk,
                callback,
                threads,
                checkpoint_every,
                None if start_from is None else os.fspath(start_from),
            )
        except RunError as e:
            _attach_outputs(e, dest, None if tmp else dest)
            raise
        result = Result(read_history(dest / "history.csv"), summary, None if tmp else dest)
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    if interrupted:
        raise Interrupted(result)
    return result


def resume(
    out: Union[str, os.PathLike],
    progress: Union[bool, Callable[[int, int, float], None]] = False,
    threads: Optional[int] = None,
) -> Result:
    """Continue the run in ``out`` from its latest checkpoint, as ``nmm resume OUT`` does,
    and return its :class:`Result` (the whole history, the rows before the checkpoint
    included). The model is read again from the file the run was made from, which must not
    have changed (a run of a model made in Python has no such file: run it from a file to
    resume it). The resumed outputs are those of an uninterrupted run, byte for byte, for a
    given thread count. ``progress`` and ``threads`` as in :func:`run`. A folder without a
    checkpoint raises ``ValueError``.
    """
    if threads is not None and (not isinstance(threads, int) or threads < 1):
        raise ValueError(f"threads: expected None or an integer ≥ 1, got {threads!r}")
    callback = _progress_callback(progress)
    dest = Path(out)
    try:
        summary, interrupted = _nmm.resume_into(os.fspath(dest), callback, threads)
    except RunError as e:
        _attach_outputs(e, dest, dest)
        raise
    result = Result(read_history(dest / "history.csv"), summary, dest)
    if interrupted:
        raise Interrupted(result)
    return result


def _progress_callback(progress: Any) -> Optional[Callable[[int, int, float], None]]:
    callback = _TextProgress() if progress is True else (progress or None)
    if callback is not None and not callable(callback):
        raise TypeError("progress: expected a bool or a callable(step, total_steps, time)")
    return callback


def _attach_outputs(e: Exception, dest: Path, out: Optional[Path]) -> None:
    import json

    e.out = out
    try:
        e.history = read_history(dest / "history.csv")
    except Exception:
        e.history = None
    try:
        e.summary = json.loads((dest / "summary.json").read_text())
    except Exception:
        e.summary = None


from . import study  # noqa: E402  (study imports nothing heavy until it runs)
