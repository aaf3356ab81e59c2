#!/usr/bin/env python3
"""Write docs/results.md from the measured files in timing/results/.

Usage: tools/results_page.py   (from anywhere; rewrites docs/results.md)

Every number on the page is read from a file a timing command wrote; the
page names that command and the machine (the *.machine.txt beside each
result). Sections whose files are missing say so.
"""
import csv
import glob
import math
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "timing", "results")
PAGE = os.path.join(ROOT, "docs", "results.md")
LINK = "../timing/results/"


def rows(name):
    path = os.path.join(RESULTS, name)
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def machine(name):
    path = os.path.join(RESULTS, name + ".machine.txt")
    if not os.path.exists(path):
        return ["(no machine file)"]
    with open(path) as f:
        return [line.rstrip("\n") for line in f if line.strip()]


def provenance(out, name):
    lines = machine(name)
    command = [l for l in lines if l.startswith("command: ")]
    if command:
        paragraph(out, "Command: `%s`" % command[0][len("command: "):])
    for line in lines:
        if not line.startswith("command: "):
            out.append("- " + line)
    out.append("")


def paragraph(out, text):
    out.append(text)
    out.append("")


def measured(out, name, command):
    """The rows of NAME.csv, its command and machine written to out; None (and a note) if not measured."""
    data = rows(name + ".csv")
    if data is None:
        paragraph(out, "Not measured yet (`%s`)." % command)
        return None
    provenance(out, name)
    return data


def table(out, header, body):
    out.append("| " + " | ".join(header) + " |")
    out.append("|" + "---|" * len(header))
    for r in body:
        out.append("| " + " | ".join(r) + " |")
    out.append("")


def g(x, digits=3):
    try:
        return "%.*g" % (digits, float(x))
    except ValueError:
        return x


def image(out, name, alt):
    if os.path.exists(os.path.join(RESULTS, name)):
        paragraph(out, "![%s](%s%s)" % (alt, LINK, name))


def ratio_range(runs, column):
    ratios = sorted(float(r[column]) for r in runs if r[column])
    return "%s to %s" % (g(ratios[0]), g(ratios[-1])) if ratios else "-"


def against_pcst(out, data, scheme):
    """Every run of an mbrt scheme with its ratios: whether it is the faster scheme at equal error."""
    runs = [r for r in data if r["engine"] == "mbrt" and r["method"].split(" ")[0] == scheme]
    if not runs:
        return
    paragraph(out, "### %s against staggered-pcst" % scheme)
    paragraph(out, "Each %s run, its time over staggered-pcst's at the same error (below 1 "
              "%s is faster; - where staggered-pcst's curve does not reach that error) and over "
              "MuJoCo's." % (scheme, scheme))
    table(out, ["problem", "method", "h", "error", "ns per step", "time ratio to staggered-pcst",
                "time ratio to MuJoCo"],
          [[r["problem"], r["method"], g(r["h"]), g(r["max_error"], 2) + (" (failed)" if r["failed"] != "0" else ""),
            g(r["ns_per_step"]), g(r["time_ratio_to_staggered_pcst"]) or "-", g(r["time_ratio_to_mujoco"]) or "-"]
           for r in runs])


def growth_slopes(data):
    """Per scheme of chain_growth.csv: its range of links and the log-log slopes of instructions per step."""
    series = {}
    for r in data:
        series.setdefault(r["scheme"], []).append((int(r["links"]), float(r["instructions_per_step"])))
    out = []
    for scheme, points in series.items():
        points.sort()
        if len(points) < 2:
            continue
        (n0, i0), (n1, i1), (n2, i2) = points[0], points[-2], points[-1]
        out.append([scheme, "%d to %d" % (n0, n2), g(math.log(i2 / i0) / math.log(n2 / n0)),
                    g(math.log(i2 / i1) / math.log(n2 / n1))])
    return out


