#!/usr/bin/env bash
# navground (C++ core with Python bindings) against strider on one world, one thread each.
#
#   benches/peers/navground.sh [SECONDS] [SEED]     (defaults: 3 and 27)
#
# Installs navground 0.7.0 from PyPI into a virtual environment under target/peers/ (once).
# benches/peers/navground_bench.py writes the world (one agent of radius 0.3 m, corner to
# corner of a 16 m square among 30 circles of radius 0.2-0.6 m, seeded by SEED) in strider's
# text format and runs it in navground: two-wheel differential drive, the HL behaviour with a
# 5 m range, time step 0.05 s, whole episodes in navground's own loop for about SECONDS. Then
# strider runs the same file with the disc and with the animated character for about as long
# (`strider run --threads 1`, its "steps alone" rate: world building and the reference
# optimum left out on both sides). Prints the steps per second of each and the ratios.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-3}
seed=${2:-27}
target=${CARGO_TARGET_DIR:-target}
venv="$target/peers/navground-venv"

if ! "$venv/bin/python" -c "import navground.sim" 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q navground==0.7.0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release --quiet --bin strider
strider="$target/release/strider"

"$venv/bin/python" benches/peers/navground_bench.py "$work/world.txt" "$seconds" "$seed" | tee "$work/navground.txt"

# strider's rate over `episodes` episodes of the world's one task with `body`: the steps per
# second of the steps alone, and the share of episodes that reached the goal.
rate() {
  "$strider" run "$work/world.txt" --body "$1" --episodes "$2" --threads 1 --format csv \
    >"$work/episodes.csv" 2>"$work/run.txt" || true
  sed -n 's/.*the steps alone: \([0-9]*\) agent-steps.*/\1/p' "$work/run.txt"
}
reached() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "reached") c = i; next }
           { n++; if ($c == "true") r++ } END { printf "%d/%d", r, n }' "$work/episodes.csv"
}
for body in disc animated; do
  # A short run gives the rate, and the episodes for about SECONDS follow from it.
  first=$(rate "$body" 10)
  steps=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "steps") c = i; next } { s += $c; n++ } END { print s / n }' "$work/episodes.csv")
  episodes=$(awk -v r="$first" -v s="$steps" -v t="$seconds" 'BEGIN { e = int(r * t / s); print (e < 10 ? 10 : e) }')
  r=$(rate "$body" "$episodes")
  echo "strider $body steps $steps reached $(reached) episodes"
  echo "strider $body steps/s $r"
done | tee "$work/strider.txt"

echo
echo "steps per second (one thread):"
awk '
  / steps\/s / { rate[$1 " " $2] = $NF }
  END {
    n = rate["navground steps/s"]
    printf "  %-20s %10.0f\n", "navground HL", n
    printf "  %-20s %10.0f %7.2fx\n", "strider disc", rate["strider disc"], rate["strider disc"] / n
    printf "  %-20s %10.0f %7.2fx\n", "strider character", rate["strider animated"], rate["strider animated"] / n
  }' "$work/navground.txt" "$work/strider.txt"
