#!/usr/bin/env bash
# navground's behaviours on SteerSuite's crowd cases, the baseline of strider's crowds.
#
#   benches/peers/navground_crowd.sh CASES_DIR [SEED] [BEHAVIORS] [MAX_AGENTS]
#       (defaults: seed 1, HL,ORCA, 420 agents; bottleneck-squeeze is run whatever its size)
#
# Installs navground 0.7.0 from PyPI into a virtual environment under target/peers/ (once),
# resolves every SteerSuite case of CASES_DIR (`strider gen CASE.xml --seed SEED`: every
# random draw made, as strider runs it) into a text world, and runs each world of at most
# MAX_AGENTS agents through benches/peers/navground_crowd.py: the same agents, goals in order,
# agents taken out on arrival, time step 0.05 s, capped at 400 s (600 s from 1,000 agents),
# one thread. Prints a line per world and behaviour; the worlds are kept in
# target/peers/crowd-worlds-SEED/ for benches/peers/crowd_check.py and for strider itself.
set -euo pipefail
cd "$(dirname "$0")/../.."
cases=${1:?usage: navground_crowd.sh CASES_DIR [SEED] [BEHAVIORS] [MAX_AGENTS]}
seed=${2:-1}
behaviors=${3:-HL,ORCA}
max_agents=${4:-420}
target=${CARGO_TARGET_DIR:-target}
venv="$target/peers/navground-venv"

if ! "$venv/bin/python" -c "import navground.sim" 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q navground==0.7.0
fi
cargo build --release --quiet --bin strider
strider="$target/release/strider"

worlds="$target/peers/crowd-worlds-$seed"
mkdir -p "$worlds"
selected=()
while IFS= read -r -d '' case; do
  name=$(basename "${case%.xml}")
  if ! "$strider" gen "$case" --seed "$seed" >"$worlds/$name.txt" 2>"$worlds/$name.err"; then
    echo "skipped $name: $(tail -n 1 "$worlds/$name.err")" >&2
    rm -f "$worlds/$name.txt"
    continue
  fi
  agents=$(grep -c '^agent ' "$worlds/$name.txt" || true)
  if [ "$agents" -le "$max_agents" ] || [ "$name" = bottleneck-squeeze ]; then
    selected+=("$agents $worlds/$name.txt")
  fi
done < <(find "$cases" -name '*.xml' -print0)

# Smallest cases first, so the table fills from the quick ones.
mapfile -t ordered < <(printf '%s\n' "${selected[@]}" | sort -n | cut -d' ' -f2-)
OMP_NUM_THREADS=1 "$venv/bin/python" benches/peers/navground_crowd.py "${ordered[@]}" --behaviors "$behaviors"
