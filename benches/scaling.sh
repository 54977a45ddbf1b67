#!/usr/bin/env bash
# Cost and memory against the number of unknowns (docs/scaling.md): the paper's slider in
# 2-D (pipping_slider) and 3-D (slider_3d) at several levels with each velocity solver,
# STEPS steps at the main job's time step (τ = 1.5e-3 s, the start of the loading phase),
# as a Markdown table on stdout: dofs, condensed fault unknowns, set-up time, time per
# step, fixed point and solver iterations per step, peak memory (maximum resident set size
# from /usr/bin/time -v).
#
#   bash benches/scaling.sh                                    # 2-D j = 4…7, 3-D j = 2…4
#   LEVELS_2D="8" LEVELS_3D="5" SOLVERS="tnnmg" bash benches/scaling.sh
#   STEPS=200 LEVELS_2D="" LEVELS_3D="4" bash benches/scaling.sh   # the issue's 3-D j = 4 probe
#
# Each run is limited to MEMORY_GB of address space (default 20), so a solver that does
# not fit fails instead of taking the machine; it is reported as failed. Needs python3 and
# GNU time.
set -euo pipefail
cd "$(dirname "$0")/.."
LEVELS_2D=${LEVELS_2D-"4 5 6 7"}
LEVELS_3D=${LEVELS_3D-"2 3 4"}
SOLVERS=${SOLVERS:-"direct tnnmg"}
STEPS=${STEPS:-20}
MEMORY_GB=${MEMORY_GB:-20}
END=$(python3 -c "print($STEPS * 1.5e-3)")
cargo build --release --bin pipping_slider --example slider_3d >&2
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown); $STEPS steps of 1.5e-3 s"
echo
echo "| dim | level | solver | dofs | set-up (s) | per step (ms) | FPI / step | solver its / step | peak memory (MiB) |"
echo "|---|---|---|---|---|---|---|---|---|"
run() { # dim level solver binary args...
  local dim=$1 level=$2 solver=$3 bin=$4; shift 4
  local dir="$OUT/d$dim-j$level-$solver"
  if ! prlimit --as=$((MEMORY_GB * 1024 * 1024 * 1024)) /usr/bin/time -v -o "$dir.time" \
      "$bin" --level "$level" --solver "$solver" --steps "$STEPS" --end-time "$END" \
      --out "$dir" "$@" > "$dir.log" 2>&1; then
    echo "| $dim | $level | $solver | failed: $(tail -1 "$dir.log" | cut -c1-120) |"
    return
  fi
  python3 - "$dir" "$dim" "$level" "$solver" "$STEPS" <<'EOF'
import json, re, sys
d, dim, level, solver, steps = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5])
t = open(f"{d}.time").read()
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
log = open(f"{d}.log").read()
if dim == "2":
    s = json.load(open(f"{d}/summary.json"))
    dofs, setup, wall = s["dofs"], s["setup_time_s"], s["wall_time_s"]
    fpi = s["stats"]["fpi_mean"]
    its = s["stats"]["solver_iterations"] / steps
else:
    dofs = int(re.search(r"(\d+) dofs", log).group(1))
    setup = float(re.search(r"set-up ([\d.]+) s", log).group(1))
    wall = float(re.search(r"steps in ([\d.]+) s", log).group(1))
    fpi = float(re.search(r"fixed point iterations ([\d.]+)", log).group(1))
    its = float(re.search(r"solver iterations ([\d.]+)", log).group(1))
print(f"| {dim} | {level} | {solver} | {dofs} | {setup:.2f} | {1e3 * wall / steps:.1f} | {fpi:.2f} | {its:.2f} | {rss:.0f} |")
EOF
}
for level in $LEVELS_2D; do
  for solver in $SOLVERS; do
    run 2 "$level" "$solver" target/release/pipping_slider
  done
done
for level in $LEVELS_3D; do
  for solver in $SOLVERS; do
    run 3 "$level" "$solver" target/release/examples/slider_3d --frame-every 0
  done
done
