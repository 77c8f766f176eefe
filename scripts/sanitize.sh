#!/usr/bin/env bash
# uniarc under AddressSanitizer and UndefinedBehaviorSanitizer (docs/testing.md, "Sanitizers"):
# builds uniarc with -fsanitize=address,undefined, -O0 -g and the Debug build's FPE traps, but not its
# -fcheck=all (ASan checks the memory; the bounds checks add more of the reads of unallocated arrays'
# descriptors, GCC bug 77504, that UBSan reports as integer overflows), into build-sanitize/; runs the
# whole test suite there (every test runs the sanitized uniarc and unit-test executables), then a
# fixed-seed fuzz of N mutants (default 300) with the sanitized uniarc. An ASan report ends the process
# that makes it; UBSan's are printed and counted. Any report makes the status non-zero (and a mutant
# that prints one fails the fuzz).
#
#   scripts/sanitize.sh [--mutants N] [--jobs J] [--valgrind]
#
# --valgrind also runs every deck of input/ and tests/regression/decks under valgrind's memcheck with
# the plain Debug build (build-tests/, as scripts/test.sh makes it); valgrind and ASan cannot share a
# process. Writes build-sanitize/sanitize_summary.txt; exit status 0 if everything was clean.
set -euo pipefail
cd "$(dirname "$0")/.."

mutants=300
jobs=$(nproc)
valgrind=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --mutants) mutants="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --valgrind) valgrind=1; shift ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "sanitize.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

build=build-sanitize
summary=$build/sanitize_summary.txt
flags="-O0 -g -fbacktrace -ffpe-trap=invalid,zero,overflow -fsanitize=address,undefined -fno-omit-frame-pointer"
# A build type of its own, so that neither the Release nor the Debug flags of CMakeLists.txt apply.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_Fortran_FLAGS="$flags" \
      -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j"$jobs"

# halt_on_error: the first report ends the process with a non-zero status. No leak detection: the
# variables of a Fortran main program are never deallocated (the standard does not ask it at END
# PROGRAM), and LeakSanitizer reports each of them.
# allocator_may_return_null: an allocation too large for memory fails as the program expects (allocate
# with stat=, a message, exit code 2) instead of ASan aborting.
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=0:abort_on_error=0:exitcode=86:allocator_may_return_null=1
# UBSan reports and goes on (halt_on_error=0), so that one report does not hide the next: the summary
# counts the reports of each source line, and any report makes the status non-zero.
export UBSAN_OPTIONS=halt_on_error=0:print_stacktrace=1

status=0
{
  echo "uniarc sanitizers: $(date -u +%Y-%m-%dT%H:%MZ), $(git rev-parse --short HEAD 2>/dev/null || echo '?'), flags: $flags"
} > "$summary"

ctest_log=$build/sanitize_ctest.log
if ctest --test-dir "$build" -j"$jobs" --output-on-failure > "$ctest_log" 2>&1; then
  echo "test suite under ASan/UBSan: $(grep -E 'tests passed' "$ctest_log")" >> "$summary"
else
  status=1
  echo "test suite under ASan/UBSan FAILED: $(grep -E 'tests passed' "$ctest_log" || echo 'no summary')" >> "$summary"
  grep -E '^\s+[0-9]+ - ' "$ctest_log" >> "$summary" || true
fi
reports=$(grep -cE 'ERROR: AddressSanitizer|runtime error:' "$ctest_log" || true)
[[ $reports == 0 ]] || status=1
echo "sanitizer reports in the suite's output: $reports" >> "$summary"
grep -E 'ERROR: AddressSanitizer|runtime error:' "$ctest_log" | sed -E 's/^.*(src|tests)\//\1\//' | sort | uniq -c >> "$summary" || true

# The sanitized uniarc reserves terabytes of address space: no memory limit (--memory-mb 0).
fuzz_summary=$build/sanitize_fuzz.txt
if python3 tests/fuzz/uniarc_fuzz.py --uniarc "$build/uniarc" --seed 20261201 --count "$mutants" --jobs "$jobs" \
     --timeout 120 --memory-mb 0 --work "$build/fuzz_work" --keep "$build/fuzz_failures" \
     --known tests/fuzz/known_failures.txt --summary "$fuzz_summary" > "$build/sanitize_fuzz.log" 2>&1; then
  echo "fuzz under ASan/UBSan: $(sed -n 2,3p "$fuzz_summary" | tr '\n' ';')" >> "$summary"
else
  status=1
  echo "fuzz under ASan/UBSan FAILED (see $fuzz_summary):" >> "$summary"
  cat "$fuzz_summary" >> "$summary" 2>/dev/null || tail -5 "$build/sanitize_fuzz.log" >> "$summary"
fi

if [[ $valgrind == 1 ]]; then
  cmake -S . -B build-tests -DCMAKE_BUILD_TYPE=Debug >/dev/null
  cmake --build build-tests -j"$jobs" --target uniarc
  clean=0
  dirty=0
  for deck in input/*.inp tests/regression/decks/*.inp; do
    name=$(basename "$deck" .inp)
    out=$build/valgrind/$name
    rm -rf "$out"
    if valgrind -q --error-exitcode=99 --track-origins=yes build-tests/uniarc "$deck" -o "$out" -q \
         > "$build/valgrind_$name.log" 2>&1; then
      clean=$((clean + 1))
    else
      code=$?
      if [[ $code == 99 ]]; then
        dirty=$((dirty + 1))
        status=1
        where=$(grep -m1 -E '^==[0-9]+==    (at|by) .*\(.*\.f90:[0-9]+\)' "$build/valgrind_$name.log" | sed 's/.*: //')
        echo "valgrind: $deck: $(grep -m1 -E '^==[0-9]+== [A-Z]' "$build/valgrind_$name.log" | sed 's/^==[0-9]*== //') at $where" >> "$summary"
      else
        clean=$((clean + 1))   # the deck's own exit code (e.g. 1); memcheck found nothing
      fi
    fi
  done
  echo "valgrind memcheck (Debug build): $clean decks clean, $dirty with reports" >> "$summary"
fi

cat "$summary"
exit "$status"
