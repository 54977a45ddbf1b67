#!/usr/bin/env bash
# SCEC SEAS BP1-QD (examples/seas_bp1.rs) at several element sizes and domain sizes, in one
# session: events, first event, mean recurrence (4th interval on), peak slip rate,
# hypocentre depth, surface slip, steps, fixed point iterations per step, wall and CPU time
# per step and peak memory, as a Markdown table on stdout (the tables of docs/seas-bp1.md).
#
#   bash benches/seas_bp1.sh                                  # Δz 200 m, 100 and 400 km, 700 yr
#   RUNS="200:400 100:400" YEARS=3000 bash benches/seas_bp1.sh  # dz:domain_km pairs
#   RUNS="25:400" YEARS=3000 bash benches/seas_bp1.sh           # the spec (about 40 min)
#   SCHEME=implicit bash benches/seas_bp1.sh                    # the paper's scheme
#
# SCHEME is the example's --scheme (default runge-kutta); EXTRA more flags for it (e.g.
# "--inertia"). "work/step" is fixed point iterations per step for the implicit scheme and
# right-hand side evaluations per step for the Runge–Kutta one.
#
# Peak memory is the maximum resident set size from /usr/bin/time -v. Needs python3 and GNU
# time. Outputs stay in OUT (default a temporary folder) for plotting against published
# results.
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${RUNS:-"200:100 200:400"}
YEARS=${YEARS:-700}
SCHEME=${SCHEME:-runge-kutta}
EXTRA=${EXTRA:-}
cargo build --release --example seas_bp1 >&2
BIN=target/release/examples/seas_bp1
OUT=${OUT:-$(mktemp -d)}
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown); $YEARS years; scheme $SCHEME $EXTRA"
echo
echo "| Δz (m) | domain (km) | nodes | events | first (yr) | recurrence (yr) | peak V (m/s) | hypocentre (km) | surface slip (m) | steps | work/step | CPU per step (ms) | wall (s) | peak memory (MiB) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for run in $RUNS; do
  dz=${run%%:*}; km=${run##*:}
  dir="$OUT/dz${dz}_L${km}"
  # shellcheck disable=SC2086
  /usr/bin/time -v -o "$dir.time" "$BIN" --dz "$dz" --domain-km "$km" --end-years "$YEARS" \
    --scheme "$SCHEME" $EXTRA --out "$dir" --overwrite > "$dir.log" 2>&1 || { echo "| $dz | $km | failed: $(tail -1 "$dir.log") |"; continue; }
  python3 - "$dir" "$dz" "$km" <<'PY'
import json, re, sys
d, dz, km = sys.argv[1:4]
s = json.load(open(f"{d}/summary.json"))
t = open(f"{d}.time").read()
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
rec = s["mean_recurrence_from_4th_interval_years"]
hyp = s["hypocentre_depths_m"]
slip = s["surface_slip_m"]
print(f"| {dz} | {km} | {s['nodes']} | {s['events']} | {s['first_event_years']:.1f} | "
      f"{'—' if rec is None else f'{rec:.1f}'} | {s['peak_slip_rate_mps']:.2f} | "
      f"{(sum(hyp) / len(hyp) / 1e3) if hyp else float('nan'):.1f} | "
      f"{(sum(slip) / len(slip)) if slip else float('nan'):.2f} | {s['accepted_steps']} | "
      f"{(s['rate_evaluations'] or 0) / s['accepted_steps'] if s.get('rate_evaluations') else s['fixed_point_iterations_mean']:.2f} | "
      f"{1e3 * s['cpu_time_s'] / s['accepted_steps']:.2f} | "
      f"{s['wall_time_s']:.0f} | {rss:.0f} |")
PY
done
