# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Choosing a suppressor
#
# Which impact suppressor should your object get, and is it better than a plain tuned-mass damper
# (TMD) of the same mass? Change the numbers in the next cell and run all cells (under 30 s on
# two cores): you get both devices optimised for your object and band by a small global search
# (the library call behind `python -m impactdamper design`, on the `budget` below: 16 global
# samples, one local search of 3 compass polls, one round of the 2 % check), for the peak, the
# band average, the travel limit and the TMD's worst case with the object's natural frequency
# off by +-`detuning`; their strokes and loads; then the frequency response of your own
# suppressor beside them. The full answer (the command's budget, 128 samples, and with
# `--robust` the impact suppressor's worst cases with the force amplitude between `force` times
# the design force and the restitution drifting by +-`restitution`) is one command away: the
# next cells print it. A design table the workflow saved for this same object is shown instead.
#
# The model is that of Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
# [10.18698/0236-3941-2019-1-90-100](https://doi.org/10.18698/0236-3941-2019-1-90-100). All
# parameters are the paper's relative ones; lengths are in units of $x_{st} = P_0/c_1$.

# %% tags=["parameters"]
import os

from impactdamper.studies.design import optimum

# ---- your object and suppressor: change these, then run all cells -----------------------
mu = 0.08  # suppressor's mass over the object's, m2/m1 (0.01 to 0.25)
delta1 = 0.05  # object's relative damping, k1/(2 m1 omega1) (0.005 to 0.2)
band = (0.5, 1.5)  # forcing frequencies the object meets, theta = omega/omega1
detuning = 0.1  # the object's natural frequency may be off by +- this fraction
force = (0.5, 2.0)  # the force amplitude may be this many times the design force
restitution = 0.15  # the stop's coefficient of restitution may drift by +- this
# your own impact suppressor, for the frequency response:
N = 0.5  # suppressor's partial frequency over the object's, omega2/omega1
delta2 = 0.05  # suppressor's relative damping, k2/(2 m2 omega1)
R = 0.7  # coefficient of restitution: 0 plastic ... 1 elastic
gap = 2.0  # initial gap Delta0/x_st
# a design table saved for this same object, band and uncertainty, shown instead of searching
# again (the workflow names its own, figures/design_optimum.json); None: always search
saved = os.environ.get("IMPACTDAMPER_DESIGN_RECORD")
# the tour's search: small, stated (the design command's own budget is optimum.BUDGET)
budget = optimum.Budget(samples=16, starts=1, polls=3, polish=0, checks=1)

# %%
import matplotlib.pyplot as plt
import numpy as np

import impactdamper as idp
from impactdamper.analysis import response
from impactdamper.reporting import plotting
from impactdamper.studies.design import design
from impactdamper.studies import vocabulary

plt.style.use(plotting.STYLE_FILE)

# %% [markdown]
# ## Both devices optimised
#
# Every device is judged on its *worst branch*: the largest $\max|x_1|/x_{st}$ over every motion a
# slow sweep of the forcing frequency can follow in either direction (jumps located, the motion
# without contact up to where it first touches the stop, attractors from random starts), located
# to $10^{-6}$ in $\theta$. The table holds each criterion's optimum of each device and every
# row's worst cases; `impact` and `tmd` are the pair optimal for the peak.

# %%
uncertainty = optimum.Uncertainty(detuning, force, restitution)
result, source = optimum.saved_or_searched(
    saved, band, mu, delta1, uncertainty=uncertainty, progress=print, budget=budget
)
print(f"the design table: {source}, budget {result['budget']}")
print(
    f"the full answer: python -m impactdamper design --mu {mu} --delta1 {delta1} --theta-start {band[0]} "
    f"--theta-stop {band[1]} --detuning {detuning} --force-low {force[0]} --force-high {force[1]} "
    f"--restitution-drift {restitution} --robust"
)
print(f"{'device':26s} {'peak':>7s} {'avg':>6s} {'detuned':>8s} {'force':>7s} {'R drift':>8s} {'stroke':>7s}")
for d in result["devices"]:
    w = d["worst"]
    note = " (never reaches its stop: the TMD limit)" if d.get("tmd_limit") else ""
    print(
        f"{d['device']:26s} {d['peak']:7.3f} {d['band_average']:6.3f} {w['detuning']:8.3f} {w['force']:7.3f} "
        f"{w['restitution']:8.3f} {d['stroke']:7.2f}{note}"
    )
