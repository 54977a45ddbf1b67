#!/usr/bin/env bash
# What a newcomer waits for: the README's two commands from a fresh clone of this
# repository's HEAD (an empty target/; crates.io sources from the local registry), each
# under /usr/bin/time -v, with cargo's build timings (HTML reports: the heaviest units,
# how parallel the build is). Prints the rows of the table in docs/performance.md,
# "What a newcomer waits for".
#
#   bash benches/build_study.sh                 # both commands
#   ONLY=main bash benches/build_study.sh       # the main job only (ONLY=tests: the tests)
#   KEEP=1 bash benches/build_study.sh          # keep the clone (and its timings reports)
#
# Run it on a quiet machine: the wall times are the numbers, and other builds change them.
set -euo pipefail
cd "$(dirname "$0")/.."
ONLY=${ONLY:-all}
CLONE=$(mktemp -d)/rsf
git clone -q . "$CLONE"
trap 'if [ -z "${KEEP:-}" ]; then rm -rf "$(dirname "$CLONE")"; fi' EXIT
cd "$CLONE"
unset CARGO_TARGET_DIR
export CARGO_INCREMENTAL=0 CARGO_TERM_COLOR=never
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; load $(cut -d' ' -f1-3 /proc/loadavg); commit $(git rev-parse --short HEAD)"
echo
echo "| command | wall | of it the build | CPU (user + sys) | peak RSS |"
echo "|---|---|---|---|---|"
# Wall seconds of /usr/bin/time -v's "h:mm:ss" or "m:ss".
row() {
  python3 - "$@" <<'EOF'
import re, sys
name, timefile, log = sys.argv[1], sys.argv[2], sys.argv[3]
t = open(timefile).read()
wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", t).group(1)
parts = [float(x) for x in wall.split(":")]
wall_s = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
user = float(re.search(r"User time \(seconds\): (\S+)", t).group(1))
sys_ = float(re.search(r"System time \(seconds\): (\S+)", t).group(1))
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1e6
build = re.findall(r"Finished `\S+` profile .* in (?:(\d+)m )?([\d.]+)s", open(log).read())
b = sum(60 * float(m or 0) + float(s) for m, s in build)
fmt = lambda s: f"{int(s // 60)} min {s % 60:.0f} s"
print(f"| `{name}` | {fmt(wall_s)} | {fmt(b)} | {user:.0f} s + {sys_:.0f} s | {rss:.2f} GB |")
EOF
}
if [ "$ONLY" != tests ]; then
  /usr/bin/time -v -o main.time cargo run --release --timings -- \
    --out "$CLONE/out/main_job" > main.log 2>&1
  row "cargo run --release" main.time main.log
fi
if [ "$ONLY" != main ]; then
  /usr/bin/time -v -o tests.time cargo test --workspace --all-features --timings > tests.log 2>&1 || {
    echo "the tests failed: $CLONE/tests.log" >&2; KEEP=1; }
  row "cargo test --workspace --all-features" tests.time tests.log
  grep -E "^test result" tests.log | awk '{p += $4; f += $6; i += $8} END {print "tests: " p " passed, " f " failed, " i " ignored"}'
fi
echo
echo "timings reports: $CLONE/target/cargo-timings/ (kept with KEEP=1)"
