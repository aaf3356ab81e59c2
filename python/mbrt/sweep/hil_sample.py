"""One sample of a HIL scenario sweep (`mbrt sweep --hil`): the model's
compiled `hil` loop and `stub` controller run against each other over LCM on
loopback, in a private network namespace of their own (scripts/
in-private-network), so samples running at once never hear each other. The
sample's parameters are the programs' options: `stub.drop=0.1` gives the stub
`--drop 0.1`, `hil.command-timeout=0.02` the loop `--command-timeout 0.02`;
any other key is the model's runtime parameter, which the loop takes as
`--set KEY=VALUE` (`upper.mass=2` gives `--set upper.mass=2`).
The stub's fault seed is the sample's own, derived from the sweep's seed.

Inside the namespace, `python3 -m mbrt.sweep.hil_sample` starts the loop,
then the controller, and prints both exit codes and JSON reports as one JSON
line; run_hil_sample makes the record of it:

- `ok`: both ran, the loop's state stayed finite and no step failed;
- `non_finite`: the loop ended with a non-finite state or failed steps;
- `refused`: a program refused its options (exit 1 or 2), with its message;
- `error`: anything else (a crash, no namespace), with what happened.
"""
import json
import pathlib
import subprocess
import sys
import tempfile
import time

from . import PACKAGE_ROOT, python_environment
from .record import error_message, make_record
from .spec import format_value, sample_seed

LCM_URL = "udpm://239.255.76.67:7667?ttl=0"  # loopback only, in the sample's own namespace
START_GAP_S = 0.3  # the controller starts after the loop, which runs that much longer
IN_PRIVATE_NETWORK = PACKAGE_ROOT.parent / "scripts" / "in-private-network"  # the source tree's, or share/mbrt/scripts
REPORT_FIELDS = {  # column: (program, field in its report)
    "cycles": ("hil", "cycles"), "deadline_misses": ("hil", "deadline_misses"), "overruns": ("hil", "overruns"),
    "commands_applied": ("hil", "commands_applied"), "commands_rejected": ("hil", "commands_rejected"),
    "commands_missing": ("hil", "commands_missing"), "safe_cycles": ("hil", "safe_cycles"),
    "step_failures": ("hil", "step_failures"), "cycle_p99_ns": ("hil", "cycle_ns"),
    "commands_sent": ("stub", "commands_sent"), "faults_injected": ("stub", "faults"),
    "tracking_rms": ("stub", "tracking_rms")}


def program_options(params, program):
    """`--OPTION VALUE` for the parameters `program.OPTION`, and for the loop
    `--set KEY=VALUE` for the model's parameters (keys of neither program)."""
    prefix = program + "."
    options = [a for key, v in params.items() if key.startswith(prefix) for a in ("--" + key[len(prefix):], format_value(v))]
    if program == "hil":
        options += [a for key, v in params.items() if not key.startswith(("hil.", "stub."))
                    for a in ("--set", f"{key}={format_value(v)}")]
    return options


def _report_value(report, field):
    value = report.get(field)
    if isinstance(value, dict):  # rejections by reason, faults by kind: their total; a histogram: its p99
        return value["p99"] if "p99" in value else sum(value.values())
    return value


def record(index, params, status, message="", summary=None):
    return make_record(index, params, status, message, REPORT_FIELDS, summary)


def run_hil_sample(hil, stub, duration, seed, hil_args, stub_args, sample):
    index, params = sample
    stub_seed = str(sample_seed(seed, index).generate_state(1)[0] % 2**31)
    command = [str(IN_PRIVATE_NETWORK), sys.executable, "-m", "mbrt.sweep.hil_sample", hil, stub, repr(duration),
               json.dumps([*hil_args, *program_options(params, "hil")]),
               json.dumps(["--seed", stub_seed, *stub_args, *program_options(params, "stub")])]
    r = subprocess.run(command, capture_output=True, text=True, env=python_environment())
    if r.returncode == 77:
        return record(index, params, "error", error_message(r.stderr))
    try:
        pair = json.loads(r.stdout.splitlines()[-1])
    except (IndexError, ValueError):
        return record(index, params, "error", f"exit code {r.returncode}: {error_message(r.stderr)}")
    for program in ("hil", "stub"):
        if pair[program]["exit"] in (1, 2):
            return record(index, params, "refused", f"{program}: {pair[program]['message']}")
    if any(pair[p]["report"] is None for p in ("hil", "stub")):
        return record(index, params, "error", "; ".join(f"{p}: exit {pair[p]['exit']} {pair[p]['message']}"
                                                        for p in ("hil", "stub")))
    summary = {column: _report_value(pair[program]["report"], field)
               for column, (program, field) in REPORT_FIELDS.items()}
    loop = pair["hil"]["report"]
    status = "ok" if loop["state_finite"] and loop["step_failures"] == 0 else "non_finite"
    return record(index, params, status, "", summary)


def _run_pair(hil, stub, duration, hil_args, stub_args):
    """Inside the namespace: the loop, then the controller; their exit codes, reports and last messages."""
    with tempfile.TemporaryDirectory(prefix="mbrt-hil-") as tmp:
        runs = {}
        for program, exe, seconds, args in (("hil", hil, duration + START_GAP_S, hil_args),
                                            ("stub", stub, duration, stub_args)):
            report = pathlib.Path(tmp) / f"{program}.json"
            runs[program] = (subprocess.Popen([exe, "--lcm", LCM_URL, "--duration", repr(seconds), "--report",
                                               str(report), *args], stdout=subprocess.DEVNULL,
                                              stderr=subprocess.PIPE, text=True), report)
            if program == "hil":
                time.sleep(START_GAP_S)
        out = {}
        for program, (process, report) in runs.items():
            _, err = process.communicate()
            out[program] = {"exit": process.returncode, "message": error_message(err),
                            "report": json.loads(report.read_text()) if report.exists() else None}
        return out


if __name__ == "__main__":
    hil_exe, stub_exe, seconds, loop_args, controller_args = sys.argv[1:]
    print(json.dumps(_run_pair(hil_exe, stub_exe, float(seconds), json.loads(loop_args), json.loads(controller_args))))