imp = result["impact"]
print(
    f"impact loads: largest pulse {imp['pulse']:.3f} P0/omega1, {imp['impacts_per_period']:.2f} impacts per period "
    f"({imp['impacts_per_hour']:.0f} per hour at f1 = {result['natural_frequency']:g} Hz), peak contact force "
    f"{imp['contact_force']:.0f} P0 on a stop {result['stop_stiffness']:g} times stiffer than c1"
)
print(result["recommendation"])

# %% [markdown]
# ## Your suppressor beside them

# %%
p = idp.Parameters(mu=mu, N=N, delta1=delta1, delta2=delta2, R=R, gap=gap)
mine = response.frequency_response(p, *band, 41)  # (the located peak: on the grid of steps <= 0.02, to 1e-6 in theta)
best = response.frequency_response(p.replace(**imp["parameters"]), *band, 41)
tmd = design.LinearDevice(mu, result["tmd"]["parameters"]["N"], delta1, result["tmd"]["parameters"]["delta2"])
th = np.linspace(*band, 801)
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(th, design.LinearDevice(0.0, 1.0, delta1, 0.0).amplitude(th), ":", color="0.3", label="object alone")
ax.plot(th, tmd.amplitude(th), color="C3", label="optimal TMD")
for r, color, text in ((mine, "C0", "your suppressor"), (best, "C2", "optimal impact suppressor")):
    ax.plot(r.thetas, [q.up.max_abs_x1 for q in r.points], "-", color=color, lw=1.0, label=f"{text}, upward")
    ax.plot(r.thetas, [q.down.max_abs_x1 for q in r.points], "--", color=color, lw=0.9, label=f"{text}, downward")
    ax.plot([r.peak_where()[0]], [r.peak()], "o", color=color, ms=4)
ax.set_xlabel(vocabulary.SPEC["theta"].label)  # (the parameter table's axis label)
ax.set_ylabel(r"$\max|x_1|/x_{st}$")
ax.legend(fontsize=7)
plt.show()
theta, branch = mine.peak_where()
print(
    f"your suppressor: worst branch {mine.peak():.4f} at theta {theta:.5f} ({branch}; the grid's largest sample "
    f"{mine.grid_peak():.4f}), band average {mine.band_average():.3f}"
)

# %% [markdown]
# ## When the object's frequency is off
#
# The optimal impact suppressor's and TMD's worst branches with the object's natural frequency
# detuned (its stiffness changed; the suppressor as built), over the nominal $x_{st}$ (the
# impact suppressor robust to detuning only in a table searched with `--robust`).

# %%
rows = {d["device"]: d for d in result["devices"]}
fig, ax = plt.subplots(figsize=(7, 3), layout="constrained")
for key, color, text in (
    ("impact_peak_reach", "C2", "optimal impact suppressor"),
    ("impact_detuning", "C0", "impact, robust to detuning"),
):
    if key not in rows:
        continue
    pts = sorted(
        (s["detuning"], s["peak"]) for s in rows[key]["worst_scenarios"] if s["force"] == 1 and s["restitution"] == 0
    )
    ax.plot([100 * e for e, _ in pts], [v for _, v in pts], "o-", color=color, label=text)
es = np.linspace(-detuning, detuning, 21)
for key, color, text in (("tmd_peak", "C3", "optimal TMD"), ("tmd_detuning", "C1", "TMD, robust to detuning")):
    t = rows[key]["parameters"]
    peaks = [
        design.LinearDevice(mu, t["N"] / (1 + e), delta1 / (1 + e), t["delta2"] / (1 + e)).peak(
            (band[0] / (1 + e), band[1] / (1 + e))
        )[1]
        / (1 + e) ** 2
        for e in es
    ]
    ax.plot(100 * es, peaks, "--", color=color, label=text)
ax.set_xlabel("object's natural frequency off by (%)")
ax.set_ylabel(r"peak $\max|x_1|/x_{st}$ over the band")
ax.legend(fontsize=8)
plt.show()
