#!/usr/bin/env python3
"""Energy of an `mbrt sim --velocities --out` series, from the model file.

Usage: timing/stress_energy.py MODEL.yaml SERIES.csv STATUS_JSON [OUT.csv]

MODEL.yaml is written by tools/make_spatial.py (flow-style bodies with mass
and principal inertia, gravity). The energy, kinetic plus -m g.r per body, is
computed here from the body states, not by mbrt. Prints one JSON object:
finite, t_reached, energy_initial, max_relative_drift (max |E - E0| / |E0|
over the samples) and final_relative_drift; OUT.csv gets t, relative drift.
"""
import csv
import json
import math
import re
import sys


def bodies_and_gravity(path):
    text = open(path).read()
    gravity = [float(x) for x in re.search(r"gravity: \[([^\]]*)\]", text).group(1).split(",")]
    bodies = [(name, float(mass), [float(x) for x in inertia.split(",")])
              for name, mass, inertia in re.findall(r"name: (\w+), mass: ([^,]+), inertia: \[([^\]]*)\]", text)]
    return bodies, gravity


def energy(row, bodies, gravity):
    e = 0.0
    for name, m, j in bodies:
        v = [float(row[name + ".v" + c]) for c in "xyz"]
        w = [float(row[name + ".w" + c]) for c in "xyz"]
        r = [float(row[name + "." + c]) for c in "xyz"]
        e += 0.5 * m * sum(x * x for x in v) + 0.5 * sum(j[i] * w[i] * w[i] for i in range(3))
        e -= m * sum(gravity[i] * r[i] for i in range(3))
    return e


def main():
    model, series, status = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
    out = open(sys.argv[4], "w") if len(sys.argv) > 4 else None
    bodies, gravity = bodies_and_gravity(model)
    e0, drift, last, t = None, 0.0, 0.0, 0.0
    if out:
        out.write("t,relative_drift\n")
    for row in csv.DictReader(open(series)):
        e = energy(row, bodies, gravity)
        if not math.isfinite(e):
            break
        t = float(row["t"])
        e0 = e if e0 is None else e0
        last = (e - e0) / abs(e0)
        drift = max(drift, abs(last))
        if out:
            out.write("%.6g,%.6g\n" % (t, last))
    finite = status.get("status") == "ok"
    print(json.dumps({"finite": finite, "t_reached": t, "energy_initial": e0, "max_relative_drift": drift,
                      "final_relative_drift": last, "ns_per_step": status.get("ns_per_step")}))


if __name__ == "__main__":
    main()
