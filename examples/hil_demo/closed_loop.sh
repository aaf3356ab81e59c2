#!/usr/bin/env bash
# Runs the arm in mbrt's real-time loop and a PD controller in its own
# process, both on LCM URL $1, for $2 seconds, then prints the loop's timing
# and the controller's tracking error. Reports go to directory $3. The loop
# runs at $4 Hz (default 1000) with one step of 1/$4 s per cycle; the
# environment's HIL_OPTIONS are added to its command line (e.g. --fifo 80 --cpu 1),
# and $MODEL replaces the arm (e.g. examples/hil_demo/arm3_friction.yaml).
set -euo pipefail
url=$1 seconds=$2 out=$3 rate=${4:-1000}
cd "$(dirname "$0")/../.."
mbrt=${MBRT:-build/bin/mbrt}
model=${MODEL:-examples/hil_demo/arm3.yaml}
mkdir -p "$out"
# Compile both programs before the clock starts (cached afterwards).
step=$(python3 -c "print(repr(1.0 / $rate))")
"$mbrt" hil "$model" --h "$step" --lcm "$url" --rate "$rate" --duration 0 >/dev/null
"$mbrt" stub "$model" --lcm "$url" --duration 0 >/dev/null

# shellcheck disable=SC2086  # HIL_OPTIONS is a list of words
"$mbrt" hil "$model" --h "$step" --lcm "$url" --rate "$rate" --duration "$seconds" --report "$out/hil.json" ${HIL_OPTIONS:-} >/dev/null &
sim=$!
sleep 0.3
"$mbrt" stub "$model" --lcm "$url" --duration "$(python3 -c "print($seconds - 0.6)")" \
  --kp 200,60,10 --kd 20,6,1 --amplitude 0.5 --frequency 0.5 --report "$out/stub.json" >/dev/null
wait "$sim"

python3 - "$out/hil.json" "$out/stub.json" <<'PY'
import json, sys
sim, stub = (json.load(open(p)) for p in sys.argv[1:3])
print(f"\nclosed loop: model {sim['model']}, {sim['rate_hz']:g} Hz, {sim['cycles']} cycles, {sim['transport']}")
print(f"deadline misses {sim['deadline_misses']}, overruns (skipped releases) {sim['overruns']}")
print(f"{'microseconds':<22}{'p50':>9}{'p99':>9}{'p99.9':>9}{'max':>9}")
for key, label in (("step_ns", "step"), ("cycle_ns", "cycle (release to end)"),
                   ("wake_jitter_ns", "wake-up jitter"), ("command_rtt_ns", "command round trip")):
    h = sim[key]
    print(f"{label:<22}" + "".join(f"{h[q] / 1000:9.1f}" for q in ("p50", "p99", "p999", "max")))
rejected = sum(sim["commands_rejected"].values())
print(f"commands applied {sim['commands_applied']}, rejected {rejected}, missing {sim['commands_missing']}, "
      f"fell back to safe values {sim['commands_stale']} times ({sim['safe_cycles']} cycles, start and end included)")
print(f"tracking error of the PD controller ({stub['joints_controlled']} joints, reference 0.5 sin(pi t) rad): "
      f"RMS {stub['tracking_rms']:.4f} rad, max {stub['tracking_max']:.4f} rad")
print(f"state finite: {'yes' if sim['state_finite'] else 'NO'}")
if sim["realtime"]["warnings"]:
    print("real-time set-up: " + sim["realtime"]["warnings"].strip().replace("\n", "; "))
PY
