"""Siconos Moreau-Jean time-stepping of the suppressor (run by Debian's python3, not imported).

This file is executed as a script by :mod:`impactdamper.baselines.siconos_bridge` with the Python that
has Siconos (Debian's ``python3-siconos`` lives in /usr/bin/python3's dist-packages), so it
may import only the standard library, numpy and siconos. It reads one JSON object on stdin
and writes one on stdout.

The model, written for Siconos's Lagrangian formalism (eqs. 2 and 9 of Timofeev et al.
2019): q = (x1, x2), M q'' + C q' + K q = (P0 sin(omega t), 0) with
M = diag(m1, m2), K = [[c1 + c2, -c2], [-c2, c2]], C = [[k1 + k2, -k2], [-k2, k2]];
the unilateral constraint y = Delta0 + x1 - x2 >= 0 (``LagrangianLinearTIR``) with Newton's
impact law of restitution R (``NewtonImpactNSL``); Moreau-Jean's theta-scheme
(``MoreauJeanOSI``, theta = 1/2) with a linear complementarity problem per step (``LCP``).

Time-stepping has no impact times: an impact is a step whose velocity-level impulse
(``lambda(1)``) is positive, and is dated at the end of that step (error O(h)); consecutive
steps with an impulse count as one contact episode, dated at its first step.

Input keys: m1, m2, c1, c2, k1, k2, P0, omega, Delta0, R (SI units), t0, t_end, state
(x1, x2, x1', x2'), steps (number of steps over [t0, t_end]), theta, repeats.
Output keys: impacts (list of times), final_time, final_state, cpu_seconds (median over
``repeats`` of the process CPU time of one run: model set-up and time loop, interpreter start
and imports excluded), steps, siconos_version.
"""

import json
import math
import statistics
import sys
import time


def _run_once(cfg):
    import numpy as np
    import siconos.kernel as sk

    m1, m2, c1, c2, k1, k2 = (cfg[k] for k in ("m1", "m2", "c1", "c2", "k1", "k2"))
    P0, w = cfg["P0"], cfg["omega"]
    t0, t_end, steps = cfg["t0"], cfg["t_end"], int(cfg["steps"])
    h = (t_end - t0) / steps
    x1, x2, v1, v2 = cfg["state"]

    class ForcedDS(sk.LagrangianLinearTIDS):
        def computeFExt(self, t, *args):
            self.setFExtPtr(np.array([P0 * math.sin(w * t), 0.0]))

    M = np.diag([m1, m2])
    K = np.array([[c1 + c2, -c2], [-c2, c2]])
    C = np.array([[k1 + k2, -k2], [-k2, k2]])
    ds = ForcedDS(np.array([x1, x2]), np.array([v1, v2]), M, K, C)
    ds.setFExtPtr(np.array([P0 * math.sin(w * t0), 0.0]))
    relation = sk.LagrangianLinearTIR(np.array([[1.0, -1.0]]), np.array([cfg["Delta0"]]))
    inter = sk.Interaction(sk.NewtonImpactNSL(cfg["R"]), relation)
    nsds = sk.NonSmoothDynamicalSystem(t0, t_end)
    nsds.insertDynamicalSystem(ds)
    nsds.link(inter, ds)
    osi = sk.MoreauJeanOSI(cfg.get("theta", 0.5))
    sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(t0, h), osi, sk.LCP())
    impacts = []
    in_contact = False
    for k in range(steps):
        sim.computeOneStep()
        impulse = inter.lambda_(1)[0]
        if impulse > 0.0:
            if not in_contact:
                impacts.append(t0 + (k + 1) * h)
            in_contact = True
        else:
            in_contact = False
        sim.nextStep()
    q, v = ds.q(), ds.velocity()
    return impacts, [float(q[0]), float(q[1]), float(v[0]), float(v[1])]


def main():
    cfg = json.load(sys.stdin)
    times = []
    result = None
    for _ in range(max(int(cfg.get("repeats", 1)), 1)):
        start = time.process_time()
        result = _run_once(cfg)
        times.append(time.process_time() - start)
    try:
        from importlib.metadata import version

        siconos_version = version("siconos")
    except Exception:  # noqa: BLE001 - the version is informative only
        siconos_version = "unknown"
    impacts, state = result
    json.dump(
        {
            "impacts": impacts,
            "final_time": cfg["t_end"],
            "final_state": state,
            "cpu_seconds": statistics.median(times),
            "steps": int(cfg["steps"]),
            "siconos_version": siconos_version,
        },
        sys.stdout,
    )


if __name__ == "__main__":
    main()
