#!/usr/bin/env python3
"""`mbrt sweep` on a pendulum whose gravity and mass are runtime parameters
(tests/models/sweep_pendulum.yaml: 1 m, released from rest at 0.05 rad).

usage: test_sweep.py MBRT MODELS_DIR WORK_DIR EXECUTOR...

With the first executor: a grid and a Monte Carlo sweep, every row checked
against closed forms (initial energy -m g cos 0.05; bob.x at t_end against
the small-angle solution sin(0.05 cos(sqrt(g) t))); failures as rows; an
interrupted sweep resumed (a killed driver, and a journal cut mid-line with a
result written twice) giving the uninterrupted table; command-line errors.
Every further executor must give the identical tables (ns_per_step, a
timing, aside). Exit 77 (skipped) without numpy, or without Dask for dask.
"""
import csv
import json
import math
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

try:
    import numpy  # noqa: F401  (the sweep's sampling)
except ImportError:
    print("skipped: numpy is missing (Debian: apt-get install python3-numpy)")
    sys.exit(77)

mbrt, models, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
executors = sys.argv[4:]
if "dask" in executors:
    try:
        import distributed  # noqa: F401
    except ImportError:
        print("skipped: Dask is missing (Debian: apt-get install python3-distributed)")
        sys.exit(77)
model = models / "sweep_pendulum.yaml"
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
# The tests' one compile cache where ctest sets it: the pendulum's program
# is compiled once for the executors' tests.
CACHE = pathlib.Path(os.environ.get("MBRT_TEST_CACHE_DIR") or work / "cache")
os.environ["MBRT_CACHE_DIR"] = str(CACHE)
THETA0, T_END = 0.05, 0.5
TIMING = "ns_per_step"
GRID = ["--grid", "gravity.y=-1.62,-9.81,-24.79,bob.mass=0.5:2:4"]
MONTE_CARLO = ["--samples", "6", "--distribution", "gravity.y=uniform(-25,-1),bob.mass=lognormal(0,0.5)", "--seed", "7"]
COMMON = ["--t-end", str(T_END), "--outputs", "bob.x,bob.y"]
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    failures += not ok


def sweep(out, *args, executor="local"):
    r = subprocess.run([mbrt, "sweep", str(model), "--out", str(work / out), "--executor", executor, "--workers", "2",
                        *args], capture_output=True, text=True)
    return r


def table(out):
    with open(work / out / "results.csv", newline="") as f:
        return list(csv.DictReader(f))


def without_timing(rows):
    return [{k: v for k, v in r.items() if k != TIMING} for r in rows]


def check_against_closed_forms(rows, what):
    worst_x = worst_e = 0.0
    steps = {r["steps"] for r in rows}
    check(steps == {str(round(T_END / 1e-3))}, f"{what}: every sample ran {round(T_END / 1e-3)} steps ({steps})")
    for r in rows:
        g, m = -float(r["gravity.y"]), float(r["bob.mass"])
        if r["status"] != "ok":
            check(False, f"{what}: sample {r['sample']} ok ({r['status']}: {r['message']})")
            continue
        worst_e = max(worst_e, abs(float(r["energy_initial"]) + m * g * math.cos(THETA0)) / (m * g))
        worst_x = max(worst_x, abs(float(r["bob.x"]) - math.sin(THETA0 * math.cos(math.sqrt(g) * T_END))))
    check(worst_e < 1e-12, f"{what}: initial energy -m g cos(theta0) of every sample's own m and g (worst {worst_e:.1e})")
    check(worst_x < 2e-4, f"{what}: bob.x at t_end within 2e-4 m of the small-angle solution (worst {worst_x:.1e} m)")


def run_checked(out, args, executor):
    r = sweep(out, *args, *COMMON, executor=executor)
    check(r.returncode == 0, f"{executor} {out}: exit 0 ({r.returncode}: {r.stderr.strip()[-300:]})")
    summary = json.loads(r.stdout.splitlines()[-1])
    rows = table(out)
    check(summary["finished"] == summary["samples"] == len(rows), f"{executor} {out}: every sample finished, once")
    check([int(x["sample"]) for x in rows] == list(range(len(rows))), f"{executor} {out}: rows in sample order")
    check_against_closed_forms(rows, f"{executor} {out}")
    return rows