def work_precision(out):
    paragraph(out, "## Peers: work-precision against MuJoCo, Simbody and DART")
    data = measured(out, "work_precision", "timing/work_precision")
    if data is None:
        return
    paragraph(out,
        "Every mbrt scheme at 4 step sizes and every peer integrator at 7, run alternately in one "
        "process (the fastest of the rounds kept), each problem at the euler_updates its line in "
        "timing/CMakeLists.txt lists (several give curves named `SCHEME euK`, as the heavy top's 4 and 1). Error: the largest distance of the observed point "
        "from an independent reference (minimal-coordinate equations by RK4 at 1e-5 s, the closed-form "
        "Lagrange top, the Test Set for IVP Solvers' solution for Andrews' squeezer at t = 0.03 s), see "
        "timing/problems.cpp. On a03_andrews the observed point is the crank's joint F, 7 mm from its "
        "pivot: no error exceeds 0.014 m, and errors of a few mm mean the crank angle is off by tenths "
        "of a radian, no accuracy. Run time: stepping only. The ratio to MuJoCo is the run's time "
        "over the time of the faster MuJoCo integrator at the same error (log-log interpolation of "
        "MuJoCo's curves); below 1 mbrt is faster. The ratio to staggered-pcst is the same against "
        "mbrt's staggered-pcst curve (with the same euler_updates). Runs whose error lies outside the "
        "compared curve's range have no ratio. Full table: [work_precision.txt](%swork_precision.txt)." % LINK)
    paragraph(out,
        "Builds: mbrt's steps as `mbrt sim` compiles them (-O3, AVX2 and FMA where the CPU has them); "
        "MuJoCo 2.2.2, Simbody 3.7 and DART 6.12 are Debian's libraries. Models: the same masses, inertias and "
        "initial states in each engine (timing/peers/); DART (World::step, its semi-implicit Euler, on the "
        "articulated-body forward dynamics in joint coordinates) runs the trees only (A01, the arm, the "
        "chain), not the loops or the heavy top; MuJoCo closes loops with `connect` equality "
        "constraints as stiff as it allows (time constant clamped to two steps, impedance 0.9999), "
        "Simbody with ball constraints projected to a 1e-10 tolerance after each step; Andrews' spring is "
        "a MuJoCo spatial tendon and a Simbody two-point spring, its torque a MuJoCo actuator's constant "
        "bias and a Simbody mobility force. Allocations are "
        "counted by a malloc interposer over the stepping only.")
    problems = curve_table(out, data)
    against_pcst(out, data, "staggered-nps")
    for p in problems:
        image(out, "work_precision_%s.png" % p, p + " work-precision")
    work_precision_trees(out)
    work_precision_spatial(out)
    work_precision_rk8(out)
    tree_costs(out)
    a01_high_precision(out)


def work_precision_spatial(out):
    """timing/work_precision's run on the spatial trees (model-file problems), with the peers built from the files."""
    paragraph(out, "### The spatial trees: 6- and 7-link arms, a 30-link humanoid, a 16-link spatial chain")
    data = measured(out, "work_precision_spatial", "timing/work_precision 3 arm_6,arm_7,humanoid_30,spatial_chain_16 "
                    "staggered-pcst,staggered-tree,midpoint-tree,rk4-tree work_precision_spatial")
    if data is None:
        return
    paragraph(out,
        "The stress suite's spatial trees of revolute joints (tests/models/stress: arm_6, arm_7, humanoid_30, "
        "spatial_chain_16_revolute), released under gravity and run for 0.5 s. Each peer builds the tree from "
        "the same model file (timing/peers/tree_engine.hpp: bodies, joint points and axes, inertias and initial "
        "state, checked against the file's to 1e-9 before the run). Error: the largest distance of one body's "
        "centre of mass (the arms' last link, the humanoid's left hand, the chain's last link) from a reference "
        "sampled every 1 ms, which timing/tree_reference computes with Simbody's error-controlled "
        "Runge-Kutta-Merson at accuracy 1e-12 (timing/references/; it differs from the same at 1e-10 by at most "
        "8.8e-12 m and from MuJoCo's RK4 at 1e-6 s by at most 1.5e-13 m). Each run is compared at the samples "
        "its steps land on. In rk4-tree, midpoint-tree, staggered-tree and staggered-pcst; columns as above. Full table: [work_precision_spatial.txt](%swork_precision_spatial.txt)."
        % LINK)
    problems = curve_table(out, data)
    paragraph(out, "Best mbrt run against MuJoCo's faster integrator at the same error, per problem and scheme "
              "(the goal for the arm class: at most 0.1):")
    body = []
    for p in problems:
        for scheme in ("rk4-tree", "midpoint-tree", "staggered-tree", "staggered-pcst"):
            runs = [r for r in data if r["problem"] == p and r["engine"] == "mbrt" and r["method"] == scheme
                    and r["failed"] == "0" and r["time_ratio_to_mujoco"]]
            if not runs:
                continue
            best = min(runs, key=lambda r: float(r["time_ratio_to_mujoco"]))
            worst = max(runs, key=lambda r: float(r["time_ratio_to_mujoco"]))
            body.append([p, scheme, g(best["time_ratio_to_mujoco"]), g(best["h"]), g(best["max_error"], 2),
                         g(worst["time_ratio_to_mujoco"]), g(worst["h"]), g(worst["max_error"], 2)])
    table(out, ["problem", "scheme", "best ratio to MuJoCo", "at h", "error (m)", "worst ratio", "at h",
                "error (m)"], body)
    against_pcst(out, data, "rk4-tree")
    against_pcst(out, data, "midpoint-tree")
    against_pcst(out, data, "staggered-tree")
    for p in problems:
        image(out, "work_precision_spatial_%s.png" % p, p + " work-precision, spatial trees")


