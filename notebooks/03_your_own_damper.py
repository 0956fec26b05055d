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
# # Your own damper
#
# Change the numbers in the next cell and run all cells: you get the settled motion of your
# impact vibration suppressor (its regime, the cycle) and what it does for the object,
# compared with the object alone and with the suppressor's mass bolted on rigidly.
#
# The model is that of Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
# [10.18698/0236-3941-2019-1-90-100](https://doi.org/10.18698/0236-3941-2019-1-90-100): the
# object $m_1$ on $(c_1, k_1)$ forced by $P_0\sin\omega t$, the suppressor $m_2$ on
# $(c_2, k_2)$ attached to it, a one-sided stop with restitution $R$, and the gap
# $\Delta = \Delta_0 - (x_2 - x_1) \ge 0$. All parameters are the paper's relative ones;
# lengths are in units of the static deflection $x_{st} = P_0/c_1$.

# %% tags=["parameters"]
# ---- your damper: change these, then run all cells -------------------------------------
theta = 1.0  # forcing frequency over the object's natural frequency, omega/omega1
mu = 0.08  # suppressor's mass over the object's, m2/m1
N = 0.5  # suppressor's partial frequency over the object's, omega2/omega1
delta1 = 0.05  # object's relative damping, k1/(2 m1 omega1)
delta2 = 0.05  # suppressor's relative damping, k2/(2 m2 omega1)
R = 0.7  # coefficient of restitution: 0 plastic ... 1 elastic
gap = 0.0  # initial gap Delta0/x_st (negative: the suppressor is preloaded against the stop)
omega = 10.0  # forcing frequency in rad/s (only sets the time scale)
FREQUENCY_RESPONSE = True  # also sweep theta from 0.6 to 1.4 (about 20 s)

# %%
import matplotlib.pyplot as plt
import numpy as np

import impactdamper as idp
from impactdamper.core import linear
from impactdamper.reporting import plotting
from impactdamper.studies import vocabulary

plt.style.use(plotting.STYLE_FILE)

p = idp.Parameters(theta=theta, mu=mu, N=N, delta1=delta1, delta2=delta2, R=R, gap=gap, omega=omega)
print(p)
print(f"T = {p.T:.6g} s, omega1 = {p.omega1:.6g} rad/s, omega2 = {p.omega2:.6g} rad/s")

# %% [markdown]
# ## The settled motion
#
# Algorithm No. 2 (event after event, with the exact flow between impacts and persistent
# contact where impacts accumulate) from the paper's step 1, run until the motion repeats.

# %%
ss = idp.steady_state(p)
print(f"regime: {ss.regime}")
if ss.settled:
    print(
        f"period T_c = {ss.period_multiple} T, {ss.impacts_per_cycle} impact(s) per cycle,"
        f" settled after {ss.periods} forcing periods"
    )
else:
    print(f"no period up to 8T within {ss.periods} forcing periods; the last 8 periods are shown")
print(f"share of the cycle in persistent contact: {ss.contact_fraction:.3f}")
for k, i in enumerate(ss.impacts[:12], 1):
    print(
        f"  impact {k}: t = {i.t_over_T:.4f} T into the cycle, closing velocity"
        f" {i.velocity / (p.x_st * p.omega):.4f} x_st omega, pulse {i.impulse / (p.m1 * p.x_st * p.omega):.4f} m1 x_st omega"
    )
if len(ss.impacts) > 12:
    print(f"  ... {len(ss.impacts) - 12} more")

# %% [markdown]
# Algorithm No. 1 (the closed form for one impact per period) is a quick first guess; it
# holds only if its orbit exists, never crosses the stop, and is the motion that settles.

# %%
a1 = idp.algorithm1(p)
if not a1.exists:
    print("Algorithm No. 1: no orbit:", a1.reason)
elif not a1.admissible:
    print(f"Algorithm No. 1: its orbit crosses the stop on {a1.negative_gap_intervals} (units of T): not a motion")
else:
    print(f"Algorithm No. 1: admissible orbit, impact phase {a1.impact_phase:.9f}")
    if ss.regime == "single_impact":
        print(f"Algorithm No. 2 settles on impact phase {ss.impacts[0].phase:.9f}")
    else:
        print(f"but Algorithm No. 2 from step 1 settles on a {ss.regime} motion instead")

# %% [markdown]
# ## The cycle
#
# The relative coordinates $\bar x_1 = x_1/x_{st}$, $\bar x_2 = (x_2 - \Delta_0)/x_{st}$ over
# the settled cycle and the next impact; the gap is $\Delta/x_{st} = \bar x_1 - \bar x_2$.
# Dotted: impacts; shaded: persistent contact.

# %%
t_end = ss.cycle_start + ss.cycle_duration
t = np.linspace(ss.cycle_start, t_end + 0.1 * p.T, 2000)
x1b, x2b = ss.sample(t)
tt = (t - ss.cycle_start) / p.T
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6.3, 3.8), height_ratios=(2, 1), layout="constrained")
top.plot(tt, x1b, label=r"$\bar x_1$ (object)")
top.plot(tt, x2b, label=r"$\bar x_2$ (suppressor)")
bottom.plot(tt, x1b - x2b, color="C2")
bottom.axhline(0.0, color="k", lw=0.8)
for e in ss.trajectory.events:
    if e.kind == "impact" and t[0] <= e.t <= t[-1]:
        for ax in (top, bottom):
            ax.axvline((e.t - ss.cycle_start) / p.T, color="C3", lw=0.5, ls=":")
