#!/usr/bin/env bash
# The fault ODE's integrators, error against CPU time (docs/work-precision.md, "The fault
# ODE's integrators"): runs every run folder DIR/PROBLEM_INTEGRATOR_TOL that is not there
# yet (each program under `/usr/bin/time -v`, one thread, its output in DIR/NAME.log, whose
# set-up CPU line the study takes off), JOBS runs at a time, then
# `work_precision --study integrators`, which writes docs/work-precision/integrators.csv and
# docs/figures/work_precision_integrators.png.
#
#   bash benches/integrators_study.sh                          # every problem, one run at a time
#   JOBS=2 PROBLEMS="bp6a ok1" bash benches/integrators_study.sh
#
# Each problem's reference is its dormand-prince run at the smallest tolerance (REF below).
# CPU times compare only when the runs share the machine alike: JOBS=2 on two cores gives
# each run a core of its own.
set -euo pipefail
cd "$(dirname "$0")/.."
DIR=${DIR:-out/integrators}
JOBS=${JOBS:-1}
PROBLEMS=${PROBLEMS:-"bp1 fe2 fe1 ok2 ok1 bp6a"}
mkdir -p "$DIR"
cargo build --release --example seas_bp1 --example seas_bp5 --example seas_bp6 \
    --example work_precision
bin=$PWD/target/release/examples

# PROBLEM: command, tolerance flag, "INTEGRATOR:TOL TOL …" groups, reference tolerance.
spec() {
    case $1 in
        bp1) echo "$bin/seas_bp1 --dz 100 --end-years 700 --kernel dense|--rk-tolerance|auto:1e-4,1e-5,1e-6,1e-7 rkc:1e-4,1e-5,1e-6,1e-7 dormand-prince:1e-4,1e-5,1e-6,1e-7 bogacki-shampine:1e-4,1e-5,1e-6,1e-7|1e-9" ;;
        fe2) echo "$bin/seas_bp5 --kernel fe --dx 2000 --end-years 300|--tolerance|auto:1e-4,1e-5,1e-6 rkc:1e-4,1e-5,1e-6 dormand-prince:1e-4,1e-5,1e-6|1e-8" ;;
        # The volume at 1 km, at the ℋ-accuracy of its 1 800-year target run (docs/seas-bp5.md).
        fe1) echo "$bin/seas_bp5 --kernel fe --dx 1000 --epsilon 1e-4 --end-years 300|--tolerance|auto:1e-4,1e-5,1e-6 rkc:1e-4,1e-5 dormand-prince:1e-4,1e-5,1e-6|1e-8" ;;
        ok2) echo "$bin/seas_bp5 --dx 2000 --end-years 300|--tolerance|auto:1e-4,1e-5,1e-6 rkc:1e-4,1e-5,1e-6 dormand-prince:1e-4,1e-5,1e-6|1e-8" ;;
        # Okada at BP5's 1 km: RKC2 at 1e-6 would take ~15 min of CPU (5x the pair's, as at 2 km).
        ok1) echo "$bin/seas_bp5 --dx 1000 --end-years 300|--tolerance|auto:1e-4,1e-5,1e-6 rkc:1e-4,1e-5 dormand-prince:1e-4,1e-5,1e-6|1e-8" ;;
        bp6a) echo "$bin/seas_bp6 --variant a|--tolerance|auto:1e-4,1e-5,1e-6,1e-7 rkc:1e-4,1e-5,1e-6,1e-7 dormand-prince:1e-4,1e-5,1e-6,1e-7|1e-9" ;;
        *) echo "unknown problem $1" >&2; exit 2 ;;
    esac
}

jobs_file=$(mktemp)
trap 'rm -f "$jobs_file"' EXIT
for p in $PROBLEMS; do
    IFS='|' read -r cmd flag groups ref <<<"$(spec "$p")"
    for g in $groups dormand-prince:$ref; do
        integrator=${g%%:*}
        for tol in $(tr ',' ' ' <<<"${g#*:}"); do
            name=${p}_${integrator}_${tol}
            [ -f "$DIR/$name/summary.json" ] && continue
            echo "/usr/bin/time -v $cmd $flag $tol --integrator $integrator --threads 1 --out $DIR/$name --overwrite > $DIR/$name.log 2>&1" >>"$jobs_file"
        done
    done
done
echo "$(wc -l <"$jobs_file") runs to do in $DIR, $JOBS at a time"
xargs -P "$JOBS" -I{} sh -c '{}' <"$jobs_file"
"$bin/work_precision" --study integrators --runs "$DIR" --out docs/work-precision --overwrite \
    --figures docs/figures