def work_precision_rk8(out):
    """timing/work_precision's run of rk8-tree and rk4-tree on the spatial trees, beside the peers."""
    paragraph(out, "### Eighth order on the spatial trees: rk8-tree and rk4-tree in one run")
    data = measured(out, "work_precision_rk8", "timing/work_precision 5 arm_6,arm_7,humanoid_30,spatial_chain_16 "
                    "rk4-tree,rk8-tree work_precision_rk8")
    if data is None:
        return
    paragraph(out,
        "The same problems, references and peers as above; rk8-tree (docs/staggered-tree.md, \"rk8-tree\") at "
        "32 times the others' steps. Each mbrt run's time over MuJoCo's faster integrator at the same error "
        "(the goal for the arm class at 1e-6 m: at most 0.1; - where MuJoCo's curves do not reach that error). "
        "Full table: [work_precision_rk8.txt](%swork_precision_rk8.txt)." % LINK)
    runs = [r for r in data if r["engine"] == "mbrt"]
    table(out, ["problem", "scheme", "h", "error (m)", "ns per step", "time ratio to MuJoCo"],
          [[r["problem"], r["method"], g(r["h"]), g(r["max_error"], 2) + (" (failed)" if r["failed"] != "0" else ""),
            g(r["ns_per_step"]), g(r["time_ratio_to_mujoco"]) or "-"] for r in runs])
    for p in sorted({r["problem"] for r in data}):
        image(out, "work_precision_rk8_%s.png" % p, p + " work-precision, rk8-tree and rk4-tree")


def a01_high_precision(out):
    """timing/work_precision's run of A01 over 2000 s: the cheapest run of each method within 1e-3 m."""
    paragraph(out, "### A01 at the IFToMM benchmark's high precision: 1e-3 m over 2000 s")
    data = measured(out, "work_precision_a01_2000s", "timing/work_precision 3 a01_2000s all work_precision_a01_2000s")
    if data is None:
        return
    paragraph(out,
        "A01 (a 1 kg bob on a massless 1 m bar, released horizontal) over 2000 s, compared every 0.5 s with "
        "the minimal-coordinate equation by RK4 at 1e-4 s (reference_solutions.hpp, which "
        "tests/test_a01_pendulum.cpp checks against the benchmark's published values). The absolute-coordinate "
        "schemes run tests/models/a01_pendulum.yaml (a particle on a distance joint), the tree schemes "
        "tests/models/a01_revolute.yaml (the bob on a revolute joint, 1e-12 kg m^2 of its own, as in MuJoCo's "
        "model). Per method, the largest step whose run stays within 1e-3 m, its CPU time per simulated "
        "second, and that time over MuJoCo's best (the goal: at most 0.1). Full table: "
        "[work_precision_a01_2000s.txt](%swork_precision_a01_2000s.txt)." % LINK)
    best = {}
    for r in data:
        if r["failed"] != "0" or r["max_error"] in ("", "nan") or float(r["max_error"]) > 1e-3:
            continue
        key = (r["engine"], r["method"])
        cost = float(r["run_s"]) / 2000.0
        if key not in best or cost < best[key][0]:
            best[key] = (cost, r)
    mujoco = min((c for (e, _), (c, _) in best.items() if e == "mujoco"), default=None)
    body = []
    for (engine, method), (cost, r) in sorted(best.items(), key=lambda kv: kv[1][0]):
        body.append([engine, method, g(r["h"]), g(r["max_error"], 2), g(r["ns_per_step"]), g(cost * 1e6),
                     g(cost / mujoco) if mujoco else ""])
    table(out, ["engine", "method", "largest h within 1e-3 m", "error (m)", "ns per step",
                "CPU us per simulated s", "over MuJoCo's best"], body)


