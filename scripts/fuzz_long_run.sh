#!/usr/bin/env bash
# The long fuzz run of README "Sanitizers and fuzzing": every libFuzzer target of
# test/fuzz/targets.txt, each over a fresh copy of its seeds with a random seed, for the number of
# inputs given as TARGET=RUNS arguments (fuzz_generate, slow per input, as fuzz_generate=SECONDS),
# two targets at a time at nice 19. Uses the fuzz binaries that scripts/run_sanitizers.sh built
# in $SE3_WS/sanitize (run it first) and the exploration's options of that script. Prints a row
# per target (inputs, seconds, inputs/s, corpus size, finding) and the total; exits non-zero on
# a finding. Logs, corpora and any finding's input: $SE3_WS/fuzz_long_run/.
#   scripts/fuzz_long_run.sh fuzz_lie=4500000 fuzz_validate=3500000 fuzz_generate=300
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

build="$SE3_WS/sanitize"
out="$SE3_WS/fuzz_long_run"
rm -rf "$out"
mkdir -p "$out"

declare -A budget
for arg in "$@"; do
  budget[${arg%%=*}]=${arg#*=}
done

# One target's run in the background: its row goes to $out/$target.row.
run_target() {
  local target=$1 seeds=$2 max_len=$3 amount=$4 limit status=0 start runs seconds finding
  local corpus="$out/corpus_$target" artifacts="$out/artifacts_$target" log="$out/$target.log"
  mkdir -p "$artifacts"
  cp -r "$SE3_ROOT/$seeds" "$corpus"
  limit=(-runs="$amount")
  [ "$target" = fuzz_generate ] && limit=(-max_total_time="$amount")
  start=$SECONDS
  ASAN_OPTIONS=${SE3_FUZZ_ASAN_OPTIONS:-malloc_context_size=0} nice -n 19 \
    "$build/$target" "${limit[@]}" -seed=0 -rss_limit_mb=2048 -timeout=60 -max_len="$max_len" -len_control=10 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" >"$log" 2>&1 || status=$?
  seconds=$((SECONDS - start))
  runs=$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+)/\1/p' "$log" | tail -n 1)
  runs=${runs:-0}
  finding=none
  # slow-unit- inputs (above 10 s of wall time at nice 19 beside other jobs) are not findings
  if [ "$status" -ne 0 ] || [ -n "$(find "$artifacts" -type f ! -name 'slow-unit-*')" ]; then
    finding="yes (exit status $status, inputs: $artifacts)"
  fi
  echo "$target $runs $seconds $((runs / (seconds > 0 ? seconds : 1))) $(find "$SE3_ROOT/$seeds" -type f | wc -l) $(find "$corpus" -type f | wc -l) $finding" \
    >"$out/$target.row"
}

running=0
while read -r target seeds max_len; do
  [ -n "${budget[$target]:-}" ] || continue
  [ -x "$build/$target" ] || { echo "$build/$target is missing: run scripts/run_sanitizers.sh first" >&2; exit 2; }
  run_target "$target" "$seeds" "$max_len" "${budget[$target]}" &
  running=$((running + 1))
  if [ "$running" -ge 2 ]; then
    wait -n
    running=$((running - 1))
  fi
done < <(grep -vE '^(#|$)' "$SE3_ROOT/test/fuzz/targets.txt")
wait

total=0
findings=0
echo "target inputs seconds inputs/s seeds corpus finding"
for row in "$out"/*.row; do
  cat "$row"
  read -r _ runs _ _ _ _ finding <"$row"
  total=$((total + runs))
  [ "$finding" = none ] || findings=$((findings + 1))
done
echo "long run: $total inputs in all, $findings targets with findings"
[ "$findings" -eq 0 ]
