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
# # The gap sweep: regime bands and the bifurcation diagram
#
# Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
# [10.18698/0236-3941-2019-1-90-100](https://doi.org/10.18698/0236-3941-2019-1-90-100), note
# that with a negative initial gap $\Delta_0$ and small forcing "the object and the
# suppressor move together", with large forcing the suppressor "works with one blow during
# the period", and in between several impacts per period and periods $T_c = kT$ appear.
# Relative to the forcing, a more negative $\Delta_0/x_{st}$ is a smaller forcing, so a sweep
# over the gap crosses all of these motions. Here: the reference case of Fig. 2 with only
# $\Delta_0/x_{st}$ varied.
#
# This notebook is a tour on a coarse grid, computed live; the sweep figures of the report
# come from the Snakemake workflow, on its own grid and settings.

# %%
import time

import matplotlib.pyplot as plt
import numpy as np

import impactdamper as idp
from impactdamper.core import linear
from impactdamper.reporting import plotting
from impactdamper.analysis import ladder, linear_device, point, sweeps, transitions
from impactdamper.studies import vocabulary

GAP = vocabulary.SPEC["gap"].symbol  # the gap's symbol in TeX: its row of the parameter table

plt.style.use(plotting.STYLE_FILE)

# %% [markdown]
# ## The sweep
#
# Each motion is classified by `steady_state` once it repeats with a period $T_c = kT$,
# $k \le 8$ (see `impactdamper.REGIMES`), and labelled after Peterka as $z/k$: $z$ impacts in
# $k$ forcing periods.
#
# | regime | label | meaning |
# |---|---|---|
# | `stuck` | stuck | the bodies stay in contact: they move as one mass |
# | `chatter` | c/k | the cycle has a phase of persistent contact (reached through an accumulation of impacts) and a lift-off |
# | `multi_impact` | z/k | a periodic motion with several impacts per cycle or $k > 1$ |
# | `single_impact` | 1/1 | one impact per forcing period: the motion Algorithm No. 1 describes |
# | `no_contact` | 0/1 | the bodies never touch: a linear dynamic absorber |
# | `nonperiodic` | np | no period up to $8T$ found within the sweep's budget of periods |
#
# `impactdamper.analysis.sweeps` runs the gap three ways: upward and downward, each point starting
# from its neighbour's settled motion (as a slowly changing machine would), and every point
# from the paper's step 1 (Algorithm No. 2 as the paper runs it). Where they differ, several
# motions coexist at that gap. The sweep caps each simulation at a small number of periods
# and speeds up with continuation of periodic orbits; `nonperiodic` means "no period found
# within that budget", not a proof of chaos (see the module's documentation).

# %%
reference = idp.Parameters()
gaps = np.round(np.arange(-36.0, 15.01, 0.75), 10)

start = time.perf_counter()
both = sweeps.two_way_sweep(reference, "gap", gaps)
print(f"up and down sweeps of {len(gaps)} gaps: {time.perf_counter() - start:.1f} s")
start = time.perf_counter()
from_step1 = [ladder.solve_point(reference.replace(gap=float(g))) for g in gaps]
print(f"every gap from step 1: {time.perf_counter() - start:.1f} s")
runs = {"up": both["up"], "down": both["down"], "step 1": from_step1}

# %% [markdown]
# ## The regime bands
#
# Consecutive grid points with the same label form a band. The grid is coarse: a band
# boundary is only known to within a grid step, and a narrow band may fall between two
# points.


# %%
def bands(points):
    """[first value, last value, label, regime] of each run of equal labels."""
    out = []
    for pt in points:
        if out and out[-1][2] == pt.label:
            out[-1][1] = pt.value
        else:
            out.append([pt.value, pt.value, pt.label, pt.regime])
    return out


for name, points in runs.items():
    print(f"{name}:")
    for lo, hi, lab, regime in bands(points):
        print(f"  gap {lo:7.2f} .. {hi:7.2f}: {lab:>6s} ({regime})")