def tree_costs(out):
    """timing/tree_costs: flops and instructions per step and per body of the spatial trees."""
    paragraph(out, "### Flops and instructions per body of the trees")
    data = measured(out, "tree_costs", "timing/tree_costs")
    if data is None:
        return
    paragraph(out,
        "`mbrt gen MODEL --scheme S --report`: floating-point operations counted in the generated step (a fused "
        "multiply-add as two) and instructions per step by callgrind in the compiled program. Targets: at most "
        "500 flops per body on spatial revolute arms and chains, 200 on planar chains, instructions at most 1.5 "
        "times the flops. A scheme written `SCHEME:on_demand` was generated with `--body-states on_demand`: its "
        "step leaves the bodies' world states to `refresh_bodies()` (docs/staggered-tree.md, \"Body states on "
        "demand\"). Rows of schemes an earlier run measured are kept; the flop counts do not depend on the "
        "machine or its load.")
    table(out, ["model", "made by", "bodies", "scheme", "flops per step", "flops per body",
                "instructions per step", "instructions per flop"],
          [[r["model"], "`%s`" % r["made_by"], r["bodies"], r["scheme"], r["flops_per_step"], r["flops_per_body"],
            g(r["instructions_per_step"]) if r["instructions_per_step"] else "-",
            r["instructions_per_flop"] or "-"] for r in data])


def work_precision_trees(out):
    """timing/work_precision's run of the tree schemes on the trees, against staggered-pcst and the peers."""
    paragraph(out, "### midpoint-tree and staggered-tree on the trees")
    data = measured(out, "work_precision_trees", "timing/work_precision 3 arm_3,chain_10 "
                    "staggered-pcst,staggered-tree,midpoint-tree work_precision_trees")
    if data is None:
        return
    paragraph(out,
        "The problems whose models are trees of revolute joints (the 3-link arm and the 10-link chain), "
        "in midpoint-tree, staggered-tree and staggered-pcst and the peers' integrators, in one run of its "
        "own (so the ratios compare runs of that process only); columns as above. Full table: "
        "[work_precision_trees.txt](%swork_precision_trees.txt)." % LINK)
    problems = curve_table(out, data)
    against_pcst(out, data, "midpoint-tree")
    against_pcst(out, data, "staggered-tree")
    for p in problems:
        image(out, "work_precision_trees_%s.png" % p, p + " work-precision, the tree schemes")


def curve_table(out, data):
    """One row per problem and curve (engine, method): error range, cost, ratios at equal error."""
    header = ["problem", "engine", "method", "error range", "ns per step", "allocations per step",
              "time ratio to MuJoCo at equal error", "time ratio to staggered-pcst at equal error"]
    body = []
    problems = []
    for r in data:
        if r["problem"] not in problems:
            problems.append(r["problem"])
    for p in problems:
        curves = []
        for r in data:
            if r["problem"] == p and (r["engine"], r["method"]) not in curves:
                curves.append((r["engine"], r["method"]))
        for engine, method in curves:
            runs = [r for r in data if r["problem"] == p and r["engine"] == engine and r["method"] == method]
            good = [r for r in runs if r["failed"] == "0"]
            failed = len(runs) - len(good)
            errors = sorted(float(r["max_error"]) for r in good)
            ns = sorted(float(r["ns_per_step"]) for r in good)
            allocs = sorted(float(r["allocations_per_step"]) for r in runs)
            body.append([
                p, engine, method,
                ("%s to %s" % (g(errors[0], 2), g(errors[-1], 2)) if errors else "-") +
                (" (%d failed)" % failed if failed else ""),
                "%s to %s" % (g(ns[0]), g(ns[-1])) if ns else "-",
                g(allocs[-1]) if allocs[0] == allocs[-1] else "%s to %s" % (g(allocs[0]), g(allocs[-1])),
                ratio_range(good, "time_ratio_to_mujoco"),
                ratio_range(good, "time_ratio_to_staggered_pcst"),
            ])
    table(out, header, body)
    return problems


