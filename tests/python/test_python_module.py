"""The Python module on the heavy symmetric top (tests/models/heavy_top.yaml).

Usage: test_python_module.py MBRT MODELS_DIR WORK_DIR. Exit 77 (skipped) when
numpy or pybind11's headers are missing.

Against closed forms: a top on a fixed point under gravity keeps its energy
(1/2 m |v|^2 + 1/2 w.J w + m g z) and the vertical component of its angular
momentum about the fixed point (gravity's torque there is horizontal; e.g.
Goldstein, Classical Mechanics, section 5.7), both computed here from the
state alone. Against the C++ step: the trajectory equals `mbrt sim --out`'s
CSV to round-off. And errors: an invalid model file raises ModelError naming
the file and line; an invalid option raises ValueError naming it.
"""
import csv
import os
import pathlib
import subprocess
import sys
import sysconfig

try:
    import numpy as np
except ImportError:
    print("skipped: numpy is missing (Debian: apt-get install python3-numpy)")
    sys.exit(77)
if not any((pathlib.Path(d) / "pybind11" / "pybind11.h").is_file()
           for d in ("/usr/include", "/usr/local/include", sysconfig.get_paths()["include"])):
    print("skipped: pybind11's headers are missing (Debian: apt-get install pybind11-dev)")
    sys.exit(77)

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python"))
import mbrt  # noqa: E402

exe, models, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
work.mkdir(parents=True, exist_ok=True)
os.environ["MBRT_CACHE_DIR"] = os.environ.get("MBRT_TEST_CACHE_DIR") or str(work / "cache")  # the tests' one cache
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += not ok


def rotation(p):
    e0, e1, e2, e3 = p
    return 2.0 * np.array([[e0 * e0 + e1 * e1 - 0.5, e1 * e2 - e0 * e3, e1 * e3 + e0 * e2],
                           [e1 * e2 + e0 * e3, e0 * e0 + e2 * e2 - 0.5, e2 * e3 - e0 * e1],
                           [e1 * e3 - e0 * e2, e2 * e3 + e0 * e1, e0 * e0 + e3 * e3 - 0.5]])


# The model file's data: m, J about the COM (body axes), COM at (0, 1, 0) in body axes from the fixed point.
m, J, g, c = 15.0, np.diag([0.234375, 0.46875, 0.234375]), 9.81, np.array([0.0, 1.0, 0.0])
J_fixed = J + m * (c @ c * np.eye(3) - np.outer(c, c))  # parallel axes


def invariants(q, v):
    r, p, vel, w = q[:3], q[3:7], v[:3], v[3:6]
    energy = 0.5 * m * vel @ vel + 0.5 * w @ J @ w + m * g * r[2]
    return energy, (rotation(p) @ J_fixed @ w)[2]


top = mbrt.load(models / "heavy_top.yaml", h=1e-4, mbrt=exe)
check(top.name == "heavy_top" and top.body_names == ["top"] and top.h == 1e-4, "model name, bodies and step")
e0, lz0 = invariants(top.q, top.v)
steps, trajectory = 2000, [np.concatenate([[top.t], top.q, top.v])]
worst_e = worst_lz = 0.0
for _ in range(steps):
    top.step()
    trajectory.append(np.concatenate([[top.t], top.q, top.v]))
    e, lz = invariants(top.q, top.v)
    worst_e, worst_lz = max(worst_e, abs(e - e0) / abs(e0)), max(worst_lz, abs(lz - lz0) / abs(lz0))
print(f"relative drift over {steps} steps: energy {worst_e:.3g}, vertical angular momentum {worst_lz:.3g}")
check(worst_e < 1e-7, "energy conserved to 1e-7")
check(worst_lz < 1e-8, "vertical angular momentum about the fixed point conserved to 1e-8")
check(abs(top.energy().total - e0) < 1e-6 * e0, "energy() agrees with the closed form")
top.reset()
check(top.t == 0.0 and np.array_equal(top.q, trajectory[0][1:8]), "reset() returns to the initial state")

# The same model through `mbrt sim`: every step's row of its CSV.
out = work / "heavy_top.csv"
sim = subprocess.run([exe, "sim", str(models / "heavy_top.yaml"), "--h", "1e-4", "--t-end", str(steps * 1e-4),
                      "--out", str(out), "--velocities"], env=os.environ, capture_output=True, text=True)
check(sim.returncode == 0, f"mbrt sim ran (exit {sim.returncode}) {sim.stderr.strip()}")
with open(out) as f:
    rows = [np.array([float(x) for x in row]) for row in list(csv.reader(f))[1:]]
n = min(len(rows), len(trajectory))
check(n >= steps, f"CSV has a row per step ({len(rows)} rows)")
difference = max(np.max(np.abs(rows[i] - trajectory[i])) for i in range(n))
check(difference < 1e-12 * 150.0, f"Python and mbrt sim trajectories agree to round-off (max difference {difference:.3g})")

# Errors.
try:
    mbrt.load(models / "bad" / "unknown_body.yaml", mbrt=exe)
    check(False, "an invalid model raises ModelError")
except mbrt.ModelError as e:
    check("unknown_body.yaml:10:" in str(e) and "crnk" in str(e), f"ModelError names file and line: {e}")
try:
    mbrt.load(models / "heavy_top.yaml", scheme="nosuch", mbrt=exe)
    check(False, "an invalid scheme raises ValueError")
except ValueError as e:
    check("--scheme" in str(e) and "nosuch" in str(e), f"ValueError names the option: {e}")
try:
    top.step(-1)
    check(False, "step(-1) raises ValueError")
except ValueError as e:
    check(True, f"step(-1) raises ValueError: {e}")

sys.exit(1 if failures else 0)