differ = [float(g) for g, *pts in zip(gaps, *runs.values()) if len({pt.label for pt in pts}) > 1]
print("gaps where the three runs disagree (coexisting motions):", differ)

# %% [markdown]
# Some band edges have closed forms (`impactdamper.analysis.transitions`), which the sweep should bracket:
#
# * the bodies can stay joined only while the stop's force stays positive over the joined
#   bodies' forced motion: below the lift-off gap;
# * the bodies can stay apart only while the impact-free motion's relative swing $U_1$
#   (eq. 12) stays below the gap: above $U_1/x_{st}$;
# * Algorithm No. 1's orbit exists only for $|\Delta_0| \le \sqrt{U_1^2 + U_2^2}$ (eq. 16), and
#   is admissible only above the gap where it starts to cross the stop between impacts.

# %%
thresholds = {
    "stuck lift-off": transitions.stuck_liftoff_gap(reference),
    "no contact above (U1)": transitions.no_contact_gap(reference),
    "Alg. 1 exists within +-": transitions.algorithm1_existence_gap(reference),
    "Alg. 1 admissible above": transitions.algorithm1_grazing_gap(reference, (-7.0, -11.0)),
}
for name, value in thresholds.items():
    print(f"  {name:>24s}: {value:9.4f}")

# %% [markdown]
# ## The bifurcation diagram
#
# For each gap and each run, every impact of the settled cycle (for a nonperiodic motion: of
# its last eight periods) as a dot: its closing velocity and its phase in the forcing period
# (filled: upward sweep; open: downward sweep). One dot per gap is a one-impact motion; $n$
# dots, $n$ impacts per cycle; a smear, a motion that does not repeat. The top strips are the
# regime bands of the three runs. The bottom panel is what the suppressor is for: the
# object's largest excursion, against the object alone, the suppressor rigidly attached
# (mass $m_1 + m_2$ on $c_1, k_1$) and the suppressor on its spring with no stop (a linear
# absorber, eq. 10). Dashed verticals: the closed-form edges above; dotted: the paper's -5.8.

# %%
COLORS = {
    "stuck": "C5",
    "chatter": "C3",
    "multi_impact": "C4",
    "single_impact": "C0",
    "no_contact": "C2",
    "nonperiodic": "C1",
}
p = reference
alone = float(linear_device.LinearDevice.bare(p.delta1).amplitude([p.theta])[0])
rigid = transitions.rigid_amplitude(p)
absorber = abs(linear.forced_amplitudes(p)[0]) / p.x_st

fig, axes = plt.subplots(
    6, 1, sharex=True, figsize=(6.3, 7.4), height_ratios=(0.22, 0.22, 0.22, 1.4, 1, 1), layout="constrained"
)
strips, (vel, phase, amp) = axes[:3], axes[3:]
step = gaps[1] - gaps[0]
for ax, (name, points) in zip(strips, runs.items()):
    for lo, hi, _, regime in bands(points):
        ax.axvspan(lo - step / 2, hi + step / 2, color=COLORS[regime], alpha=0.85, lw=0)
    ax.set_yticks([0.5])
    ax.set_yticklabels([name], fontsize=7)
    ax.grid(False)
found = [r for r in idp.REGIMES if any(pt.regime == r for pts in runs.values() for pt in pts)]
strips[0].legend(
    [plt.Rectangle((0, 0), 1, 1, color=COLORS[r]) for r in found],
    found,
    ncol=3,
    loc="lower center",
    bbox_to_anchor=(0.5, 1.05),
    fontsize=7,
)
for name, marker in (("up", "o"), ("down", "o")):
    for pt in runs[name]:
        face = COLORS[pt.regime] if name == "up" else "none"
        kw = dict(ls="none", marker=marker, ms=2.2 if name == "up" else 3.6, mfc=face, mec=COLORS[pt.regime], mew=0.5)
        vel.plot([pt.value] * len(pt.velocities), pt.velocities, **kw)
        phase.plot([pt.value] * len(pt.phases), pt.phases, **kw)
