"""Penalty stiffness study, in a notebook's style: how stiff must the penalty be?

Runs examples/hertz_rigid_fast.toml (a rigid flat pressed on an elastic cylinder, Hertz's
p_max = 383.51 MPa) in process with `penalty` over a range of stiffness factors (k = factor x
each row's local stiffness), next to `lagrange` as the exact answer, and plots the peak-pressure
error and the penetration against the factor. Run it after the README's first command:

    PYTHONPATH=build/python python3 examples/python/penalty_sweep.py [OUT_DIR]

It prints a table and writes OUT_DIR/penalty_sweep.png (default: out/python).
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import contact2d  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
scene = os.path.join(here, "..", "hertz_rigid_fast.toml")
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("out", "python")
os.makedirs(out, exist_ok=True)

exact = contact2d.run(scene, method="lagrange")
p_ref = exact["reference"]["p_max"]
print(f"lagrange: p_max {exact['contact']['p_max']:.2f} MPa "
      f"(error {100 * (exact['contact']['p_max'] / p_ref - 1):+.3f} %)")

factors = np.logspace(0, 6, 7)
rows = []
for f in factors:
    s = contact2d.run(scene, method="penalty", set=[f"contact.penalty.factor={f:g}"])
    c = s["contact"]
    rows.append((f, s["status"], c["p_max"], c["max_penetration"], c["iterations"]))
    if s["status"] != "converged":  # e.g. ill_conditioned: a failed run has no figures
        print(f"factor {f:8.0e}: {s['status']}")
        continue
    print(f"factor {f:8.0e}: {s['status']:>10}  p_max {c['p_max']:8.2f} MPa  "
          f"error {100 * (c['p_max'] / p_ref - 1):+7.3f} %  penetration {c['max_penetration']:.2e} mm")

ok = [r for r in rows if r[1] == "converged"]
fig, ax = plt.subplots(1, 2, figsize=(9, 3.5))
ax[0].loglog([r[0] for r in ok], [abs(r[2] / p_ref - 1) * 100 for r in ok], "o-", label="penalty")
ax[0].axhline(abs(exact["contact"]["p_max"] / p_ref - 1) * 100, color="k", ls="--",
              label="lagrange")
ax[0].set_xlabel("penalty factor (k / local stiffness)")
ax[0].set_ylabel("|p_max error| (%)")
ax[0].legend()
ax[1].loglog([r[0] for r in ok], [max(r[3], 1e-300) for r in ok], "s-")
ax[1].set_xlabel("penalty factor (k / local stiffness)")
ax[1].set_ylabel("max penetration (mm)")
fig.suptitle("Penalty stiffness on the Hertz rigid flat (hertz_rigid_fast.toml)")
fig.tight_layout()
path = os.path.join(out, "penalty_sweep.png")
fig.savefig(path, dpi=120)
print("wrote", path)

# The stiffest converged penalty should reach lagrange's answer (to 0.5 % of p_max): the
# penalty's error is O(1/k).
stiff = ok[-1]
gap = abs(stiff[2] / exact["contact"]["p_max"] - 1)
print(f"stiffest converged penalty (factor {stiff[0]:g}) vs lagrange: {100 * gap:.4f} %")
sys.exit(0 if gap < 5e-3 else 1)