first = executors[0]
grid = run_checked("grid", GRID, first)
check(len(grid) == 12 and {(x["gravity.y"], x["bob.mass"]) for x in grid} ==
      {(g, m) for g in ("-1.62", "-9.81", "-24.79") for m in ("0.5", "1.0", "1.5", "2.0")}, "the grid's 12 combinations")
monte_carlo = run_checked("monte_carlo", MONTE_CARLO, first)
masses = [float(x["bob.mass"]) for x in monte_carlo]
check(len(set(masses)) == 6 and all(-25 <= float(x["gravity.y"]) <= -1 for x in monte_carlo),
      "Monte Carlo: 6 distinct samples, gravity within its uniform range")

if first == "local":
    # The same seed draws the same samples; another seed others.
    sweep("monte_carlo_again", *MONTE_CARLO, *COMMON)
    check(without_timing(table("monte_carlo_again")) == without_timing(monte_carlo), "the same seed, the same table")
    sweep("monte_carlo_seed8", *MONTE_CARLO[:-1], "8", *COMMON)
    check(float(table("monte_carlo_seed8")[0]["bob.mass"]) not in masses, "another seed, other samples")

    # Failures are data: a diverging sample and one the program refuses (a start off the bar) are rows.
    x0 = repr(math.sin(THETA0))
    r = sweep("failures", "--grid", f"gravity.y=-9.81,-1e300,bob.position.x={x0},0.5", *COMMON)
    rows = {(x["gravity.y"], x["bob.position.x"]): x for x in table("failures")} if r.returncode == 0 else {}
    check(r.returncode == 0 and len(rows) == 4, f"a sweep with failing samples finishes ({r.returncode}: {r.stderr[-300:]})")
    if rows:
        check(rows[("-9.81", x0)]["status"] == "ok", "the good sample is ok")
        diverged = rows[("-1e+300", x0)]
        check(diverged["status"] == "non_finite" and diverged["bob.x"] == "",
              f"the diverging sample is non_finite, without outputs ({diverged['status']}: {diverged['message']})")
        refused = rows[("-9.81", "0.5")]
        check(refused["status"] == "refused" and "violates the joints" in refused["message"],
              f"the start off the bar is refused with the program's message ({refused['status']}: {refused['message']})")

    # Interrupted: the driver killed while samples run, then the same command again.
    many = ["--samples", "40", "--distribution", "gravity.y=uniform(-25,-1),bob.mass=uniform(0.5,2)", "--seed", "3"]
    p = subprocess.Popen([mbrt, "sweep", str(model), "--out", str(work / "killed"), "--workers", "1", *many, *COMMON],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    journal = work / "killed" / "journal" / "driver.jsonl"
    while p.poll() is None and (not journal.exists() or journal.read_bytes().count(b"\n") < 5):
        time.sleep(0.002)
    os.killpg(p.pid, signal.SIGKILL)
    p.wait()
    killed_after = journal.read_bytes().count(b"\n")
    print(f"     (killed after {killed_after} of 40 samples)")
    r = sweep("killed", *many, *COMMON, executor="local")
    check(r.returncode == 0 and f"resuming, {killed_after} of 40" in r.stderr,
          f"the rerun resumes after the {killed_after} finished samples ({r.returncode}: {r.stderr[-300:]})")
    sweep("uninterrupted", *many, *COMMON)
    check(without_timing(table("killed")) == without_timing(table("uninterrupted")),
          "the resumed table equals an uninterrupted one")

    # A journal cut mid-line by a crash, with one result also in a second journal file.
    cut = work / "cut"
    shutil.copytree(work / "grid", cut)
    (cut / "results.csv").unlink()
    lines = (cut / "journal" / "driver.jsonl").read_text().splitlines(keepends=True)
    (cut / "journal" / "driver.jsonl").write_text("".join(lines[:5]) + lines[5][:40])
    (cut / "journal" / "slurm-1-0.jsonl").write_text(lines[0])
    r = sweep("cut", *GRID, *COMMON)
    check(r.returncode == 0 and "resuming, 5 of 12" in r.stderr, f"resumes after the 5 whole lines ({r.stderr[-300:]})")
    resumed = table("cut")
    check(without_timing(resumed) == without_timing(grid), "the resumed table equals the uninterrupted one")
    kept = {json.loads(x)["sample"] for x in lines[:5]}
    check(all(a[TIMING] == b[TIMING] for a, b in zip(resumed, grid) if int(a["sample"]) in kept),
          "the finished samples were kept, not run again")
    journal_lines = (cut / "journal" / "driver.jsonl").read_text().splitlines()
    check(sorted(json.loads(x)["sample"] for x in journal_lines) == list(range(12)),
          "the cut line was dropped; each sample journaled once")

    # Command-line errors: exit 2 naming the option or key.
    for args, expect, what in [
            (["--grid", "bob.nosuch=1,2"], "bob.nosuch", "an unknown parameter"),
            (["--grid", "gravity.y=1:2"], "--grid", "a range without a count"),
            (["--distribution", "bob.mass=poisson(1)", "--samples", "2"], "poisson", "an unknown distribution"),
            (["--distribution", "bob.mass=uniform(1,2)"], "--samples", "--distribution without --samples"),
            (["--grid", "bob.mass=1", "--outputs", "bob.nosuch"], "bob.nosuch", "an unknown output column"),
            (["--grid", "bob.mass=1", "--scheme", "nosuch"], "nosuch", "an unknown scheme"),
            (["--grid", "bob.mass=1", "--executor", "nosuch"], "--executor", "an unknown executor")]:
        r = sweep("errors", *args)
        check(r.returncode == 2 and expect in r.stderr, f"{what}: exit 2 naming '{expect}' ({r.returncode}: "
                                                        f"{r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ''})")
    r = sweep("grid", "--grid", "gravity.y=-1.62", *COMMON)
    check(r.returncode == 2 and "another sweep" in r.stderr, "another spec in a sweep's out directory: exit 2")

    # mbrt build: the cached program's path, compiled once.
    r = subprocess.run([mbrt, "build", str(model)], capture_output=True, text=True)
    program = pathlib.Path(r.stdout.strip())
    check(r.returncode == 0 and os.access(program, os.X_OK) and str(CACHE) in str(program),
          f"mbrt build prints the cached program ({r.stdout.strip()})")
    check("compiling" not in r.stderr, "mbrt build took it from the cache")
    r = subprocess.run([mbrt, "build", str(model), "--program", "nosuch"], capture_output=True, text=True)
    check(r.returncode == 2 and "--program" in r.stderr, "mbrt build --program nosuch: exit 2 naming --program")

if first == "dask":
    # A running cluster, given by its scheduler's address: a scheduler and a worker started here, the
    # worker importing mbrt.sweep from PYTHONPATH as a real cluster's would.
    scheduler_file = work / "scheduler.json"
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(__file__).resolve().parents[2] / "python"))
    cluster = [subprocess.Popen([sys.executable, "-m", f"distributed.cli.dask_{p}", *args, "--no-dashboard",
                                 "--scheduler-file", str(scheduler_file)], env=env, stderr=subprocess.DEVNULL)
               for p, args in (("scheduler", ["--host", "127.0.0.1", "--port", "0"]), ("worker", ["--nthreads", "2"]))]
    try:
        while not scheduler_file.exists():
            time.sleep(0.1)
        time.sleep(0.5)  # the file is written whole once the scheduler listens
        address = json.loads(scheduler_file.read_text())["address"]
        r = sweep("monte_carlo_scheduler", *MONTE_CARLO, *COMMON, "--scheduler", address, executor="dask")
        check(r.returncode == 0 and without_timing(table("monte_carlo_scheduler")) == without_timing(monte_carlo),
              f"dask --scheduler {address}: the same table ({r.returncode}: {r.stderr[-300:]})")
    finally:
        for process in cluster:
            process.terminate()
            process.wait()

for executor in executors[1:]:
    check(without_timing(run_checked(f"grid_{executor}", GRID, executor)) == without_timing(grid),
          f"{executor}: the grid's table equals {first}'s")
    check(without_timing(run_checked(f"monte_carlo_{executor}", MONTE_CARLO, executor)) == without_timing(monte_carlo),
          f"{executor}: the Monte Carlo table equals {first}'s for the same seed")

print(f"{failures} failures")
sys.exit(1 if failures else 0)
