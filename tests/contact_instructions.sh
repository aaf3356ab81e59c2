#!/usr/bin/env bash
# The contact step does the same work whatever the contacts do
# (docs/contact.md), and the joint friction step whatever the joints do
# (docs/friction.md): every sampled step of each model (all but its first,
# which resolves the dynamic linker's symbols) executes the same number of
# instructions under callgrind. Exit 77 (skip) without valgrind.
#   contact_instructions.sh PROGRAM WORK_DIR
set -euo pipefail
program=$1
work=$2
command -v valgrind >/dev/null || { echo "valgrind not found: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$work/out" "$program" >/dev/null 2>"$work/valgrind.log"
# Each dump: "desc: Trigger: Client Request: <model>" and "totals: <instructions>".
# Dumps are numbered in the order taken: out.1, out.2, ...
for dump in "$work"/out.*; do
  model=$(sed -n 's/^desc: Trigger: Client Request: //p' "$dump")
  total=$(sed -n 's/^\(totals\|summary\): //p' "$dump" | head -1)
  echo "${dump##*.} $model $total"
done | sort -n | cut -d' ' -f2- > "$work/totals.txt"
status=0
for model in contact_balls contact_incline contact_tumble contact_jointed friction_pendulum_pcst friction_incline_mu_pcst contact_hub_friction_pcst; do
  counts=$(awk -v m="$model" '$1 == m {print $2}' "$work/totals.txt")
  samples=$(echo "$counts" | wc -l)
  distinct=$(echo "$counts" | tail -n +2 | sort -u)
  echo "$model: $samples sampled steps, instructions per step (after the first): $(echo "$distinct" | tr '\n' ' ')"
  if [ "$samples" -lt 50 ] || [ "$(echo "$distinct" | wc -l)" -ne 1 ]; then
    echo "FAIL: $model's sampled steps differ in instructions (or too few samples)"
    status=1
  fi
done
exit $status
