"""Parameter studies on dask.distributed: many runs of nmm, one row of figures each.

    import nmm, nmm.study
    base = nmm.Model.load("incline.toml")
    table = {f"phi{p}": {"interface.0.friction_angle": p} for p in (10, 15, 20, 25)}
    df = nmm.study.run(table, base=base, out="study")      # a LocalCluster on this machine
    df = nmm.study.run(table, base=base, out="study", client=Client("tcp://host:8786"))

Each run writes ``OUT/NAME/`` (history.csv, summary.json, blocks.csv; VTK frames with
``vtk=True``) with the same library call as ``nmm run``, so its history.csv is the one
``nmm run MODEL --out OUT/NAME`` writes, byte for byte. ``OUT/NAME/study.json`` is written
last, with the content hash of the run's model (its canonical TOML, the bytes of the files
it reads, the nmm version and the outputs asked for): a later study with the same name and
hash and complete outputs skips that run (status "skipped", its figures read back from its
outputs). A model that fails validation, or a run that fails, records its one-line error in
its row and does not stop the others. ``OUT/study.csv`` keeps the table.

Folders and model files must be reachable at the same paths from every worker (on a
cluster: a shared file system); see docs/studies.md.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import time
from pathlib import Path
from typing import Any, Dict, Mapping, Optional, Union

__all__ = ["run", "model_hash", "row_from_outputs"]

#: columns every study table has, before the monitor figures
BASE_COLUMNS = [
    "status",
    "error",
    "out",
    "steps",
    "time",
    "unknowns",
    "iterations",
    "iterations_max",
    "cuts",
    "steps_cut",
    "wall_time",
    "hash",
]


def model_hash(model, vtk: bool = False) -> str:
    """The content hash of a run: the model's canonical TOML (comments and layout do not
    count), the bytes of the files it reads (its motion record), the nmm version and whether
    VTK frames are written."""
    import nmm

    files = {}
    for f in model.files():
        try:
            files[os.path.basename(f)] = hashlib.sha256(Path(f).read_bytes()).hexdigest()
        except OSError:
            files[os.path.basename(f)] = None
    blob = json.dumps(
        {"nmm": nmm.__version__, "model": model.canonical(), "files": files, "vtk": bool(vtk)},
        sort_keys=True,
    )
    return hashlib.sha256(blob.encode()).hexdigest()


def _check_name(name: Any) -> str:
    if not isinstance(name, str) or not name:
        raise ValueError(f"a run's name must be a non-empty string, got {name!r}")
    if name in (".", "..") or "/" in name or "\\" in name or name.startswith("."):
        raise ValueError(f"a run's name is a folder name (no '/', not starting with '.'), got {name!r}")
    return name


def _monitor_figures(history, columns) -> Dict[str, float]:
    row: Dict[str, float] = {}
    for c in columns:
        if c not in history.columns:
            continue
        s = history[c]
        row[f"{c}.min"] = float(s.min()) if len(s) else math.nan
        row[f"{c}.max"] = float(s.max()) if len(s) else math.nan
        row[f"{c}.final"] = float(s.iloc[-1]) if len(s) else math.nan
    return row


def row_from_outputs(folder: Union[str, os.PathLike], status: str = "ok") -> Dict[str, Any]:
    """A study row from a run's folder (summary.json and history.csv)."""
    import nmm

    folder = Path(folder)
    summary = json.loads((folder / "summary.json").read_text())
    history = nmm.read_history(folder / "history.csv")
    cols = list(history.columns)
    monitors = cols[2 : cols.index("iterations")] if "iterations" in cols else cols[2:]
    row: Dict[str, Any] = {
        "status": status,
        "error": None,
        "out": str(folder),
        "steps": summary.get("steps"),
        "time": summary.get("time"),
        "unknowns": summary.get("unknowns"),
        "iterations": (summary.get("iterations") or {}).get("total"),
        "iterations_max": (summary.get("iterations") or {}).get("max"),
        "cuts": (summary.get("cuts") or {}).get("total"),
        "steps_cut": (summary.get("cuts") or {}).get("steps_cut"),
        "wall_time": (summary.get("timings") or {}).get("total"),
    }
    row.update(_monitor_figures(history, monitors))
    return row


def _complete(folder: Path, digest: str) -> bool:
    try:
        mark = json.loads((folder / "study.json").read_text())
        summary = json.loads((folder / "summary.json").read_text())
    except (OSError, ValueError):
        return False
    return (
        mark.get("hash") == digest
        and mark.get("status") == "ok"
        and summary.get("status") == "finished"
        and (folder / "history.csv").is_file()
    )