vel.set_ylabel(r"closing velocity / $x_{st}\omega$")
phase.set_ylabel(r"impact phase $t/T$ mod 1")
phase.set_ylim(0, 1)
amp.plot(gaps, [pt.x1_max for pt in runs["up"]], ".-", ms=3, color="k", lw=0.6, label="with the suppressor (up)")
amp.plot(gaps, [pt.x1_max for pt in runs["down"]], "o", ms=3.6, mfc="none", mec="k", mew=0.5, label="(down)")
for value, text, style in (
    (alone, "object alone", "--"),
    (rigid, "rigidly attached", ":"),
    (absorber, "absorber, no stop", "-."),
):
    amp.axhline(value, ls=style, lw=0.9, color="C5", label=f"{text}: {value:.2f}")
amp.set_ylabel(r"max $|x_1|/x_{st}$")
amp.set_xlabel(vocabulary.SPEC["gap"].label)
amp.legend(loc="lower left", fontsize=7, ncol=2)
edges = [
    thresholds["stuck lift-off"],
    thresholds["no contact above (U1)"],
    thresholds["Alg. 1 admissible above"],
    -thresholds["Alg. 1 exists within +-"],
    thresholds["Alg. 1 exists within +-"],
]
for ax in (vel, phase, amp):
    ax.axvline(-5.8, color="k", lw=0.5, ls=":")
    for e in edges:
        ax.axvline(e, color="C5", lw=0.5, ls="--")
fig.suptitle(f"Reference case of Fig. 2, {vocabulary.SPEC['gap'].label} varied", fontsize=9)
# %%
# The reading below describes what was computed above; stop here if it no longer does.
for points in runs.values():
    assert points[0].regime == "stuck" and points[-1].regime == "no_contact"
    assert {pt.regime for pt in points if pt.value == -5.25} == {"single_impact"}
assert thresholds["stuck lift-off"] < thresholds["Alg. 1 admissible above"] < thresholds["no contact above (U1)"]

# %% [markdown]
# Reading it from the right (large positive gap) to the left (deep preload):
#
# * above $U_1/x_{st}$ the bodies never meet: the suppressor is a plain linear absorber, and
#   the object moves with the absorber's amplitude;
# * as the gap closes, one impact per period appears (`1/1`): the band where Algorithm No. 1
#   applies, with a short irregular stretch at its upper edge where the impacts start as
#   grazing contacts. The object's excursion has its minimum inside this band: the impacts
#   take energy out of the object's resonance;
# * going deeper into the preload, past the gap where Algorithm No. 1's orbit starts to cross
#   the stop, the one-impact motion gives way to motions with several impacts and longer
#   periods (like the paper's Fig. 2b), motions that do not repeat, and chatter; several
#   motions can coexist at one gap;
# * below the lift-off gap the stop never opens: the bodies move together, and the object
#   moves as the rigidly attached pair does.
#
# ## One case of each regime, over time
#
# For each regime found in the upward sweep, the gap in the middle of its widest band,
# simulated again by `steady_state` from the state the sweep point started from (a check
# that the sweep's shortcuts found the motion the plain simulation settles on), over the
# last stretch of the motion: two cycles, at least four forcing periods; for a nonperiodic
# motion its last eight periods. Dotted lines: impacts; shading: persistent contact.


