#!/usr/bin/env bash
# Instructions per core operation, counted by valgrind's callgrind (deterministic, unlike
# wall-clock timings): bench/count_ops runs each operation N = 0 and N = 2000 times and the
# difference of the two totals, divided by 2000, is the cost of one operation.
#
# Usage: scripts/instruction_counts.sh            print the table
#        scripts/instruction_counts.sh --check    compare with bench/instruction_counts.txt and
#                                                 check bench/instruction_targets.txt; exit 1 if any
#                                                 count grew by more than 10 % or a target is missed
#                                                 (last line: `instructions: N passed, N failed`,
#                                                 a row or a target a test)
#        scripts/instruction_counts.sh --update   rewrite bench/instruction_counts.txt (the rows of
#                                                 peers not given are kept as committed)
# The driver is built with g++ -O2 -DNDEBUG (default x86-64 flags, no catkin) into
# $SE3_WS/bench; counts depend on the compiler, whose version the results file records.
# A run takes about 2 minutes of one core (48 callgrind runs); run_tests.sh runs the check beside the
# sanitizers' tests, which run one at a time.
# Optional peers (bench/bench_peers.h: Sophus, manif, basalt), counted when a local copy is given:
# SE3_BENCH_SOPHUS_DIR, SE3_BENCH_MANIF_DIR, SE3_BENCH_BASALT_DIR (see se3_bench_peer_setup in
# scripts/common.sh). Without them their committed rows are reported as skipped, not as failures.
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

mode=print
case "${1:-}" in
  "") ;;
  --check) mode=check ;;
  --update) mode=update ;;
  *)
    echo "usage: $0 [--check | --update]" >&2
    exit 2
    ;;
esac

REPEATS=2000
TOLERANCE=0.10
RESULTS="$SE3_ROOT/bench/instruction_counts.txt"
TARGETS="$SE3_ROOT/bench/instruction_targets.txt"
OUT="$SE3_WS/bench"
CXX=${CXX:-g++}
CXXFLAGS="-std=c++17 -O2 -DNDEBUG"
mkdir -p "$OUT"

command -v valgrind >/dev/null || { echo "valgrind not found (apt-get install valgrind)" >&2; exit 2; }
se3_bench_peer_setup || exit 2

# Rebuild the driver when it is missing, older than any source it includes, or built with other
# peers.
driver="$OUT/count_ops"
stamp="$driver.peers"
if [ ! -x "$driver" ] || [ "$(cat "$stamp" 2>/dev/null)" != "${se3_bench_peer_flags[*]}" ] ||
  [ -n "$(find "$SE3_ROOT/bench" "$SE3_ROOT/include" \( -name '*.h' -o -name count_ops.cpp \) -newer "$driver" | head -n 1)" ]; then
  echo "building $driver ($CXX $CXXFLAGS; peers: ${se3_bench_peers:-none})" >&2
  # shellcheck disable=SC2086
  "$CXX" $CXXFLAGS -I"$SE3_ROOT/include" -I/usr/include/eigen3 "${se3_bench_peer_flags[@]}" \
    "$SE3_ROOT/bench/count_ops.cpp" -o "$driver.$$" -lorocos-kdl && mv "$driver.$$" "$driver"
  echo "${se3_bench_peer_flags[*]}" >"$stamp"
fi

