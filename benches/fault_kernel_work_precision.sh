#!/usr/bin/env bash
# Work–precision of the quasi-dynamic BP1 run (examples/seas_bp1.rs, Runge–Kutta on the
# condensed fault) with the dense and the hierarchical kernel at several tolerances
# (docs/performance.md, "Long runs: kernel and tolerance"). Each configuration is
# KERNEL:EPSILON:RK_TOLERANCE (EPSILON "-" for the dense kernel or the default ε = the
# Runge–Kutta tolerance); the first one is the reference the errors are measured against.
# Prints a Markdown table on stdout: first event, mean recurrence from the 4th interval on,
# largest peak slip rate, their differences from the reference, steps, evaluations, CPU.
#
#   bash benches/fault_kernel_work_precision.sh                      # Δz 100 m, 400 km, 3000 yr
#   DZ=25 THREADS=2 CONFIGS="dense:-:1e-6 hierarchical:-:1e-6" bash benches/fault_kernel_work_precision.sh
#
# Needs python3 and GNU time; outputs stay in OUT (default a temporary folder).
set -euo pipefail
cd "$(dirname "$0")/.."
DZ=${DZ:-100}
KM=${KM:-400}
YEARS=${YEARS:-3000}
THREADS=${THREADS:-1}
CONFIGS=${CONFIGS:-"dense:-:1e-8 dense:-:1e-5 dense:-:1e-6 dense:-:1e-7 hierarchical:1e-3:1e-6 hierarchical:1e-4:1e-6 hierarchical:-:1e-6 hierarchical:1e-8:1e-6 hierarchical:-:1e-5 hierarchical:-:1e-7"}
cargo build --release --example seas_bp1 >&2
BIN=${CARGO_TARGET_DIR:-target}/release/examples/seas_bp1
OUT=${OUT:-$(mktemp -d)}
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown); Δz $DZ m, $KM km, $YEARS years, $THREADS thread(s)"
echo
echo "| kernel | ε | RK tolerance | ‖S − S_H‖_F/‖S‖_F | first event (yr) | Δ first (yr) | recurrence (yr) | Δ recurrence (yr) | peak V (m/s) | Δ peak V (rel.) | steps | evaluations | µs per evaluation | CPU (s) | wall (s) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
ref=""
for c in $CONFIGS; do
  IFS=: read -r kernel eps tol <<<"$c"
  dir="$OUT/${kernel}_${eps}_${tol}"
  args=(--dz "$DZ" --domain-km "$KM" --end-years "$YEARS" --kernel "$kernel" --rk-tolerance "$tol" --threads "$THREADS" --out "$dir" --overwrite)
  [[ "$eps" != "-" ]] && args+=(--kernel-epsilon "$eps")
  /usr/bin/time -v -o "$dir.time" "$BIN" "${args[@]}" > "$dir.log" 2>&1 || { echo "| $kernel | $eps | $tol | failed: $(tail -1 "$dir.log") |"; continue; }
  [[ -z "$ref" ]] && ref="$dir"
  python3 - "$dir" "$ref" "$kernel" "$eps" "$tol" <<'PY'
import json, sys
d, ref, kernel, eps, tol = sys.argv[1:6]
s, r = json.load(open(f"{d}/summary.json")), json.load(open(f"{ref}/summary.json"))
k = s.get("kernel") or {}
err = "0 (dense)" if kernel == "dense" else f"{k.get('relative_error_frobenius', float('nan')):.1e}"
def diff(a, b):
    return "—" if a is None or b is None else f"{a - b:+.4f}"
rec, rrec = s["mean_recurrence_from_4th_interval_years"], r["mean_recurrence_from_4th_interval_years"]
pv, rpv = s["peak_slip_rate_mps"], r["peak_slip_rate_mps"]
ev = s.get("rate_evaluations") or 0
print(f"| {kernel} | {'= tol' if eps == '-' and kernel != 'dense' else ('—' if eps == '-' else eps)} | {tol} | {err} | "
      f"{s['first_event_years']:.4f} | {diff(s['first_event_years'], r['first_event_years'])} | "
      f"{'—' if rec is None else f'{rec:.4f}'} | {diff(rec, rrec)} | {pv:.4f} | {(pv - rpv) / rpv:+.1e} | "
      f"{s['accepted_steps']} | {ev} | {1e6 * s['cpu_time_s'] / max(ev, 1):.0f} | {s['cpu_time_s']:.1f} | {s['wall_time_s']:.1f} |")
PY
done
echo
echo "(outputs in $OUT)"
