"""A model's blocks as cut, and a run's frames read back from its VTK output.

The files are read by the library's own reader (``nmm::picture::read_frame``, the one
``nmm plot RUN_DIR`` draws from, through :mod:`nmm._nmm`); this module only turns the
arrays it returns into numpy arrays and pandas DataFrames.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterator, List, Optional, Union

from . import _nmm

#: The fields a frame's elements are coloured by in ``nmm plot`` and :func:`nmm.plot`.
FIELDS = ("u", "ux", "uy", "sxx", "syy", "sxy")


def _f64(b: bytes, columns: int = 2):
    import numpy as np

    a = np.frombuffer(b, dtype=np.float64).copy()
    return a.reshape(-1, columns) if columns > 1 else a


def blocks_table(rows: list, joints: list):
    """The DataFrame of :meth:`nmm.Model.blocks` from the rows the compiled core makes."""
    import numpy as np
    import pandas as pd

    df = pd.DataFrame(
        {
            "name": [r["name"] for r in rows],
            "material": [r["material"] for r in rows],
            "fixed": np.array([r["fixed"] for r in rows], dtype=bool),
            "area": np.array([r["area"] for r in rows], dtype=np.float64),
            "parent": [r["parent"] for r in rows],
            "polygon": [_f64(r["polygon"]) for r in rows],
            "joints": [np.array(r["joints"], dtype=np.int64) for r in rows],
        }
    )
    df.index.name = "id"
    df.attrs["joints"] = list(joints)
    return df


class Frame:
    """One frame of a run (``Result.frame(k)``): the deformed blocks and their fields at
    one output step, as the run's VTK output holds them, and the contacts of that step.

    * ``index`` (in ``blocks.pvd``, from 0), ``step``, ``time`` (s), ``file`` (the .vtu);
    * ``elements``: DataFrame, one row per manifold element (a VTK cell): ``block`` (id),
      ``name`` (the block's name), ``ux``, ``uy`` (m, the mean of the element's vertex
      displacements), ``u`` (m, the mean of their magnitudes), ``sxx``, ``syy``, ``sxy``,
      ``szz`` (Pa, the element's stress; tension positive);
    * ``polygons``: the elements' deformed polygons, a list of (n, 2) arrays (m);
    * ``points``, ``displacement``, ``velocity``: (n, 2) arrays over the elements' vertices
      (each element has its own copies; ``cells`` lists each element's vertex indices);
    * ``blocks``: DataFrame, one row per block id: ``name``, ``polygon`` (its deformed
      outline, counter-clockwise, an (n, 2) array), ``outlines`` (all its outlines, the
      largest first: more than one only where its elements touch at a point);
    * ``contacts``: DataFrame, one row per contact of the step (empty when there is none):
      ``x``, ``y`` (the vertex where it was detected), ``state`` (0 open, 1 stick, 2 slide),
      ``normal_force``, ``shear_force`` (N/m), ``nx``, ``ny`` (the normal), ``fx``, ``fy``
      (force on the vertex block), ``vertex_block``, ``edge_block``, ``joint`` (-1 for a
      face of a block as drawn);
    * ``field(name)``: per element, the value ``nmm plot --field name`` colours it by.

    Units SI; displacements relative to the base, totals since t = 0 (docs/outputs.md).
    """

    def __init__(self, out: Path, raw: dict):
        import numpy as np
        import pandas as pd

        self.out = out
        self.index: int = raw["index"]
        self.time: float = raw["time"]
        self.step: Optional[int] = raw["step"]
        self.file: Path = out / raw["file"]
        g = raw["blocks"]
        self.points = _f64(g["points"])
        sizes = np.asarray(g["cell_sizes"], dtype=np.int64)
        conn = np.asarray(g["connectivity"], dtype=np.int64)
        self.cells: List = np.split(conn, np.cumsum(sizes)[:-1]) if len(sizes) else []
        self.polygons: List = [self.points[c] for c in self.cells]
        pdata = {k: _f64(b, c) for k, (c, b) in g["point_data"].items()}
        cdata = {k: _f64(b, c) for k, (c, b) in g["cell_data"].items()}
        self.displacement = pdata["displacement"][:, :2]
        self.velocity = pdata["velocity"][:, :2] if "velocity" in pdata else None
        self.block_names: List[str] = list(g["field_strings"].get("block_names", []))
        n = len(self.cells)
        block = cdata["block"].astype(np.int64) if "block" in cdata else np.zeros(n, np.int64)
        names = np.array(self.block_names + [""], dtype=object)
        self._fields = {k: _f64(v, 1) for k, v in raw["fields"].items()}
        stress = cdata.get("stress", np.full((n, 4), np.nan))
        self.elements = pd.DataFrame(
            {
                "block": block,
                "name": names[np.where((block >= 0) & (block < len(self.block_names)), block, -1)],
                "ux": self._fields["ux"],
                "uy": self._fields["uy"],
                "u": self._fields["u"],
                "sxx": stress[:, 0],
                "syy": stress[:, 1],
                "sxy": stress[:, 2],
                "szz": stress[:, 3],
            }
        )
        outlines = [[_f64(r) for r in loops] for loops in raw["outlines"]]
        nblocks = max(len(self.block_names), len(outlines))
        outlines += [[] for _ in range(nblocks - len(outlines))]
        self.blocks = pd.DataFrame(
            {
                "name": [self.block_names[i] if i < len(self.block_names) else str(i)
                         for i in range(nblocks)],
                "polygon": [o[0] if o else np.zeros((0, 2)) for o in outlines],
                "outlines": outlines,
            }
        )
        self.blocks.index.name = "id"
        self.contacts = _contacts(raw["contacts"])

    def field(self, name: str):
        """The value of ``name`` (``u``, ``ux``, ``uy``, ``sxx``, ``syy``, ``sxy``) per
        element, as ``nmm plot --field`` colours it (m or Pa)."""
        key = "sxy" if name == "txy" else name
        if key not in self._fields:
            raise ValueError(f"field: unknown field {name!r} (expected one of {', '.join(FIELDS)})")
        return self._fields[key]

    def __repr__(self) -> str:
        return (
            f"nmm.Frame(index={self.index}, step={self.step}, time={self.time}, "
            f"elements={len(self.elements)}, contacts={len(self.contacts)})"
        )


def _contacts(g: Optional[dict]):
    import numpy as np
    import pandas as pd

    cols = ["x", "y", "state", "normal_force", "shear_force", "nx", "ny", "fx", "fy",
            "vertex_block", "edge_block", "joint"]
    if g is None:
        return pd.DataFrame({c: pd.Series(dtype=np.int64 if c in ("state", "vertex_block", "edge_block", "joint") else np.float64) for c in cols})
    pts = _f64(g["points"])
    conn = np.asarray(g["connectivity"], dtype=np.int64)
    first = np.cumsum(np.r_[0, np.asarray(g["cell_sizes"], dtype=np.int64)])[:-1]
    at = pts[conn[first]] if len(first) else np.zeros((0, 2))
    n = len(first)
    cd = {k: _f64(b, c) for k, (c, b) in g["cell_data"].items()}

    def col(name, k=None, dtype=np.float64):
        if name not in cd:
            return np.full(n, -1 if dtype is np.int64 else np.nan, dtype=dtype)
        a = cd[name]
        return (a[:, k] if k is not None else a).astype(dtype)

    return pd.DataFrame(
        {
            "x": at[:, 0],
            "y": at[:, 1],
            "state": col("state", dtype=np.int64),
            "normal_force": col("normal_force"),
            "shear_force": col("shear_force"),
            "nx": col("normal", 0),
            "ny": col("normal", 1),
            "fx": col("force_on_vertex_block", 0),
            "fy": col("force_on_vertex_block", 1),
            "vertex_block": col("blocks", 0, np.int64),
            "edge_block": col("blocks", 1, np.int64),
            "joint": col("joint", dtype=np.int64),
        }
    )


class Frames:
    """The frames of a run's ``blocks.pvd``, in order: ``len()``, indexing (negative from
    the end; a slice gives a list), iteration (each frame read when it is reached),
    ``times`` (s), ``steps`` and ``files``."""

    def __init__(self, out: Union[str, os.PathLike]):
        self.out = Path(out)
        listed = _nmm.run_frames(os.fspath(self.out))
        self.times: List[float] = [t for t, _, _ in listed]
        self.files: List[Path] = [self.out / f for _, f, _ in listed]
        self.steps: List[Optional[int]] = [s for _, _, s in listed]

    def __len__(self) -> int:
        return len(self.times)

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        if not isinstance(k, int) and hasattr(k, "__index__"):
            k = k.__index__()
        if not isinstance(k, int):
            raise TypeError(f"frame index: expected an int, got {type(k).__name__}")
        n = len(self)
        if not -n <= k < n:
            raise IndexError(f"{self.out}: no frame {k} (blocks.pvd has frames 0 … {n - 1})")
        k %= n
        return Frame(self.out, _nmm.read_frame(os.fspath(self.out), k))

    def __iter__(self) -> Iterator[Frame]:
        for k in range(len(self)):
            yield self[k]

    def nearest(self, time: float) -> Frame:
        """The frame nearest to ``time`` (s), as ``nmm plot --time``."""
        k = min(range(len(self)), key=lambda i: abs(self.times[i] - time))
        return self[k]

    def __repr__(self) -> str:
        return f"nmm.Frames({str(self.out)!r}, frames={len(self)})"