def wcet(out):
    paragraph(out, "## Worst-case timing")
    files = sorted(f for f in glob.glob(os.path.join(RESULTS, "wcet_*.csv"))
                   if not f.endswith("_instructions.csv") and "_hist_" not in f)
    if not files:
        paragraph(out, "Not measured yet (`timing/wcet MODEL.yaml`).")
        return
    paragraph(out,
        "Per-step times of `step()` (steady clock around each call; `timer` is the cost of reading it), "
        "warm, with the caches evicted before every step (64 MB written), warm under `stress-ng` "
        "on every core, and (`realtime_loaded`) under the same load at `SCHED_FIFO` priority 80, pinned "
        "to one CPU with memory locked, as `mbrt hil --fifo 80 --cpu N` runs; the instructions of 200 sampled steps counted by callgrind, each step alone. "
        "The machine is a shared virtual machine without isolated cores, so even at real-time "
        "priority the largest times include the hypervisor's preemption; the instruction count is the figure "
        "that does not depend on the machine.")
    for f in files:
        tag = os.path.basename(f)[:-4]
        paragraph(out, "### %s" % tag[len("wcet_"):])
        provenance(out, tag)
        data = rows(tag + ".csv")
        table(out, ["mode", "steps", "failed", "timer ns", "min ns", "median ns", "p99 ns", "p99.99 ns",
                    "max ns", "max / median", "p99.99 / median"],
              [[r["mode"], r["steps"], r["failed"], r["timer_ns"], r["min_ns"], r["median_ns"], r["p99_ns"],
                r["p99_99_ns"], r["max_ns"], r["max_over_median"], r["p99_99_over_median"]] for r in data])
        counts = rows(tag + "_instructions.csv")
        if counts:
            c = counts[0]
            paragraph(out, "Instructions per step (callgrind): %s sampled steps, min %s, max %s, %s distinct value%s." % (
                c["sampled_steps"], c["min_instructions"], c["max_instructions"], c["distinct_counts"],
                "" if c["distinct_counts"] == "1" else "s"))
        image(out, tag + "_hist.png", tag + " histogram")


