#!/usr/bin/env bash
# fuzzylite (C++) against strider on the same FLL engines and the same inputs, one thread each.
#
#   benches/peers/fuzzylite.sh [SECONDS] [RESOLUTIONS]     (defaults: 2 and 100,200,500)
#
# Needs fuzzylite 6 (Debian: libfuzzylite-dev), installed here when missing and run as root.
# Builds benches/peers/fuzzylite_bench.cpp with g++ -O2 and the `fuzzy_peer` example with
# cargo --release, runs both on benches/fixtures/*.fll and the navigation engine of
# scripts/simple_nav.rhai (exported to FLL), prints inferences per second of each and the
# ratio, and checks that both compute the same outputs on the first inputs.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-2}
resolutions=${2:-100,200,500}

if [ ! -e /usr/include/fl/Headers.h ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    apt-get install -y -qq libfuzzylite-dev >/dev/null || { apt-get update -qq && apt-get install -y -qq libfuzzylite-dev >/dev/null; }
  else
    echo "fuzzylite is missing: install libfuzzylite-dev (Debian/Ubuntu: sudo apt-get install libfuzzylite-dev) and run again"
    exit 0
  fi
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
g++ -O2 -o "$work/fuzzylite_bench" benches/peers/fuzzylite_bench.cpp -lfuzzylite
cargo build --release --quiet --example fuzzy_peer
peer="${CARGO_TARGET_DIR:-target}/release/examples/fuzzy_peer"
"$peer" --export scripts/simple_nav.rhai > "$work/nav.fll"
engines=(benches/fixtures/*.fll "$work/nav.fll")

"$work/fuzzylite_bench" "$seconds" "$resolutions" "${engines[@]}" | tee "$work/fuzzylite.txt"
"$peer" "$seconds" "$resolutions" "${engines[@]}" | tee "$work/strider.txt"

echo
echo "same outputs? first inputs of each engine and resolution, largest difference relative to max(|output|, 1):"
awk '
  $1 == "check" { key = $2 " " $3 " " $4; n = 0; out = 0
    for (i = 5; i <= NF; i++) { if ($i == "out") { out = 1; continue } if (out) v[FILENAME, key, ++n] = $i }
    keys[key] = n }
  END {
    worst = 0
    for (k in keys) for (i = 1; i <= keys[k]; i++) {
      a = v[ARGV[1], k, i] + 0; b = v[ARGV[2], k, i] + 0
      if ((a != a) || (b != b)) { if ((a != a) != (b != b)) { print "  " k ": " a " vs " b; bad = 1 } continue }
      d = a - b; if (d < 0) d = -d; s = (a < 0 ? -a : a); if (s < 1) s = 1
      if (d / s > worst) worst = d / s
    }
    printf "  %g over %d inputs\n", worst, length(keys)
    if (worst > 1e-6 || bad) { print "  outputs differ"; exit 1 }
  }' "$work/fuzzylite.txt" "$work/strider.txt"

echo
echo "inferences per second (one thread):"
awk '
  /inferences\/s/ { sub(":", "", $4); rate[$1, $2, $4] = $5; if (!seen[$2, $4]++) order[++n] = $2 " " $4 }
  END {
    printf "  %-10s %10s %14s %14s %8s\n", "engine", "resolution", "fuzzylite", "strider", "ratio"
    for (i = 1; i <= n; i++) { split(order[i], p, " ")
      f = rate["fuzzylite", p[1], p[2]]; s = rate["strider", p[1], p[2]]
      printf "  %-10s %10s %14.0f %14.0f %7.1fx\n", p[1], p[2], f, s, (f > 0 ? s / f : 0) }
  }' "$work/fuzzylite.txt" "$work/strider.txt"
