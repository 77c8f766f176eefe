#!/usr/bin/env bash
# A long fuzz campaign: N mutants of the example and test decks (default 10000) with a random seed (or
# --seed S), run on a Release build of uniarc, each with a timeout, against the exit-code contract
# (tests/fuzz/uniarc_fuzz.py, docs/testing.md "Fuzzing"). Writes OUT/summary.txt (counts per outcome,
# the failure classes with one mutant each) and OUT/summary.txt.json, and copies every failing mutant
# with its report to OUT/failures/. Exit status 0 if no mutant broke the contract, 1 if some did.
#
#   scripts/fuzz_campaign.sh [--count N] [--seed S] [--jobs J] [--timeout SECONDS] [--out DIR]
#                            [--uniarc EXE] [--known FILE]
#
# Without --uniarc it builds build/ (Release) first. A failure is reproduced with
#   python3 tests/fuzz/uniarc_fuzz.py --uniarc build/uniarc --seed S --only INDEX --keep DIR
set -euo pipefail
cd "$(dirname "$0")/.."

count=10000
seed=""
jobs=2
timeout=20
out=""
uniarc=""
known=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --count) count="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --uniarc) uniarc="$2"; shift 2 ;;
    --known) known="$2"; shift 2 ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "fuzz_campaign.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [[ -z "$seed" ]]; then
  seed=$(python3 -c 'import random; print(random.SystemRandom().randrange(1 << 31))')
fi
out=${out:-fuzz-campaign-$seed}
if [[ -z "$uniarc" ]]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$jobs" --target uniarc >/dev/null
  uniarc=build/uniarc
fi
mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/uniarc_fuzz_campaign.XXXXXX")
trap 'rm -rf "$work"' EXIT

arguments=(--uniarc "$uniarc" --seed "$seed" --count "$count" --jobs "$jobs" --timeout "$timeout"
           --work "$work" --keep "$out/failures" --summary "$out/summary.txt")
[[ -n "$known" ]] && arguments+=(--known "$known")
echo "fuzz campaign: python3 tests/fuzz/uniarc_fuzz.py ${arguments[*]}" | tee "$out/command.txt"
status=0
python3 tests/fuzz/uniarc_fuzz.py "${arguments[@]}" > "$out/log.txt" 2>&1 || status=$?
cat "$out/summary.txt" 2>/dev/null || tail -20 "$out/log.txt"
exit "$status"
