#!/usr/bin/env python3
"""`mbrt sweep --hil` on the demo arm: a HIL scenario sweep over the stub's
drop probability, each sample a closed loop of `mbrt hil` and `mbrt stub` in
its own private network namespace.

usage: test_hil_sweep.py MBRT MODEL WORK_DIR CACHE_DIR

Checks from the merged table, as tests/hil/closed_loop.py does from the two
reports: without faults every command sent is applied and nothing is
rejected; with drops, the loop counts as missing what the controller
dropped; the controller tracks its reference in both; and a probability the
stub refuses (1.5) is a row with its message, not a failed sweep. Exit 77
(skipped) where private network namespaces are not permitted.
"""
import csv
import math
import os
import pathlib
import shutil
import subprocess
import sys

mbrt, model, tunable_model, work, cache = sys.argv[1:6]
namespace = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "in-private-network"
if subprocess.run([str(namespace), "true"]).returncode == 77:
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.environ["MBRT_CACHE_DIR"] = cache  # shared with the hil_* tests: the programs are compiled once
AMPLITUDE = 0.5
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    failures += not ok


# Generous command timeouts, as closed_loop.py's: a busy machine must not turn into rejections.
r = subprocess.run([mbrt, "sweep", model, "--hil", "--grid", "stub.drop=0,0.1,1.5", "--duration", "2.4",
                    "--hil-args", "--command-timeout 0.5 --max-command-age 0.5", "--stub-args", f"--kp 200,60,10 --kd 20,6,1 --amplitude {AMPLITUDE}", "--seed", "5",
                    "--workers", "1", "--out", work], capture_output=True, text=True)
check(r.returncode == 0, f"the sweep finished (exit {r.returncode}: {r.stderr.strip()[-400:]})")
with open(pathlib.Path(work) / "results.csv", newline="") as f:
    rows = {x["stub.drop"]: x for x in csv.DictReader(f)}
n = {k: {c: float(v) for c, v in x.items() if c not in ("status", "message") and v != ""} for k, x in rows.items()}
for drop in ("0.0", "0.1"):
    check(rows[drop]["status"] == "ok", f"drop {drop}: ok ({rows[drop]['status']}: {rows[drop]['message']})")
    check(n[drop]["tracking_rms"] < 0.25 * AMPLITUDE / math.sqrt(2),
          f"drop {drop}: the controller closed the loop (tracking RMS {n[drop]['tracking_rms']:.3g} rad)")
    check(n[drop]["commands_applied"] == n[drop]["commands_sent"], f"drop {drop}: every command sent was applied")
nominal, dropped = n["0.0"], n["0.1"]
check(nominal["commands_rejected"] == nominal["faults_injected"] == nominal["commands_missing"] == 0,
      "no faults: nothing rejected, nothing missing")
check(dropped["faults_injected"] > 20, f"drops were injected ({dropped['faults_injected']:.0f})")
# A drop shows as a gap when a later command arrives: all but those after the last command sent.
check(dropped["faults_injected"] - 3 <= dropped["commands_missing"] <= dropped["faults_injected"],
      f"missing {dropped['commands_missing']:.0f} == dropped {dropped['faults_injected']:.0f}")
check(rows["1.5"]["status"] == "refused" and "--drop" in rows["1.5"]["message"],
      f"a probability of 1.5 is refused, naming the option ({rows['1.5']['status']}: {rows['1.5']['message']})")
# Over the plant: the upper link's mass set in the loop.
plant = pathlib.Path(work) / "plant"
r = subprocess.run([mbrt, "sweep", tunable_model, "--hil", "--grid", "upper.mass=1,30", "--duration", "2.4",
                    "--hil-args", "--command-timeout 0.5 --max-command-age 0.5", "--stub-args", f"--kp 200,60,10 --kd 20,6,1 --amplitude {AMPLITUDE}",
                    "--workers", "1", "--out", str(plant)], capture_output=True, text=True)
check(r.returncode == 0, f"the plant sweep finished (exit {r.returncode}: {r.stderr.strip()[-400:]})")
with open(plant / "results.csv", newline="") as f:
    rows = {float(x["upper.mass"]): x for x in csv.DictReader(f)}
check(all(x["status"] == "ok" for x in rows.values()), f"both masses ran ({[x['status'] for x in rows.values()]})")
light, heavy = (float(rows[m]["tracking_rms"]) for m in (1.0, 30.0))
check(heavy > 1.5 * light, f"the heavy arm tracks worse: RMS {heavy:.3g} against {light:.3g} rad")
r = subprocess.run([mbrt, "sweep", tunable_model, "--hil", "--grid", "upper.colour=1", "--duration", "0.1",
                    "--out", str(pathlib.Path(work) / "unknown")], capture_output=True, text=True)
check(r.returncode == 2 and "upper.colour" in r.stderr, f"an unknown key stops the sweep, named (exit {r.returncode}: {r.stderr.strip()[-300:]})")
print(f"{failures} failures")
sys.exit(1 if failures else 0)