def stability(out):
    paragraph(out, "## Stability")
    paragraph(out, "### Long runs")
    data = measured(out, "stability_long_runs", "timing/stability")
    if data is not None:
        paragraph(out,
            "Drifts are computed by timing/stability.cpp from the body states and the model files' "
            "inertias: energy |E - E0|, angular momentum |L - L0| (heavy top: vertical component about the "
            "fixed point; tumbling body: the world vector), largest | |p| - 1 |, largest position "
            "violation; flips: sign changes of the body-y rate, sampled 1000 times (a lower bound).")
        table(out, ["model", "scheme", "h", "steps", "t end (s)", "failed steps", "energy drift (J)",
                    "momentum drift", "| |p| - 1 |", "position violation (m)", "flips", "ns per step"],
              [[r["model"], r["scheme"], r["h"], r["steps"], g(r["t_end"]), r["failed_steps"],
                r["max_energy_drift_J"], r["max_momentum_drift"], r["max_quaternion_norm_error"],
                r["max_position_violation"], r["intermediate_axis_flips"], r["ns_per_step"]] for r in data])
        for m in sorted({r["model"] for r in data}):
            image(out, "stability_%s.png" % m, m + " drift")
    paragraph(out, "### Stress suite: spatial arms, chains and a spinning body")
    data = measured(out, "stability_stress", "timing/stability_stress")
    if data is not None:
        paragraph(out,
            "Conservative models of tools/make_spatial.py (docs/stability.md), every mbrt scheme and "
            "MuJoCo's and Simbody's fixed-step integrators (timing/peer_stability.cpp) on the same model. "
            "Energy from the body states (timing/stress_energy.py, peer_stability); drift: the largest "
            "|E - E0| / |E0| over the run; t reached: when the state stopped being finite, or the end. "
            "staggered-tree runs only the models on revolute joints (the arms and the revolute chains). "
            "Rows of an earlier run that the last one did not redo are kept; the machine lines marked "
            "`earlier run` are that run's, and ns per step compare only within one run.")
        table(out, ["model", "engine", "h", "finite", "t reached (s)", "largest drift", "drift at the end",
                    "ns per step"],
              [[r["model"], r["engine"], r["h"], r["finite"], g(r["t_reached"]), g(r["max_relative_drift"]),
                g(r["final_relative_drift"]), g(r["ns_per_step"])] for r in data])
        steps = rows("stability_stress_steps.csv")
        if steps is not None:
            paragraph(out, "The largest step tried that stays finite with the energy within 2 %:")
            table(out, ["model", "engine", "largest step"],
                  [[r["model"], r["engine"], r["largest_step_within_2_percent"]] for r in steps])
        for m in sorted({r["model"] for r in data}):
            image(out, "stability_stress_%s.png" % m, m + " energy at 1 ms")
    paragraph(out, "### Largest stable step")
    data = measured(out, "stable_step", "timing/stable_step")
    if data is not None:
        paragraph(out,
            "Stable: every step `ok`, |E(T) - E(0)| <= 1% of |E(0)| and position violation <= 1e-3 m "
            "(timing/stable_step doubles the step until a run fails, then bisects twice in log h).")
        table(out, ["model", "scheme", "largest stable h", "first unstable h", "energy drift at it (J)",
                    "violation at it (m)"],
              [[r["model"], r["scheme"], r["largest_stable_h"], r["first_unstable_h"],
                r["energy_drift_at_stable_J"], r["violation_at_stable_m"]] for r in data])
    paragraph(out, "### Cost against size")
    data = measured(out, "chain_growth", "timing/chain_growth")
    if data is not None:
        paragraph(out,
            "The planar chain of tools/make_chain.py at h = 1e-4 s in mbrt's schemes and, beside them, "
            "MuJoCo's, Simbody's and DART's fixed-step integrators on the same chain (timing/peer_chain_step.cpp; "
            "`ENGINE-METHOD`, in joint coordinates, so no constraint rows; staggered-tree steps the joint "
            "angles too). Instructions per step by callgrind "
            "from runs of K and 2K steps (mbrt K = 200, peers K = 20); ns per step over 20000 steps for mbrt, "
            "2000 for the peers. Rows of schemes the last run did not run are an earlier run's (the machine "
            "lines marked `earlier run`).")
        table(out, ["links", "scheme", "constraint rows", "instructions per step", "ns per step"],
              [[r["links"], r["scheme"], r["constraint_rows"], r["instructions_per_step"], g(r["ns_per_step"])]
               for r in data])
        image(out, "chain_growth.png", "cost against chain length")
        paragraph(out, "How each grows: the log-log slope of instructions per step against links (1 is "
                  "linear, 2 quadratic), over the whole range measured and between its two largest chains.")
        table(out, ["scheme", "links", "slope, whole range", "slope, two largest"], growth_slopes(data))
    spatial = measured(out, "chain_growth_spatial", "timing/chain_growth_spatial")
    if spatial is not None:
        paragraph(out,
            "Spatial revolute chains (`tools/make_spatial.py chain N --joint revolute`, consecutive axes at "
            "general angles) at h = 1e-3 s in mbrt's tree schemes and staggered-pcst and in the peers, each "
            "building the chain from the same model file (timing/peer_stability). Instructions per step by "
            "callgrind from runs of K and 2K steps (mbrt K = 200, peers K = 20); ns per step over 20000 steps "
            "for mbrt, 2000 for the peers.")
        table(out, ["links", "engine", "instructions per step", "ns per step"],
              [[r["links"], r["engine"], r["instructions_per_step"], g(r["ns_per_step"])] for r in spatial])
        image(out, "chain_growth_spatial.png", "cost against spatial chain length")
    check = rows("chain_growth_check.csv")
    if check is not None:
        paragraph(out, "Same chain in every engine: the tip of the 10-link chain after 0.2 s "
                  "(timing/chain_growth stops if a peer's is more than 1e-3 m from mbrt's).")
        table(out, ["engine", "tip x (m)", "tip y (m)", "distance to mbrt (m)"],
              [[r["engine"], g(r["tip_x"], 9), g(r["tip_y"], 9), g(r["distance_to_mbrt"], 2)] for r in check])