stuck = ss.trajectory.sample(t)[1] == "stuck"
for ax in (top, bottom):
    ax.fill_between(tt, 0, 1, where=stuck, transform=ax.get_xaxis_transform(), color="C5", alpha=0.25, lw=0)
period = f"$T_c = {ss.period_multiple}T$" if ss.settled else "last 8 periods"
top.set_title(f"{ss.regime}, {period}")
top.set_ylabel("relative coordinate")
top.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
bottom.set_ylabel(r"$\Delta/x_{st}$")
bottom.set_xlabel(r"$(t - t_{\rm start})/T$")

# %% [markdown]
# ## What it does for the object
#
# The object's largest excursion $\max|x_1|/x_{st}$ over the settled motion, against
#
# * the object alone (one degree of freedom): $1/\sqrt{(1 - \theta^2)^2 + (2\delta_1\theta)^2}$;
# * the suppressor's mass rigidly attached (mass $m_1 + m_2$ on $c_1, k_1$):
#   $1/\sqrt{(1 - (1 + \mu)\theta^2)^2 + (2\delta_1\theta)^2}$;
# * the suppressor on its spring without the stop (a linear dynamic absorber, eq. 10).
#
# The closed forms are checked against the library's linear modes.


# %%
def amplitude(mode):
    """Amplitude of coordinate 0 of a linear mode's forced response (Y = Im(Yhat e^{iwt}))."""
    y = mode.forced(np.array([0.0, 0.25 * 2 * np.pi / mode.omega]))[:, 0]
    return float(np.hypot(y[0], y[1]))


def comparisons(p):
    alone = 1.0 / np.hypot(1 - p.theta**2, 2 * p.delta1 * p.theta)
    rigid = 1.0 / np.hypot(1 - (1 + p.mu) * p.theta**2, 2 * p.delta1 * p.theta)
    absorber = abs(linear.forced_amplitudes(p)[0]) / p.x_st
    return alone, rigid, absorber


alone, rigid, absorber = comparisons(p)
rigid_mode = amplitude(linear.stuck_mode(p)) / p.x_st
print(f"rigidly attached: closed form {rigid:.10f}, stuck mode {rigid_mode:.10f}")
rows = [
    ("with your suppressor", ss.x1_max),
    ("object alone", alone),
    ("rigidly attached mass", rigid),
    ("absorber without the stop", absorber),
]
for name, value in rows:
    print(f"  {name:>26s}: max |x1|/x_st = {value:8.4f}  ({value / alone:6.1%} of the object alone)")

fig, ax = plt.subplots(figsize=(6.3, 2.2), layout="constrained")
ax.barh([r[0] for r in rows][::-1], [r[1] for r in rows][::-1], color=["C5", "C5", "C5", "C0"])
ax.set_xlabel(r"max $|x_1|/x_{st}$")
ax.set_title("The object's largest excursion")
# %% [markdown]
# ## Around your forcing frequency
#
# The same comparison over $\theta = \omega/\omega_1$ from 0.6 to 1.4, everything else as you
# set it (to keep this quick, each motion gets at most 800 forcing periods to settle; dots are
# coloured by regime).

# %%
COLORS = {
    "stuck": "C5",
    "chatter": "C3",
    "multi_impact": "C4",
    "single_impact": "C0",
    "no_contact": "C2",
    "nonperiodic": "C1",
}
if FREQUENCY_RESPONSE:
    thetas = np.linspace(0.6, 1.4, 33)
    fine = np.linspace(0.6, 1.4, 401)
    curves = np.array([comparisons(p.replace(theta=float(th))) for th in fine])
    runs = [idp.steady_state(p.replace(theta=float(th)), max_periods=800) for th in thetas]
    fig, ax = plt.subplots(layout="constrained")
    for k, (text, style) in enumerate((("object alone", "--"), ("rigidly attached", ":"), ("absorber, no stop", "-."))):
        ax.plot(fine, curves[:, k], style, color="C5", lw=0.9, label=text)
    ax.plot(thetas, [s.x1_max for s in runs], "-", color="k", lw=0.5)
    for regime in idp.REGIMES:
        sel = [s for s in runs if s.regime == regime]
        if sel:
            ax.plot([s.p.theta for s in sel], [s.x1_max for s in sel], "o", ms=3, color=COLORS[regime], label=regime)
    ax.axvline(p.theta, color="k", lw=0.5, ls=":")
    ax.set_xlabel(vocabulary.SPEC["theta"].label)
    ax.set_ylabel(r"max $|x_1|/x_{st}$")
    ax.set_ylim(0, 1.15 * max(curves.max(), max(s.x1_max for s in runs)))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)

# %%
plt.show()  # run as a script: show the figures (in Jupyter they are shown already)