# %%
def representative(points, regime):
    runs_ = [b for b in bands(points) if b[3] == regime]
    lo, hi, _, _ = max(runs_, key=lambda b: b[1] - b[0])
    inside = [pt for pt in points if lo <= pt.value <= hi]
    return inside[len(inside) // 2]


cases = []
for regime in idp.REGIMES:
    if any(pt.regime == regime for pt in runs["up"]):
        pt = representative(runs["up"], regime)
        s = idp.steady_state(pt.p, state=pt.start_state, max_periods=1500)
        again = point.label_of(s.regime, s.period_multiple, s.impacts_per_cycle)
        print(
            f"gap {pt.value:7.2f}: sweep {pt.label:>6s} ({pt.method}), steady_state {again:>6s}, max|x1|/x_st"
            f" {pt.x1_max:.6f} vs {s.x1_max:.6f}"
        )
        cases.append(s)

fig, axes = plt.subplots(len(cases), 1, figsize=(6.3, 1.45 * len(cases) + 0.6), layout="constrained", squeeze=False)
for ax, s in zip(axes[:, 0], cases):
    p_ = s.p
    span = max(2 * s.cycle_duration, 4 * p_.T) if s.settled else s.cycle_duration
    t_end = s.cycle_start + s.cycle_duration
    t = np.linspace(max(t_end - span, s.trajectory.segments[0][1].t0), t_end, 1600)
    x1b, x2b = s.sample(t)
    tt = (t - t_end) / p_.T
    ax.plot(tt, x1b, label=r"$\bar x_1$")
    ax.plot(tt, x2b, label=r"$\bar x_2$")
    for e in s.trajectory.impacts(t[0], t_end + 1e-9 * p_.T):
        ax.axvline((e.t - t_end) / p_.T, color="C3", lw=0.4, ls=":")
    mode = s.trajectory.sample(t)[1]
    ax.fill_between(tt, 0, 1, where=mode == "stuck", transform=ax.get_xaxis_transform(), color="C5", alpha=0.25, lw=0)
    period = f", $T_c = {s.period_multiple}T$" if s.settled else ""
    ax.set_title(rf"{s.regime}{period}, ${GAP} = {p_.gap:g}$", fontsize=8, loc="left", pad=2)
    ax.set_ylabel("rel. coord.")
axes[0, 0].legend(loc="upper right", ncol=2, fontsize=7)
axes[-1, 0].set_xlabel(r"$(t - t_{\rm end})/T$")
# %% [markdown]
# Algorithm No. 1 can only describe the one-impact band. Where it applies, its closed-form
# impact phase should match the settled motion's. Where its orbit does not exist or crosses
# the stop, the settled motion is something else. And an admissible orbit need not be what
# the motion settles to: it may be unstable, or the start may lie in the basin of another
# motion (the paper's algorithms say nothing about either).

# %%
for s in cases:
    a1 = idp.algorithm1(s.p)
    if not a1.exists:
        verdict = "no orbit (" + a1.reason + ")"
    elif not a1.admissible:
        verdict = f"orbit with a negative gap on {[(round(a, 3), round(b, 3)) for a, b in a1.negative_gap_intervals]} T"
    else:
        verdict = f"admissible orbit, impact phase {a1.impact_phase:.9f}"
    settled = f", settled phase {s.impacts[0].phase:.9f}" if s.regime == "single_impact" else ""
    print(f"gap {s.p.gap:7.2f} ({s.regime}): Algorithm No. 1: {verdict}{settled}")

# %% [markdown]
# ## A closer look at a nonperiodic motion
#
# If a motion did not settle, its stroboscopic section (the state at $t = nT$) over many
# periods shows what it does instead: a cloud or a curve rather than $k$ points. Here the
# middle nonperiodic gap of the upward sweep, run for 1500 periods from its start.

# %%
nonperiodic = [pt for pt in runs["up"] if pt.regime == "nonperiodic"]
if nonperiodic:
    pt = nonperiodic[len(nonperiodic) // 2]
    traj = idp.simulate(pt.p, 1500 * pt.p.T, state=pt.start_state)
    n = np.arange(500, 1501)
    full, _ = traj.sample(n * pt.p.T)
    fig, ax = plt.subplots(figsize=(4.0, 3.2), layout="constrained")
    ax.plot(full[:, 0] / pt.p.x_st, full[:, 2] / (pt.p.x_st * pt.p.omega), ".", ms=1.5)
    ax.set_xlabel(r"$x_1/x_{st}$ at $t = nT$")
    ax.set_ylabel(r"$\dot x_1/(x_{st}\omega)$ at $t = nT$")
    ax.set_title(rf"Stroboscopic section, ${GAP} = {pt.value:g}$, periods 500-1500", fontsize=8)
else:
    print("no nonperiodic motion in the upward sweep")

# %%
plt.show()  # run as a script: show the figures (in Jupyter they are shown already)
