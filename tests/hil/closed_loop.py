#!/usr/bin/env python3
"""Closed-loop HIL scenarios: `mbrt hil` runs a model in its real-time loop,
`mbrt stub` runs a PD controller for it in another process, both over LCM
(or, given --can BUS, a CAN bus; with --can-fd, in CAN FD frames) on loopback (run inside
scripts/in-private-network). Each scenario injects
one kind of fault and checks, from the two JSON reports, that the loop kept
running, that nothing non-finite entered the state, that the simulator
counted exactly what the controller did wrong, and that control resumed.

usage: closed_loop.py MBRT MODEL WORK_DIR SCENARIO [--can BUS [--can-fd]]
"""
import json
import math
import os
import subprocess
import sys
import time

from hil_test import GAINS, LCM_URL, check, compile_programs, environment, finish

SIM_S = 5.0 if sys.argv[4] == "crash_restart" else 3.0  # the simulator runs longer than the controller,
STUB_S = 2.4       # so every command is sent while the loop still reads
START_GAP_S = 0.3  # the controller starts after the simulator
# Generous command timeouts: a busy test machine can stall a process for tens
# of milliseconds, which must not turn into rejections the test did not inject.
# After a crash, though, the last command holds until the stale timeout, so
# that scenario falls back to safe values sooner.
MAX_AGE_S = 0.5
TIMEOUT_S = 0.05 if sys.argv[4] == "crash_restart" else MAX_AGE_S
AMPLITUDE = 0.5    # reference q_ref = A sin(2 pi 0.5 t) for every joint

mbrt, model, work, scenario = sys.argv[1:5]
LINK = sys.argv[5:] if len(sys.argv) > 5 else ["--lcm", LCM_URL]
env = environment(work)


def start(command, name, *args):
    report = os.path.join(work, f"{scenario}_{name}.json")
    if os.path.exists(report):
        os.remove(report)
    cmd = [mbrt, command, model, *LINK, "--report", report, *args]
    return subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL), report


def wait_for(process, report, expect_code=0):
    code = process.wait(timeout=600)
    check(code == expect_code, f"{os.path.basename(report)}: exit code {code}, expected {expect_code}")
    if expect_code != 0:
        return None
    with open(report) as f:
        return json.load(f)


def stub(name, duration, *faults):
    return start("stub", name, "--duration", str(duration), "--amplitude", str(AMPLITUDE), *GAINS, *faults)


def run_pair(*faults, crash_after=None):
    sim, sim_report = start("hil", "sim", "--rate", "1000", "--duration", str(SIM_S),
                            "--command-timeout", str(TIMEOUT_S), "--max-command-age", str(MAX_AGE_S))
    time.sleep(START_GAP_S)
    controllers = []
    if crash_after is None:
        s, r = stub("stub", STUB_S, *faults)
        controllers.append(wait_for(s, r))
    else:
        s, r = stub("crashing_stub", STUB_S, "--crash-after", str(crash_after))
        wait_for(s, r, expect_code=3)
        time.sleep(TIMEOUT_S + 0.3)  # past the stale timeout: the loop falls back to safe values
        s, r = stub("restarted_stub", 2.2)
        controllers.append(wait_for(s, r))
    return wait_for(sim, sim_report), controllers[-1]


def check_loop(sim):
    check(sim["cycles"] == round(SIM_S * 1000), f"the loop ran all {round(SIM_S * 1000)} cycles ({sim['cycles']})")
    check(sim["state_finite"] is True, "the state is finite")
    check(sim["step_failures"] == 0, "no step was refused")


def check_tracking(stub_report):
    # Following nothing at all leaves an RMS error of A / sqrt(2).
    rms = stub_report["tracking_rms"]
    check(rms is not None and rms < 0.25 * AMPLITUDE / math.sqrt(2),
          f"the controller closed the loop: tracking RMS {rms} rad < 0.25 A/sqrt(2)")


def rejected(sim, reason):
    return sim["commands_rejected"][reason]


compile_programs(mbrt, model, env, LINK)
if scenario == "nominal":
    sim, ctl = run_pair()
    check_loop(sim)
    check_tracking(ctl)
    check(sim["commands_applied"] == ctl["commands_sent"], f"every command sent was applied ({sim['commands_applied']} of {ctl['commands_sent']})")
    check(sum(sim["commands_rejected"].values()) == 0, "nothing was rejected")
    check(sim["command_rtt_ns"]["count"] == sim["commands_applied"], "a round trip was measured per command applied")
elif scenario in ("nan", "out_of_range", "garbage", "duplicate"):
    option = {"nan": "--nan", "out_of_range": "--out-of-range", "garbage": "--garbage", "duplicate": "--duplicate"}[scenario]
    reason = {"nan": "non_finite", "out_of_range": "out_of_range", "garbage": "malformed", "duplicate": "duplicate"}[scenario]
    count = {"nan": "nan", "out_of_range": "out_of_range", "garbage": "garbage", "duplicate": "duplicated"}[scenario]
    sim, ctl = run_pair(option, "0.1")
    check_loop(sim)
    injected = ctl["faults"][count]
    check(injected > 20, f"faults were injected ({injected})")
    check(rejected(sim, reason) == injected, f"{reason} rejections {rejected(sim, reason)} == faults injected {injected}")
    others = sum(v for k, v in sim["commands_rejected"].items() if k != reason)
    check(others == 0, f"no other rejections ({others})")
    check_tracking(ctl)
elif scenario == "drop":
    sim, ctl = run_pair("--drop", "0.1")
    check_loop(sim)
    dropped = ctl["faults"]["dropped"]
    check(dropped > 20, f"commands were dropped ({dropped})")
    # A drop shows as a gap when a later command arrives: all but possibly the last.
    check(dropped - 1 <= sim["commands_missing"] <= dropped, f"missing {sim['commands_missing']} == dropped {dropped}")
    check(sim["commands_applied"] == ctl["commands_sent"], "every command sent was applied")
    check_tracking(ctl)
elif scenario == "reorder":
    sim, ctl = run_pair("--reorder", "0.1")
    check_loop(sim)
    reordered = ctl["faults"]["reordered"]
    check(reordered > 20, f"commands were reordered ({reordered})")
    # A held-back command arrives after the next one; one still held at the end is never sent.
    check(reordered - 1 <= rejected(sim, "out_of_order") <= reordered,
          f"out_of_order rejections {rejected(sim, 'out_of_order')} == reordered {reordered}")
    check_tracking(ctl)
elif scenario == "delay":
    # A compute delay above the maximum age: every command arrives late.
    sim, ctl = run_pair("--delay-us", str(MAX_AGE_S * 1.2e6), "--jitter-us", "20000")
    check_loop(sim)
    check(ctl["commands_sent"] >= 2, f"commands were sent ({ctl['commands_sent']})")
    check(rejected(sim, "late") == ctl["commands_sent"], f"late rejections {rejected(sim, 'late')} == commands sent {ctl['commands_sent']}")
    check(sim["commands_applied"] == 0, "no late command was applied")
    check(sim["safe_cycles"] == sim["cycles"], "the loop ran on the safe values throughout")
elif scenario == "crash_restart":
    sim, ctl = run_pair(crash_after=0.8)
    check_loop(sim)
    check(sim["commands_stale"] >= 2, f"the loop fell back to safe values when the controller died and at the end ({sim['commands_stale']} times)")
    check(sim["commands_applied"] > ctl["commands_sent"], "commands of both controller runs were applied")
    check(rejected(sim, "out_of_order") == 0, "the restarted sequence was accepted")
    check_tracking(ctl)
else:
    sys.exit(f"unknown scenario {scenario}")

finish()
