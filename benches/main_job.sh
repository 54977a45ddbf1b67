#!/usr/bin/env bash
# The main job (the paper's slider, Table 6.1: Dieterich, Newmark, N = 1e4, T = 15 s) at
# several levels with each velocity solver, in one session: wall time, time per step, fixed
# point iterations (mean / max), velocity-solver iterations and peak memory, as a Markdown
# table on stdout (the table of docs/performance.md).
#
#   bash benches/main_job.sh                      # levels 3 4 5 6, solvers auto direct tnnmg
#   LEVELS="4" SOLVERS="auto" bash benches/main_job.sh
#   STEPS=10000 LAW=ruina bash benches/main_job.sh
#
# Every run is the README's first command with --level/--solver (outputs in a temporary
# folder); peak memory is the maximum resident set size from /usr/bin/time -v. Needs
# python3 (to read summary.json) and GNU time.
set -euo pipefail
cd "$(dirname "$0")/.."
LEVELS=${LEVELS:-"3 4 5 6"}
SOLVERS=${SOLVERS:-"auto direct tnnmg"}
STEPS=${STEPS:-10000}
LAW=${LAW:-dieterich}
cargo build --release --bin pipping_slider >&2
BIN=target/release/pipping_slider
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo
echo "| level | solver | dofs | wall (s) | per step (ms) | FPI mean / max | solver its | peak memory (MiB) |"
echo "|---|---|---|---|---|---|---|---|"
for level in $LEVELS; do
  for solver in $SOLVERS; do
    dir="$OUT/j$level-$solver"
    /usr/bin/time -v -o "$dir.time" "$BIN" --level "$level" --solver "$solver" \
      --steps "$STEPS" --law "$LAW" --out "$dir" > "$dir.log" 2>&1 || {
      echo "| $level | $solver | failed: $(tail -1 "$dir.log") |"; continue; }
    python3 - "$dir" "$level" "$solver" "$STEPS" <<'EOF'
import json, re, sys
d, level, solver, steps = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
s = json.load(open(f"{d}/summary.json"))
t = open(f"{d}.time").read()
wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", t).group(1)
parts = [float(x) for x in wall.split(":")]
wall_s = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
st = s["stats"]
print(f"| {level} | {solver} | {s['dofs']} | {wall_s:.2f} | {1e3 * s['wall_time_s'] / steps:.3f} "
      f"| {st['fpi_mean']:.2f} / {st['fpi_max']} | {st['solver_iterations']} | {rss:.0f} |")
EOF
  done
done
