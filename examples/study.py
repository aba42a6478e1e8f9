# %% [markdown]
# # A parameter study with nmm and Dask
#
# The block on an incline (`examples/incline.toml`, θ = 30°) under a range of joint friction
# angles φ, run as one study on a Dask cluster (a LocalCluster on this machine here), then
# post-processed with pandas and matplotlib: the slip down the plane after 1 s against the
# closed form ½ g (sin θ − cos θ tan φ) t², and the slip histories.
#
#     pip install ./python matplotlib      # the package (needs the Rust toolchain)
#     python examples/study.py             # or open it as a notebook (jupytext / VS Code cells)
#
# Outputs: `out/incline_study/NAME/history.csv` per run, `out/incline_study/study.csv` (the
# table) and `out/incline_study/study.png`. Running it again skips the runs already done.

# %%
import math
import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # a PNG file, no display needed
import matplotlib.pyplot as plt

import nmm
import nmm.study

HERE = Path(__file__).resolve().parent
OUT = Path(os.environ.get("NMM_STUDY_OUT", HERE.parent / "out" / "incline_study"))
THETA = 30.0

# %% [markdown]
# The base model, and one run per friction angle: a table of overrides (key path → value)
# applied to the base model, each validated as the model file is.

# %%
base = nmm.Model.load(str(HERE / "incline.toml"))
phis = [10.0, 15.0, 20.0, 25.0, 28.0, 32.0, 35.0]
table = {f"phi{phi:g}": {"interface.0.friction_angle": phi} for phi in phis}

# %% [markdown]
# Run the study. `client=None` starts a LocalCluster of single-threaded worker processes;
# pass `client=dask.distributed.Client(...)` to use any cluster (see docs/studies.md).

# %%
df = nmm.study.run(table, base=base, out=OUT, n_workers=2)
print(df[["status", "steps", "iterations", "wall_time", "c.ux.final", "c.uy.final"]])

# %% [markdown]
# Slip down the plane from the centre's displacement, against the closed form.

# %%
s, c = math.sin(math.radians(THETA)), math.cos(math.radians(THETA))
ok = df[df["status"].isin(["ok", "skipped"])].copy()
ok["phi"] = [table[n]["interface.0.friction_angle"] for n in ok.index]
ok["slip"] = ok["c.ux.final"] * c - ok["c.uy.final"] * s
t_end = ok["time"].iloc[0]
ok["closed_form"] = [
    max(0.5 * 9.81 * (s - c * math.tan(math.radians(p))) * t_end**2, 0.0) for p in ok["phi"]
]
print(ok[["phi", "slip", "closed_form"]].to_string())

# %%
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
fine = [x / 4 for x in range(0, 161)]
ax1.plot(
    fine,
    [max(0.5 * 9.81 * (s - c * math.tan(math.radians(p))) * t_end**2, 0.0) for p in fine],
    "k-", lw=1, label="closed form",
)
ax1.plot(ok["phi"], ok["slip"], "o", color="tab:red", label="nmm")
ax1.set(xlabel="friction angle φ (°)", ylabel=f"slip after {t_end:g} s (m)",
        title=f"Block on a {THETA:g}° incline")
ax1.legend()
for name in ok.index:
    h = nmm.read_history(OUT / name / "history.csv")
    ax2.plot(h["time"], h["c.ux"] * c - h["c.uy"] * s, label=f"φ = {ok.loc[name, 'phi']:g}°")
ax2.set(xlabel="time (s)", ylabel="slip (m)", title="Slip histories")
ax2.legend(fontsize=8)
fig.tight_layout()
png = OUT / "study.png"
fig.savefig(png, dpi=120)
print(f"plot: {png}")
