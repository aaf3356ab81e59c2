"""Loads a model, steps it and plots its bodies' trajectories.

    PYTHONPATH=python python3 examples/python/plot_trajectory.py [MODEL.yaml] [--t-end T] [--png F.png]

Default: the four-bar linkage of tests/models/four_bar.yaml for 2 s. Writes
the x-y path of every body's centre of mass and the energy over time to a
PNG with matplotlib when it is installed; without it, prints the trajectory's
summary and says so.
"""
import argparse
import pathlib

import numpy as np

import mbrt

root = pathlib.Path(__file__).resolve().parents[2]
parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("model", nargs="?", default=root / "tests" / "models" / "four_bar.yaml")
parser.add_argument("--t-end", type=float, default=2.0)
parser.add_argument("--png", default="trajectory.png")
args = parser.parse_args()

model = mbrt.load(args.model)
every = max(1, round(0.01 / model.h))  # a sample every 10 ms
t, q, energy = [], [], []
while model.t < args.t_end - 0.5 * model.h:
    model.step(every)
    t.append(model.t)
    q.append(model.q)
    energy.append(model.energy().total)
t, q, energy = np.array(t), np.array(q), np.array(energy)

# Each body's x, y, z columns in q: 7 per rigid body (x, y, z, e0..e3), 3 per particle.
first = np.cumsum([0] + [7 if rigid else 3 for rigid in model.body_rigid])[:-1]
print(f"{model.name}: {len(t)} samples to t = {t[-1]:.3f} s, energy {energy[0]:.6g} -> {energy[-1]:.6g} J")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed: no plot (Debian: apt-get install python3-matplotlib)")
    raise SystemExit(0)

fig, (paths, energies) = plt.subplots(1, 2, figsize=(11, 4.5))
for name, i in zip(model.body_names, first):
    paths.plot(q[:, i], q[:, i + 1], label=name)
paths.set(xlabel="x (m)", ylabel="y (m)", title=f"{model.name}: centres of mass", aspect="equal")
paths.legend()
energies.plot(t, energy - energy[0])
energies.set(xlabel="t (s)", ylabel="E - E(0) (J)", title=f"energy, {model.scheme}, h = {model.h} s")
fig.tight_layout()
fig.savefig(args.png, dpi=120)
print(f"wrote {args.png}")
