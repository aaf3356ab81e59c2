# shellcheck shell=bash
# Sourced by the timing scripts that count instructions per step.
# callgrind_total CMD [ARG...]: the instructions CMD executes, its children
# included, counted by valgrind's callgrind (a figure that does not depend on
# machine load).
callgrind_total() {
  local dir
  dir=$(mktemp -d)
  valgrind --tool=callgrind --trace-children=yes --callgrind-out-file="$dir/cg.%p" "$@" >/dev/null 2>&1
  cat "$dir"/cg.* | awk '/^summary:/ { s += $2 } END { print s }'
  rm -rf "$dir"
}
