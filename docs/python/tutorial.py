# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # brittle_dem tutorial: outlines → templates → specimen → a short cut → forces → picture
#
# A plain script in jupytext's percent format: run it with `python docs/python/tutorial.py`
# (scripts/python-check.sh does, in CI) or open it as a notebook with jupytext. It writes into
# the folder `$TUTORIAL_OUT` (default: a new temporary folder). Units are SI: m, kg, s, N.
# About 5 s on one core.

# %%
import math
import os
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import brittle_dem as bd

ROOT = Path(__file__).resolve().parents[2] if "__file__" in globals() else Path.cwd()
OUT = Path(os.environ.get("TUTORIAL_OUT") or tempfile.mkdtemp(prefix="brittle-dem-tutorial-"))
OUT.mkdir(parents=True, exist_ok=True)
print("brittle_dem", bd.__version__, "writing into", OUT)

# %% [markdown]
# ## 1. An outline as a numpy array → a clump template
#
# A grain outline: an irregular polygon of 60 points (m). The improved method (Ye & Xu 2010)
# fills it with at most 9 discs whose masses give the grain's exact mass, centroid and
# inertia.

# %%
t = np.linspace(0.0, 2 * math.pi, 60, endpoint=False)
radius = 0.5e-3 * (1.0 + 0.15 * np.cos(3 * t) + 0.05 * np.sin(5 * t))
outline = np.column_stack([1.3 * radius * np.cos(t), radius * np.sin(t)])
template = bd.template_from_points(outline, name="grain-01", max_discs=9, density=3200.0)
print(template)
print("mass", template.mass, "kg; inertia about the centroid", template.inertia, "kg m^2")
print("discs (x, y, r in m; m in kg):\n", template.discs)
template.save(OUT / "grain-01.json")
bd.render(OUT / "grain-01.json", OUT / "grain-01.png", width=400)

# %% [markdown]
# ## 2. A specimen
#
# A 6 × 3 mm traditional specimen (one disc per grain) with the Si3N4 model's density and
# micro-parameters (`dem test cutting --specimen-from-model`).

# %%
model = bd.load_model(ROOT / "data" / "models" / "si3n4.model.json")
params = bd.SpecimenParams.from_model(model, "6mm", "3mm", "0.175mm", "0.285mm", seed=1)
model = model.with_r_mean(0.5 * (params.r_min + params.r_max))
print(params)

# %% [markdown]
# ## 3. A short cut
#
# Depth of cut 0.5 mm, 1.5 mm of travel at 2 m/s. The specimen is generated into the cut's
# folder; the callback prints the progress now and then (returning False would stop the run).

# %%
def progress(done, total):
    print(f"  {done:>7} of {total} steps")


cut = bd.cut(OUT / "cut", bd.cutting_test(depth=0.5e-3, length=1.5e-3, speed=2.0),
             specimen=params, model=model, threads=1, callback=progress, every=20000)
print(cut.report())

# %% [markdown]
# ## 4. The force history

# %%
f = cut.forces
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(f["travel_m"] * 1e3, f["main_N"], label="main (cutting) force")
ax.plot(f["travel_m"] * 1e3, f["vertical_N"], label="vertical (thrust) force")
w0, w1 = cut.window
ax.axvspan(w0 * 1e3, w1 * 1e3, color="0.9", label="steady window")
ax.set_xlabel("tool travel (mm)")
ax.set_ylabel("force (N, for t = 1 m)")
ax.legend()
fig.tight_layout()
fig.savefig(OUT / "forces.png", dpi=100)
print("mean main force in the window", cut.main_force_mean, "N")

# %% [markdown]
# ## 5. A picture of the end of the cut

# %%
# The specimen and the tool (chips fly far): view [xmin, xmax, ymin, ymax] in m.
info = bd.render(cut.out_dir / "ckpt-final.json", OUT / "cut.png", width=800, bonds=True,
                 broken=True, view=[-0.5e-3, 6.5e-3, -0.5e-3, 4.5e-3])
print("wrote", info["out"], info["width"], "x", info["height"], "px")