compiler="$("$CXX" --version | head -n 1)"
# Per-run scratch (two runs at once, e.g. run_benchmarks.sh and a --check, must not share files).
scratch=$(mktemp -d "$OUT/instruction_counts.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
callgrind_total() {
  local file="$scratch/callgrind.$1.$2.out"
  valgrind --tool=callgrind --callgrind-out-file="$file" "$driver" "$1" "$2" >/dev/null 2>"$scratch/callgrind.log" || {
    cat "$scratch/callgrind.log" >&2
    echo "callgrind run of '$1 $2' failed" >&2
    exit 2
  }
  awk '/^(summary|totals):/ { v = $2 } END { print v }' "$file"
  rm -f "$file"
}

measured="$scratch/measured"
: >"$measured"
for op in $("$driver" --list); do
  base=$(callgrind_total "$op" 0)
  full=$(callgrind_total "$op" "$REPEATS")
  echo "$op $(( (full - base + REPEATS / 2) / REPEATS ))" >>"$measured"
done

write_table() {
  echo "# Instructions per operation (callgrind Ir; totals of N = $REPEATS minus N = 0, divided by $REPEATS)."
  echo "# Driver: bench/count_ops.cpp, $CXX $CXXFLAGS (default x86-64 flags); compiler: $compiler"
  echo "# Check: scripts/instruction_counts.sh --check (fails when a count grows by more than 10 % or a"
  echo "# target of bench/instruction_targets.txt is missed);"
  echo "# regenerate: scripts/instruction_counts.sh --update."
  echo "# Rows sophus_*, manif_*, basalt_*: optional peers (SE3_BENCH_*_DIR), kept by --update without them."
  awk '{ printf "%-40s %10d\n", $1, $2 }' "$measured"
}

case "$mode" in
  print)
    write_table
    ;;
  update)
    # The committed rows of peers not given this time are kept (they were measured with them).
    if [ -f "$RESULTS" ]; then
      awk -v peers=" $se3_bench_peers " 'FNR == NR { measured[$1] = 1; next }
        $0 !~ /^#/ && NF == 2 && !($1 in measured) && $1 ~ /^(sophus|manif|basalt)_/ {
          peer = $1; sub(/_.*/, "", peer); if (index(peers, " " peer " ") == 0) print $1, $2 }' \
        "$measured" "$RESULTS" >"$scratch/kept"
      cat "$scratch/kept" >>"$measured"
    fi
    write_table >"$RESULTS"
    cat "$RESULTS"
    echo "wrote $RESULTS"
    ;;
  check)
    [ -f "$RESULTS" ] || { echo "$RESULTS does not exist; run with --update" >&2; exit 1; }
    committed_compiler=$(sed -n 's/^# Driver: .*compiler: //p' "$RESULTS")
    [ "$committed_compiler" = "$compiler" ] ||
      echo "note: the committed counts were made with '$committed_compiler', this is '$compiler'" >&2
    awk -v tol="$TOLERANCE" -v peers=" $se3_bench_peers " '
      FILENAME == ARGV[1] { if ($0 !~ /^#/ && NF == 2) committed[$1] = $2; next }
      FILENAME == ARGV[2] { measured[$1] = $2; order[++n] = $1; next }
      $0 !~ /^#/ && NF == 3 { target[++m] = $0 }
      END {
        for (i = 1; i <= n; ++i) {
          op = order[i]
          if (!(op in committed)) { printf "%-40s %10d  NEW (not in the results file)\n", op, measured[op]; ++failed; continue }
          change = (measured[op] - committed[op]) / committed[op]
          verdict = change > tol ? "GREW" : "ok"
          if (change > tol) ++failed; else ++passed
          printf "%-40s %10d  committed %10d  %+6.1f %%  %s\n", op, measured[op], committed[op], 100 * change, verdict
        }
        for (op in committed)
          if (!(op in measured)) {
            peer = op; sub(/_.*/, "", peer)
            if (op ~ /^(sophus|manif|basalt)_/ && index(peers, " " peer " ") == 0)
              printf "%-40s  skipped (no SE3_BENCH_%s_DIR given)\n", op, toupper(peer)
            else { printf "%-40s  MISSING (in the results file, not measured)\n", op; ++failed }
          }
        for (i = 1; i <= m; ++i) {
          split(target[i], f, " ")
          if (!(f[1] in measured) || !(f[3] in measured)) {
            printf "target %s <= %s x %s: NOT MEASURED\n", f[1], f[2], f[3]; ++failed; continue
          }
          limit = f[2] * measured[f[3]]
          met = measured[f[1]] <= limit
          printf "target %-32s %10d <= %s x %s = %d: %s (ratio %.2f)\n", f[1], measured[f[1]], f[2], f[3], limit,
                 met ? "met" : "MISSED", measured[f[1]] / measured[f[3]]
          if (met) ++passed; else ++failed
        }
        if (failed) print "instruction counts: FAILED (more than " 100 * tol " % growth, a changed list, or a missed " \
                          "target); run scripts/instruction_counts.sh --update if a change of the counts is intended"
        else print "instruction counts: ok (no count grew by more than " 100 * tol " %, every target met)"
        printf "instructions: %d passed, %d failed\n", passed, failed
        exit failed ? 1 : 0
      }' "$RESULTS" "$measured" "$TARGETS"
    ;;
esac
