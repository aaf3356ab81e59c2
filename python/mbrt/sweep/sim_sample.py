"""One sample of a sweep: the compiled sim program run once with the
sample's `--set KEY=VALUE` options, its exit code and JSON summary turned into
a record. Every outcome is a record (failures are data):

- `ok`, or the step's failure (`non_finite`, ...) when it exits 3, with the
  summary's fields (the run stops at the failed step);
- `refused`: the program refused its command line or the model (exit 2 or 1),
  with its message;
- `error`: it crashed, was killed, or printed no summary, with what happened.
"""
import json
import pathlib
import signal
import subprocess
import tempfile

from .record import error_message, make_record
from .spec import format_value

SUMMARY_FIELDS = ("steps", "energy_initial", "energy_final", "max_position_violation", "max_velocity_violation",
                  "max_acceleration_violation", "max_quat_norm_error", "ns_per_step")
# --every beyond any run's steps: the CSV holds the initial and the final state only.
_EVERY_FINAL_ONLY = str(10**15)


def set_options(params):
    """`--set KEY=VALUE` per parameter, each value at full precision."""
    return [a for key, value in params.items() for a in ("--set", f"{key}={format_value(value)}")]


def record(index, params, status, message="", summary=None, outputs=None):
    return make_record(index, params, status, message, SUMMARY_FIELDS, summary, outputs)


def read_final(csv_file, columns):
    """The requested columns of the CSV's last row (the state at t_end)."""
    lines = pathlib.Path(csv_file).read_text().splitlines()
    header, last = lines[0].split(","), lines[-1].split(",")
    return {c: float(last[header.index(c)]) for c in columns}


def csv_options(csv_file):
    return ["--out", str(csv_file), "--every", _EVERY_FINAL_ONLY, "--velocities", "--reactions"]


def run_sim_sample(program, run_args, outputs, sample):
    """Runs sample (index, params) and returns its record; never raises for the run's own failures."""
    index, params = sample
    with tempfile.TemporaryDirectory(prefix="mbrt-sweep-") as tmp:
        csv_file = pathlib.Path(tmp) / "final.csv"
        command = [program, *run_args, *set_options(params), *(csv_options(csv_file) if outputs else [])]
        try:
            r = subprocess.run(command, capture_output=True, text=True)
        except OSError as e:
            return record(index, params, "error", f"cannot start {program}: {e}")
        if r.returncode < 0:
            return record(index, params, "error", f"killed by {signal.Signals(-r.returncode).name}")
        if r.returncode in (1, 2):
            return record(index, params, "refused", error_message(r.stderr))
        try:
            summary = json.loads(r.stdout.splitlines()[-1])
        except (IndexError, ValueError):
            return record(index, params, "error", f"exit code {r.returncode} without a JSON summary: "
                                                  f"{error_message(r.stderr)}")
        status = summary.get("status", "error")
        if r.returncode == 0 and status == "ok":
            return record(index, params, "ok", "", summary, read_final(csv_file, outputs) if outputs else None)
        message = f"{status} at step {summary.get('steps')}" if r.returncode == 3 else f"exit code {r.returncode}"
        return record(index, params, status, message, summary)
