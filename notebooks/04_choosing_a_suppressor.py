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
# (TMD) of the same mass? Change the numbers in the next cell and run all cells (about a minute):
# you get both devices optimised for your object and band by the same optimiser and criterion
# (the library call behind `python -m impactdamper design`), their located peaks, band averages,
# worst cases with the object's natural frequency off by +-`detuning`, strokes and loads; then the
# frequency response of your own suppressor beside them.
#
# The model is that of Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
# [10.18698/0236-3941-2019-1-90-100](https://doi.org/10.18698/0236-3941-2019-1-90-100). All
# parameters are the paper's relative ones; lengths are in units of $x_{st} = P_0/c_1$.

# %% tags=["parameters"]
# ---- your object and suppressor: change these, then run all cells -----------------------
mu = 0.08  # suppressor's mass over the object's, m2/m1
delta1 = 0.05  # object's relative damping, k1/(2 m1 omega1)
band = (0.5, 1.5)  # forcing frequencies the object meets, theta = omega/omega1
detuning = 0.1  # the object's natural frequency may be off by +- this fraction
# your own impact suppressor, for the frequency response:
N = 0.5  # suppressor's partial frequency over the object's, omega2/omega1
delta2 = 0.05  # suppressor's relative damping, k2/(2 m2 omega1)
R = 0.7  # coefficient of restitution: 0 plastic ... 1 elastic
gap = 2.0  # initial gap Delta0/x_st

# %%
import matplotlib.pyplot as plt
import numpy as np

import impactdamper as idp
from impactdamper.reporting import plotting
from impactdamper.studies.design import design, optimum

plt.style.use(plotting.STYLE_FILE)

# %% [markdown]
# ## Both devices optimised
#
# The impact suppressor in its gap, $N$, $\delta_2$ and $R$; the TMD in $N$ and $\delta_2$; both by a
# Sobol sample of the parameter box and Nelder-Mead from its best points, on the peak of
# $\max|x_1|/x_{st}$ over the band (the worse sweep direction), located, not sampled.

# %%
result = optimum.design_optima(band, mu, delta1, detuning=detuning, progress=print)
for key in ("impact", "tmd", "tmd_equal_stroke"):
    d = result[key]
    print(
        f"{key:17s} {d['parameters']}: peak {d['peak']:.3f} at theta {d['peak_theta']:.3f}, band average "
        f"{d['band_average']:.3f}, worst case (+-{100 * detuning:g} %) {d['worst_case']:.3f}, stroke {d['stroke']:.2f}"
    )
imp = result["impact"]
print(
    f"impact loads: largest pulse {imp['impulse_per_impact']:.3f} P0/omega1, at most {imp['impacts_per_second']:.3f} "
    f"impacts per 1/f1, mean impact force up to {imp['mean_force']:.3f} P0; clearance {imp['clearance']:.2f} P0/c1"
)
print("impact over TMD:", {k: round(v, 3) for k, v in result["ratio"].items()})

# %% [markdown]
# ## Your suppressor beside them

# %%
p = idp.Parameters(mu=mu, N=N, delta1=delta1, delta2=delta2, R=R, gap=gap)
mine = design.impact_band_response(p, band)
best = design.impact_band_response(idp.Parameters(mu=mu, delta1=delta1, **result["impact"]["parameters"]), band)
tmd = design.LinearDevice(mu, result["tmd"]["parameters"]["N"], delta1, result["tmd"]["parameters"]["delta2"])
th = np.linspace(*band, 801)
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(th, design.LinearDevice(0.0, 1.0, delta1, 0.0).amplitude(th), ":", color="0.3", label="object alone")
ax.plot(th, tmd.amplitude(th), color="C3", label="optimal TMD")
for r, color, text in ((mine, "C0", "your suppressor"), (best, "C2", "optimal impact suppressor")):
    ax.plot(r.thetas, r.up, "-", color=color, lw=1.0, label=f"{text}, upward")
    ax.plot(r.thetas, r.down, "--", color=color, lw=0.9, label=f"{text}, downward")
    ax.plot([r.peak_theta], [r.peak], "o", color=color, ms=4)
ax.set_xlabel(r"$\theta = \omega/\omega_1$")
ax.set_ylabel(r"$\max|x_1|/x_{st}$")
ax.legend(fontsize=7)
plt.show()
print(
    f"your suppressor: located peak {mine.peak:.3f} at theta {mine.peak_theta:.4f} (grid: {mine.grid_peak():.3f}), "
    f"band average {mine.band_average:.3f}"
)
for q in mine.peaks:
    print(
        f"  local maximum {q.value:.4f} at theta {q.theta:.5f} ({q.direction}, "
        f"{'periodic' if q.periodic else 'nonperiodic'}{', at a jump' if q.jump else ''})"
    )

# %% [markdown]
# ## When the object's frequency is off
#
# The worst-case peak above is the largest over the object's natural frequency detuned by up to
# +-`detuning` (its stiffness changed; the suppressor as built). Here each device's peak against
# the detuning, both over the nominal $x_{st}$.

# %%
es = np.array(imp["worst_case_detunings"])
t = result["tmd"]["parameters"]
tmd_detuned = [
    optimum.worst_case_tmd(mu, delta1, t["N"], t["delta2"], band, 0.0)
    if e == 0
    else design.LinearDevice(mu, t["N"] / (1 + e), delta1 / (1 + e), t["delta2"] / (1 + e)).peak(
        (band[0] / (1 + e), band[1] / (1 + e))
    )[1]
    / (1 + e) ** 2
    for e in es
]
fig, ax = plt.subplots(figsize=(7, 3), layout="constrained")
ax.plot(100 * es, imp["worst_case_peaks"], "o-", color="C2", label="optimal impact suppressor")
ax.plot(100 * es, tmd_detuned, "s--", color="C3", label="optimal TMD")
ax.set_xlabel("object's natural frequency off by (%)")
ax.set_ylabel(r"peak $\max|x_1|/x_{st}$ over the band")
ax.legend(fontsize=8)
plt.show()
