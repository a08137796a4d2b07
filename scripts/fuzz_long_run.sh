#!/usr/bin/env bash
# The long fuzz run of docs/testing.md "Sanitizers and fuzzing": every libFuzzer target of
# test/fuzz/targets.txt, each over a fresh copy of its seeds with a random seed, for the number of
# inputs given as TARGET=RUNS arguments (fuzz_generate, slow per input, as fuzz_generate=SECONDS),
# two targets at a time at nice 19. Uses the fuzz binaries that scripts/run_sanitizers.sh built
# in $SE3_WS/sanitize (run it first) and the exploration's options of that script. Prints a row
# per target (inputs, seconds, inputs/s, corpus size, finding) and the total; exits non-zero on
# a finding. Logs, corpora and any finding's input: $SE3_WS/fuzz_long_run/.
#   scripts/fuzz_long_run.sh fuzz_lie=4500000 fuzz_validate=3500000 fuzz_generate=300
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

# At nice 19 (every target inherits it), so that the machine stays usable meanwhile.
renice -n 19 -p $$ >/dev/null
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
  local target=$1 seeds=$2 max_len=$3 amount=$4 limit finding=none
  local corpus="$out/corpus_$target" artifacts="$out/artifacts_$target"
  mkdir -p "$artifacts"
  cp -r "$SE3_ROOT/$seeds" "$corpus"
  limit=(-runs="$amount")
  [ "$target" = fuzz_generate ] && limit=(-max_total_time="$amount")
  se3_fuzz_explore "$build/$target" "$corpus" "$artifacts" "$out/$target.log" "$max_len" 0 "${limit[@]}"
  [ -z "$se3_fuzz_finding" ] || finding="yes (exit status $se3_fuzz_status, inputs: $artifacts)"
  echo "$target $se3_fuzz_runs $se3_fuzz_seconds $((se3_fuzz_runs / (se3_fuzz_seconds > 0 ? se3_fuzz_seconds : 1)))" \
    "$(find "$SE3_ROOT/$seeds" -type f | wc -l) $(find "$corpus" -type f | wc -l) $finding" >"$out/$target.row"
}

while read -r target seeds max_len _; do
  [ -n "${budget[$target]:-}" ] || continue
  [ -x "$build/$target" ] || { echo "$build/$target is missing: run scripts/run_sanitizers.sh first" >&2; exit 2; }
  se3_start_job run_target "$target" "$seeds" "$max_len" "${budget[$target]}"
done < <(grep -vE '^(#|$)' "$SE3_ROOT/test/fuzz/targets.txt")
se3_finish_jobs

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
