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
# Which gap should your impact suppressor have, and is it better than a plain tuned-mass damper
# of the same mass? Change the numbers in the next cell and run all cells (about half a minute):
# you get the frequency response of your suppressor (upward and downward sweeps of the forcing
# frequency, each point started from its neighbour's motion), a small design chart over the gap,
# and the linear references, each computed: the object alone, the absorber without a stop, and
# the optimal linear tuned-mass damper of the same mass ratio.
#
# The model is that of Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
# [10.18698/0236-3941-2019-1-90-100](https://doi.org/10.18698/0236-3941-2019-1-90-100). All
# parameters are the paper's relative ones; lengths are in units of $x_{st} = P_0/c_1$, pulses in
# $m_1 x_{st}\omega$.

# %% tags=["parameters"]
# ---- your suppressor: change these, then run all cells ---------------------------------
mu = 0.08      # suppressor's mass over the object's, m2/m1
N = 0.5        # suppressor's partial frequency over the object's, omega2/omega1
delta1 = 0.05  # object's relative damping, k1/(2 m1 omega1)
delta2 = 0.05  # suppressor's relative damping, k2/(2 m2 omega1)
R = 0.7        # coefficient of restitution: 0 plastic ... 1 elastic
gap = 0.85     # initial gap Delta0/x_st of the frequency response
band = (0.5, 1.5)   # forcing frequencies the object meets, theta = omega/omega1
points = 21         # theta values of the frequency response
chart_gaps = [-6.0, -3.0, 0.0, 1.0, 2.0, 3.0, 5.0]  # gaps of the design chart
chart_points = 11   # theta values per gap in the chart

# %%
import matplotlib.pyplot as plt
import numpy as np

import impactdamper as idp
from impactdamper.analysis import response
from impactdamper.reporting import plotting
from impactdamper.studies import design

plt.style.use(plotting.STYLE_FILE)
p = idp.Parameters(mu=mu, N=N, delta1=delta1, delta2=delta2, R=R, gap=gap)
print(p)

# %% [markdown]
# ## The linear references
#
# The optimal tuned-mass damper (TMD) minimises the peak of $|x_1|/x_{st}$ over the band by its
# tuning $N$ and damping $\delta_2$; for an undamped object Den Hartog's closed form is its check.

# %%
tmd = design.optimal_tmd(mu, delta1, band)
dh = design.den_hartog(mu)
check = design.optimal_tmd(mu, 0.0, band)
print(f"optimal TMD: N = {tmd.N:.4f}, delta2 = {tmd.delta2:.4f}, peak |x1|/x_st = {tmd.peak:.3f}")
print(f"check, undamped object: optimiser peak {check.peak:.4f}, N = {check.N:.4f}; Den Hartog's fixed-point "
      f"height {dh['peak']:.4f} (a lower bound), N = {dh['N']:.4f}")

# %% [markdown]
# ## Frequency response of your suppressor

# %%
r = response.frequency_response(p, band[0], band[1], points)
th = np.linspace(*band, 401)
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(th, design.bare_object_amplitude(delta1, th), ":", color="0.3", label="object alone")
ax.plot(th, design.two_mass_amplitude(mu, N, delta1, delta2, th), "-.", color="C2", label="absorber, no stop")
ax.plot(th, tmd.amplitude(th), color="C3", label="optimal TMD")
ax.plot(r.thetas, [q.up.max_abs_x1 for q in r.points], "o-", color="C0", ms=3, label="impact, upward sweep")
ax.plot(r.thetas, [q.down.max_abs_x1 for q in r.points], "s--", color="C1", ms=3, mfc="none",
        label="impact, downward sweep")
ax.set_xlabel(r"$\theta = \omega/\omega_1$")
ax.set_ylabel(r"$\max|x_1|/x_{st}$")
ax.legend(fontsize=8)
plt.show()
print(f"peak over the band {r.peak():.3f} (optimal TMD {tmd.peak:.3f}), band average {r.band_average():.3f} "
      f"(TMD {tmd.band_average:.3f}); loads: {r.loads()}")
for q in r.points:
    flag = "  hysteresis" if q.hysteresis else ""
    print(f"theta {q.theta:.3f}: {q.up.label}/{q.down.label}, max|x1| {q.up.max_abs_x1:.3f}/{q.down.max_abs_x1:.3f}, "
          f"impacts/T {q.up.impacts_per_period:g}, peak pulse {q.up.peak_impulse:.3f}, energy balance "
          f"{q.up.balance:.1e}{flag}")

# %% [markdown]
# ## Which gap?
#
# The peak over the band of the worse sweep direction, at each gap of `chart_gaps`, with the loads
# that gap brings.

# %%
chart = design.gap_chart(p, chart_gaps, band, chart_points)
best = chart.best("peak")
impulse, impacts = chart.loads()
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True, layout="constrained")
ax.plot(chart.gaps, chart.criterion("peak"), "o-", label="impact: peak over the band")
ax.plot(chart.gaps, chart.criterion("band_average"), "s--", label="impact: band average")
ax.axhline(tmd.peak, color="C3", label=f"optimal TMD peak ({tmd.peak:.2f})")
ax.axvspan(best["good_from"], best["good_to"], alpha=0.15)
ax.set_ylabel(r"$\max|x_1|/x_{st}$")
ax.legend(fontsize=8)
ax2.plot(chart.gaps, impulse, "o-", label="largest pulse")
ax2.plot(chart.gaps, impacts, "s--", label="most impacts per period")
ax2.set_xlabel(r"$\Delta_0/x_{st}$")
ax2.legend(fontsize=8)
plt.show()
print(f"best gap {best['gap']:g}: peak {best['value']:.3f} against the optimal TMD's {tmd.peak:.3f}; gaps within "
      f"{100 * best['tolerance']:.0f} % of it: {best['good_from']:g} to {best['good_to']:g}; largest pulse "
      f"{best['peak_impulse']:.3f} m1 x_st omega, {best['impacts_per_period']:g} impacts per period")