def specializations(out):
    paragraph(out, "## Specializations and the cost of a step")
    paragraph(out, "What the generator's specializations save (docs/specializations.md): floating-point operations "
               "and instructions per `step()` counted by `mbrt gen --report` in the compiled sim program under "
               "callgrind, as specialized, with `--no-specialize` (general) and with each specialization that applies "
               "turned off alone (`without NAME`); `check` is the instruction count of "
               "`timing/instructions_per_step`, an independent route to the same figure; the predicted time is "
               "the count times the calibration below, the measured one is `mbrt sim`'s (median of 3 runs; the "
               "machine is shared, so measured times vary far more than the counts).")
    data = measured(out, "specialization_counts", "timing/specialization_counts")
    if data is not None:
        table(out, ["model", "scheme", "variant", "flops per step", "instructions per step", "check",
                    "source bytes", "executable bytes", "predicted ns", "measured ns"],
              [[r["model"], r["scheme"], r["variant"], r["flops_per_step"], r["instructions_per_step"],
                r["instructions_per_step_check"] or "-", r["source_bytes"], r["executable_bytes"],
                r["predicted_ns_per_step"] or "-", r["ns_per_step"] or "-"] for r in data])
        by_model = {}
        for r in data:
            by_model.setdefault(r["model"], {})[r["variant"]] = r
        ratios = [[m, g(float(v["specialized"]["flops_per_step"]) / float(v["general"]["flops_per_step"])),
                   g(float(v["specialized"]["instructions_per_step"]) / float(v["general"]["instructions_per_step"]))]
                  for m, v in by_model.items() if "specialized" in v and "general" in v]
        paragraph(out, "Specialized over general:")
        table(out, ["model", "flops", "instructions"], ratios)
        saved = [[m, variant[len("without "):],
                  str(int(r["flops_per_step"]) - int(v["specialized"]["flops_per_step"])),
                  str(int(r["instructions_per_step"]) - int(v["specialized"]["instructions_per_step"]))]
                 for m, v in by_model.items() for variant, r in v.items() if variant.startswith("without ")]
        paragraph(out, "Per step, what each specialization saves on its own (the model with only that one "
                   "turned off, `--no-specialize=NAME`, minus the specialized model):")
        table(out, ["model", "specialization", "flops saved", "instructions saved"], saved)
    paragraph(out, "### Calibration of the predicted step time")
    data = measured(out, "flop_calibration", "timing/flop_calibration")
    if data is not None:
        table(out, ["model", "scheme", "flops per step", "ns per step", "ns per flop"],
              [[r["model"], r["scheme"], r["flops_per_step"], g(r["ns_per_step"]), g(r["ns_per_flop"])] for r in data])
    paragraph(out, "### Generation and compile time of large models")
    paragraph(out, "Wall times depend on the other jobs on the machine; CPU time (user + system) much less.")
    data = measured(out, "generation_scale", "timing/generation_scale")
    if data is not None:
        table(out, ["model", "bodies", "constraint rows", "mbrt gen wall (s)", "mbrt gen CPU (s)", "source bytes",
                    "compile wall (s)", "compile CPU (s)", "object bytes"],
              [[r["model"], r["bodies"], r["constraint_rows"], g(r["gen_wall_s"]), g(r["gen_cpu_s"]),
                r["source_bytes"], g(r["compile_wall_s"]), g(r["compile_cpu_s"]), r["object_bytes"]] for r in data])


# The fuzz targets (fuzz/README.md): name, what it fuzzes.
FUZZERS = [("model_parser", "Model-file parser"),
           ("can_udp_wire", "CAN-over-UDP datagram decoder"),
           ("can_command", "CAN command path: frames, assembler, gate"),
           ("lcm_command", "LCM command path: decode, gate")]
# File extensions of tests/fuzz_regressions/, one per target.
REGRESSION_EXTENSIONS = ["yaml", "can_udp", "can_frames", "lcm_commands"]


def fuzz_run(out, name, what):
    paragraph(out, "### %s (`%s_fuzzer`)" % (what, name))
    path = os.path.join(RESULTS, "fuzz_%s.txt" % name)
    if not os.path.exists(path):
        paragraph(out, "No long run recorded yet (`fuzz/run 600 build-fuzz %s_fuzzer`)." % name)
        return
    provenance(out, "fuzz_" + name)
    with open(path) as f:
        lines = [l.strip() for l in f]
    stats = [l for l in lines if l.startswith("stat::") or "Done " in l]
    failures = [l for l in lines if l.startswith("SUMMARY") or "Test unit written" in l]
    if stats:
        paragraph(out, "Last long run: " + "; ".join(stats) + ".")
    paragraph(out, "Failures in it: " + ("; ".join(failures) if failures else "none") + ".")