def _run_one(
    name: str,
    text: str,
    base_dir: str,
    source: str,
    folder: str,
    digest: str,
    vtk: bool,
    threads: Optional[int] = 1,
):
    """One run on a worker: returns its row (never raises for a model or run error)."""
    import nmm

    folder_p = Path(folder)
    mark = folder_p / "study.json"
    t0 = time.perf_counter()
    try:
        mark.unlink()
    except FileNotFoundError:
        pass
    try:
        model = nmm.Model.from_toml(text, base_dir, source)
        nmm.run(model, out=folder_p, vtk=vtk, threads=threads)
    except (nmm.ModelError, nmm.RunError) as e:
        return {"status": "error", "error": str(e), "out": folder, "hash": digest}
    except nmm.Interrupted as e:  # stopped (nmm._nmm.stop_all): a row, not a dead worker
        return {"status": "error", "error": f"{e} (outputs so far kept)", "out": folder, "hash": digest}
    except Exception as e:  # noqa: BLE001 - any failure is this run's, not the study's
        return {"status": "error", "error": f"{type(e).__name__}: {e}", "out": folder, "hash": digest}
    row = row_from_outputs(folder_p)
    row["hash"] = digest
    tmp = folder_p / "study.json.tmp"
    tmp.write_text(
        json.dumps({"name": name, "hash": digest, "status": "ok", "seconds": time.perf_counter() - t0}, indent=1)
        + "\n"
    )
    os.replace(tmp, mark)
    return row


def _resolve(value: Any, base, base_dir):
    """An nmm.Model from a study entry: a Model, TOML text, a path, or (with a base model)
    a dict of overrides {key_path: value}."""
    import nmm

    if isinstance(value, Mapping):
        if base is None:
            return nmm.Model.from_dict(dict(value), os.fspath(base_dir) if base_dir else ".")
        return base.with_overrides(dict(value))
    return nmm.as_model(value, base_dir)


def _entries(models, base):
    try:
        import pandas as pd

        if isinstance(models, pd.DataFrame):
            out = {}
            for name, r in models.iterrows():
                out[str(name)] = {k: _plain(v) for k, v in r.items() if not _missing(v)}
            return out
    except ImportError:  # pragma: no cover
        pass
    if not isinstance(models, Mapping):
        raise TypeError("models: expected a mapping name → model (or a DataFrame of overrides with base=)")
    return dict(models)


def _override_keys(entries) -> list:
    """The key paths of the override entries (dicts), in order of first appearance, except
    those that name a base column."""
    keys = []
    for value in entries.values():
        if isinstance(value, Mapping):
            for k in value:
                k = str(k)
                if k not in keys and k not in BASE_COLUMNS:
                    keys.append(k)
    return keys


def _override_value(value, key):
    """The value an entry gives `key` (None where it sets none, or is not an override
    dict); lists (e.g. `analysis.gravity`) stay lists."""
    if isinstance(value, Mapping):
        return value.get(key)
    return None


def _missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _plain(v):
    """A DataFrame cell as a Python value. pandas stores an integer column with empty cells
    as floats: integral floats are written as integers (which every number key accepts)."""
    v = v.item() if hasattr(v, "item") else v
    if isinstance(v, float) and v.is_integer():
        return int(v)
    return v