def bad_inputs(out):
    paragraph(out, "## Bad inputs")
    paragraph(out, "The model-file parser and the message decoders of the HIL loop are fuzzed by libFuzzer with "
               "AddressSanitizer and UndefinedBehaviorSanitizer (fuzz/README.md): in a test run configured "
               "with -DMBRT_TEST_FUZZ=ON the parser for 40 s and each decoder for 10 s (ctest `fuzz_*`), longer "
               "with `fuzz/run SECONDS`; every test run replays the inputs that once failed (`test_fuzz_regressions`).")
    for name, what in FUZZERS:
        fuzz_run(out, name, what)
    found = sorted(os.path.basename(p) for ext in REGRESSION_EXTENSIONS
                   for p in glob.glob(os.path.join(ROOT, "tests", "fuzz_regressions", "*." + ext)))
    out.append("Inputs a fuzzer failed on, now regression tests (`test_fuzz_regressions`, "
               "tests/fuzz_regressions/README.md): %s." % (", ".join("`%s`" % f for f in found) if found else "none"))
    out.append("")
    paragraph(out, "Runtime bad inputs (a NaN or absurd value in the state or an input, a diverging step) return "
               "a status and leave the last good state: tests/test_bad_numbers.cpp.")


def hil_deadlines(out):
    """The loop's deadline table, as timing/hil_deadlines wrote it (a page of its own)."""
    path = os.path.join(RESULTS, "hil_deadlines.md")
    if not os.path.exists(path):
        paragraph(out, "## HIL loop deadlines")
        paragraph(out, "Not measured yet (`timing/hil_deadlines`).")
        return
    with open(path) as f:
        lines = [line.rstrip("\n") for line in f]
    out.append("## HIL loop deadlines")  # its own title, one level down
    out.extend(lines[1:])
    out.append("")


def parallel_speedup(out):
    """timing/parallel_speedup: the parallel step against the serial one."""
    paragraph(out, "## The parallel step")
    data = measured(out, "parallel_speedup", "timing/parallel_speedup")
    if data is None:
        return
    paragraph(out,
        "docs/parallel.md. staggered-pcst at 1 ms. Per model and parts: median ns per step over the rounds of the "
        "serial program (one part), the parallel program with its workers and the same program on one thread "
        "(`--serial`: the partition's elimination order alone); the speed-up serial / parallel; the slowest step "
        "of each over all rounds (`--every 1`); the interface's blocks and rows and the parts' rows "
        "(`gen --report`). The machine line above gives what two threads gain on plain arithmetic here "
        "(`timing/parallel_ceiling`), which bounds the speed-ups.")
    table(out, ["model", "parts", "rows", "interface (blocks, rows)", "parts' rows", "serial ns", "parallel ns",
                "parallel on one thread ns", "speed-up", "slowest serial step ns", "slowest parallel step ns"],
          [[r["model"], r["parts"], r["constraint_rows"], "%s, %s" % (r["interface_blocks"], r["interface_rows"]),
            r["part_rows"].replace("/", ", "), g(r["serial_ns"]), g(r["parallel_ns"]),
            g(r["parallel_on_one_thread_ns"]), r["speedup"], g(r["serial_max_ns"]), g(r["parallel_max_ns"])]
           for r in data])
    image(out, "parallel_speedup.png", "speed-up of the parallel step over the serial one")
    interface = rows("parallel_interface.csv")
    if interface is None:
        return
    if os.path.exists(os.path.join(RESULTS, "parallel_interface.machine.txt")):
        provenance(out, "parallel_interface")
    paragraph(out,
        "The interface by preconditioned conjugate gradients against its factor (the command just above): median ns per "
        "step on one thread (`--serial`, the methods' work), the largest velocity violation, and the largest "
        "difference of the final positions and velocities from the factorized interface's.")
    table(out, ["model", "parts", "interface rows", "method", "iterations", "preconditioner", "ns per step",
                "largest velocity violation", "difference from the factor"],
          [[r["model"], r["parts"], r["interface_rows"], r["method"], r["iterations"] if r["method"] == "pcg" else "-",
            r["preconditioner"] if r["method"] == "pcg" else "-", g(r["ns_per_step"]), g(r["max_velocity_violation"]),
            g(r["difference_from_factor"])] for r in interface])


def main():
    out = ["# Results", "",
           "Generated by `tools/results_page.py` from the files in [timing/results/](%s); do not edit. "
           "Each section names the command that produced its files and the machine it ran on. "
           "The machine is shared and noisy: compare times as ratios within one run." % LINK, ""]
    work_precision(out)
    wcet(out)
    hil_deadlines(out)
    stability(out)
    parallel_speedup(out)
    specializations(out)
    bad_inputs(out)
    with open(PAGE, "w") as f:
        f.write("\n".join(out).rstrip("\n") + "\n")


if __name__ == "__main__":
    main()