def run(
    models,
    client=None,
    out: Union[str, os.PathLike] = "study",
    base=None,
    base_dir: Union[str, os.PathLike, None] = None,
    vtk: bool = False,
    n_workers: Optional[int] = None,
    rerun: bool = False,
    processes: bool = False,
    progress: bool = False,
    threads: Optional[int] = 1,
):
    """Run a study and return its table (a DataFrame indexed by name, in the given order).

    ``models``: a mapping name → an :class:`nmm.Model`, TOML text, a model file's path, or
    (with ``base``) a dict of overrides ``{key_path: value}`` applied to the base model with
    :meth:`nmm.Model.with_overrides`; or a DataFrame indexed by name whose columns are key
    paths (with ``base``). ``client``: a ``dask.distributed.Client`` of any cluster, or
    what ``Client()`` accepts (a scheduler address ``"tcp://host:8786"``, a cluster object
    such as ``dask_jobqueue.SLURMCluster`` or a Kubernetes cluster); None starts a
    LocalCluster for this study and closes it after: ``n_workers`` runs at once (default:
    the CPU count), as threads of one worker in this process (runs release the GIL), or
    with ``processes=True`` as single-threaded worker processes (isolated from each other;
    a script then needs the ``if __name__ == "__main__":`` guard that multiprocessing asks).
    ``out``: the study folder; run NAME writes ``out/NAME/``. ``vtk``: also write VTK
    frames. ``rerun``: run even what is complete and unchanged. ``progress``: one line on
    stderr per finished run (``[3/40] NAME ok 12.3 s``). ``threads``: the threads each run
    computes on (default 1: a study's parallelism is its runs at once; None: each run's
    default, ``NMM_THREADS`` or the cores of its worker); the results do not depend on it.

    Columns: status ("ok", "error" or "skipped"), error (the one-line message), out, steps,
    time, unknowns, iterations (total Newton iterations), iterations_max, cuts (Δt cuts),
    steps_cut, wall_time (s, from summary.json), hash, then the overridden values (one
    column per key path of the override dicts, e.g. ``interface.0.friction_angle``; empty
    in rows that do not set it), then ``COL.min``, ``COL.max`` and ``COL.final`` for each
    monitor column of history.csv.
    """
    import pandas as pd

    out_dir = Path(out).resolve()
    out_dir.mkdir(parents=True, exist_ok=True)
    entries = _entries(models, base)
    rows: Dict[str, Dict[str, Any]] = {}
    todo = []
    for name, value in entries.items():
        try:
            name = _check_name(name)
        except ValueError as e:
            rows[str(name)] = {"status": "error", "error": str(e)}
            continue
        folder = out_dir / name
        try:
            model = _resolve(value, base, base_dir)
        except Exception as e:  # noqa: BLE001 - ModelError, a missing file, a bad override
            msg = str(e) if not isinstance(e, KeyError) else str(e.args[0])
            rows[name] = {"status": "error", "error": msg, "out": str(folder)}
            continue
        digest = model_hash(model, vtk)
        if not rerun and _complete(folder, digest):
            try:
                row = row_from_outputs(folder, status="skipped")
                row["hash"] = digest
                rows[name] = row
                continue
            except Exception:  # noqa: BLE001 - unreadable outputs: run it again
                pass
        folder.mkdir(parents=True, exist_ok=True)
        base_abs = os.path.abspath(os.fspath(model.base_dir))
        todo.append(
            (name, model.to_toml(), base_abs, model.source, str(folder), digest, vtk, threads)
        )
        rows[name] = {"status": "pending"}

    if todo:
        own = None
        opened = None
        if client is not None and not hasattr(client, "submit"):
            # a scheduler address ("tcp://host:8786") or a cluster object (SLURMCluster, …)
            from distributed import Client

            client = opened = Client(client)
        if client is None:
            from distributed import Client, LocalCluster

            workers = n_workers or os.cpu_count() or 1
            n = min(workers, len(todo))
            if processes:
                own = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                   dashboard_address=":0")
            else:
                # one worker of n threads in this process: runs release the GIL, so they
                # compute in parallel; no process start (works in scripts without a
                # `__main__` guard and in notebooks)
                own = LocalCluster(n_workers=1, threads_per_worker=n, processes=False,
                                   dashboard_address=":0")
            client = Client(own)
        try:
            rows.update(_gather(client, todo, progress))
        except KeyboardInterrupt:
            # Ctrl-C: the runs of this process's own workers stop cleanly after their
            # current step (outputs kept; without study.json they run again next time)
            if own is not None and not processes:
                from . import _nmm

                _nmm.stop_all()
            raise
        finally:
            if own is not None:
                client.close()
                own.close()
            elif opened is not None:
                opened.close()

    table = pd.DataFrame.from_dict(
        {n: rows[n] for n in rows}, orient="index"
    )
    for c in BASE_COLUMNS:
        if c not in table.columns:
            table[c] = None
    # the overridden values, one column per key path, after the base columns
    keys = _override_keys(entries)
    for k in keys:
        table[k] = [_override_value(entries.get(n), k) for n in table.index]
    rest = [c for c in table.columns if c not in BASE_COLUMNS and c not in keys]
    table = table[BASE_COLUMNS + keys + rest]
    table.index.name = "name"
    table.to_csv(out_dir / "study.csv")
    return table


def _gather(client, todo, progress=False):
    import sys

    from distributed import as_completed

    futures = {}
    for args in todo:
        name, digest = args[0], args[5]
        f = client.submit(_run_one, *args, key=f"nmm-run-{name}-{digest[:16]}", pure=False)
        futures[f] = name
    rows = {}
    try:
        for f in as_completed(list(futures)):
            name = futures[f]
            try:
                rows[name] = f.result()
            except Exception as e:  # noqa: BLE001 - a worker that died, a lost task
                rows[name] = {"status": "error", "error": f"{type(e).__name__}: {e}"}
            if progress:
                r = rows[name]
                wall = r.get("wall_time")
                detail = f"{wall:.1f} s" if isinstance(wall, float) else (r.get("error") or "")
                sys.stderr.write(f"[{len(rows)}/{len(futures)}] {name} {r['status']} {detail}\n")
                sys.stderr.flush()
    except KeyboardInterrupt:
        # what has not started will not; what runs on a worker goes on to its end
        client.cancel([f for f in futures if not f.done()])
        raise
    return rows
