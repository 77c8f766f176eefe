#!/usr/bin/env bash
# A model that does not fit in memory while it is built ends with exit code 2, a message naming what
# did not fit and its size, and no result file (docs/contracts.md, "Memory"). The allocation failure is
# made deterministic with an address-space limit (`ulimit -v`, RLIMIT_AS) in a subshell, on a deck whose
# element count passes the memory estimate at its count field but whose element sets do not fit: a line
# of 10,000 elements (estimate 61.8 MB) and 2,500 sets of every element (40 kB each, 100 MB in
# the builder and as much again in the model).
#
# The limits, with their margins: uniarc itself (program, gfortran runtime, LAPACK, libc) occupies
# about 13 MB of address space when the count field is read (VmSize in /proc/self/status), so the
# count check needs about 13 + 62 = 75 MB; the sets need 13 + 100 MB in the builder and 13 + 200 MB
# with the model's copy. Measured with the Release build, every limit from 76 to 125 MB fails while
# the sets are built (at the card, `sets.inp:LINE:`), every one from 130 to 200 MB while finish_model
# copies them, and 210 MB passes both and is refused by the whole model's estimate. The test uses
# 100 MB and 160 MB, each about 40 MB from the ends of its range. A control run of the same line with
# 10 sets under 100 MB must succeed, so that a limit too tight for the runtime itself shows as a
# failure of this test, not as a pass.
#
# A sweep of limits then checks the contract over the whole range, whatever the build: every run under
# any limit ends with exit code 2 (the model does not fit: one line naming what and its size, no file),
# 1 (the analysis ran out of memory: "analysis failed: out of memory: cannot allocate WHAT (SIZE)",
# the rows written so far complete) or 0 (complete files) — never a signal (SIGSEGV: an unchecked copy
# of a derived type, which gfortran 12 does not check), never the runtime's text. Which of the three a
# limit gives depends on the build (Debug and Release differ in their address space by a few MB), so
# the sweep asserts the contract only; the outcomes asserted exactly are chosen far from the edges.
# Three models: a beam of 10,000 elements on a tensionless Winkler bed (10,001 contact candidates, 4
# path steps; peak resident 35 MB, Release), limits 30 to 110 MB every 8 MB; and a cantilever of
# 10,000 nodes with 300 analysis steps (*STEP, a tip load each; the deck holds 360 kB per step), limits
# 50 to 140 MB every 10 MB, all of which end while the deck is read or at the estimate — the range where
# the Release build crashed in the copies of a step's supports (an array function result that gfortran
# -O2 allocates unchecked, located with gdb). Exactly asserted: the bed under 30 MB is refused at its
# element count (its estimate, 61.8 MB, exceeds the 15 MB left), under 300 MB it runs (exit 0, 10 rows);
# the many-step deck under 90 MB is refused while its steps are read (at `steps.inp:LINE`; the Debug
# build: from about 76 to 120 MB; under 75 MB its estimate, 61.8 MB with the 64 states of the path trace, refuses it first).
# Three more reach the analysis' other checked allocations (docs/contracts.md, "Memory"): Walker's arch
# of 2,000 elements whose imperfection is computed by a first run (*IMPERFECTION without FILE=: copies
# of the model for the perfect and the imperfect structure, the nodal mode), limits 30 to 46 MB; the
# pinned strut of 2,000 elements on a tensionless bed followed onto its secondary branch (*PATH,
# SWITCH=1: the state at the bifurcation, Riks' corrections, the mode table of *OUTPUT, MODES, the
# lift-off stability test), limits 36 to 52 MB. Both fit the memory estimate with its margin (16 MB
# for the program itself), so their sweeps end at the estimate (exit code 2) or run (exit code 0): the
# contract is asserted there, and under 300 MB that each does what it is for (a limit point of the
# imperfect arch; a branch switch and its mode in STEM.modes). Only growth that the estimate does not
# count (the analysis steps of `paths`) reaches the analysis' refusals: the same 120 steps on a
# tensionless bed would reach the contact LCP's, but take 80 s a run (Release), too long for the suite.
# Further binaries (the other build type) may follow WORKDIR; the sweep runs with each.
#
# AddressSanitizer reserves terabytes of shadow memory and ignores such limits: with an ASan build the
# test is skipped (exit code 77).
#   test_out_of_memory.sh UNIARC WORKDIR [UNIARC ...]
set -euo pipefail
uniarc=$(readlink -f "$1") work=$2
shift 2
others=()
for other in "$@"; do others+=("$(readlink -f "$other")"); done
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
if ldd "$uniarc" 2>/dev/null | grep -q libasan; then echo "skipped: ASan build (ignores ulimit -v)"; exit 77; fi

# deck: a cantilever of n elements and `sets` element sets of all of them, pulled at its tip (a bar:
# condition number n; a tip force across it would bend 10 000 elements, condition number about n^4 =
# 1e16, which the static analysis refuses as not in equilibrium — its deflection was 28 % off)
write_deck() {
  local name=$1 n=$2 sets=$3 k
  {
    echo "*SECTION, NAME=beam, STIFFNESS"
    echo "1e4, 2"
    echo "*LINE, ELSET=beam, SECTION=beam"
    echo "0, 0, 10, 0, $n"
    echo "*BOUNDARY"
    echo "beam_start, FIXED"
    echo "*CLOAD"
    echo "beam_end, FX, 1e-3"
    for ((k = 1; k <= sets; k++)); do
      echo "*ELSET, ELSET=s$k, GENERATE"
      echo "1, $n"
    done
    echo "*STATIC"
  } > "$name.inp"
}
write_deck control 10000 10
write_deck sets 10000 2500

# run DECK LIMIT_MB: uniarc under an address-space limit; rc, stdout and stderr in DECK.{rc,out,err}
run() {
  local deck=$1 limit_mb=$2 rc=0
  rm -rf "out_$deck"
  ( ulimit -v $((limit_mb * 1024)); exec "$uniarc" "$deck.inp" -o "out_$deck" -q ) \
    > "$deck.out" 2> "$deck.err" || rc=$?
  echo "$rc" > "$deck.rc"
}

run control 100
[ "$(cat control.rc)" = 0 ] || fail "control run under 100 MB: exit $(cat control.rc): $(head -c 400 control.err)"
[ -s out_control/control.path ] || fail "control run under 100 MB wrote no control.path"

for limit in 100 160; do
  run sets $limit
  rc=$(cat sets.rc)
  err=$(head -c 2000 sets.err)
  [ "$rc" = 2 ] || fail "sets under $limit MB: exit $rc, expected 2: $err"
  # error: sets.inp[:LINE]: the model does not fit in memory: cannot allocate the members of element set 's7' ... (40.0 kB): ...
  # (or the grown list of the element sets itself, whichever allocation the limit refuses first)
  echo "$err" | grep -Eq "^error: sets\.inp(:[0-9]+)?: the model does not fit in memory: cannot allocate ((the work arrays of )?the members of element set 's[0-9]+'( in the model)?|the list of element sets) \([0-9.]+ [kMG]?B\): the system refused it \(stat [0-9]+\)$" \
    || fail "sets under $limit MB: unexpected message: $err"
  [ "$(wc -l < sets.err)" = 1 ] || fail "sets under $limit MB: more than one line on stderr: $err"
  if grep -Eqi "runtime error|segmentation|backtrace|nan" sets.err sets.out; then
    fail "sets under $limit MB: a crash or NaN: $err"
  fi
  if [ -d out_sets ] && [ -n "$(ls -A out_sets)" ]; then
    fail "sets under $limit MB: files left in the output directory: $(ls -A out_sets)"
  fi
  echo "sets under $limit MB: $err"
done

# --- The sweep. bed: the beam on the bed; steps: the cantilever of 300 analysis steps.
cat > bed.inp <<'DECK'
*PARAMETER
n = 10000
*SECTION, NAME=beam, STIFFNESS
1e4, 1
*LINE, ELSET=beam, SECTION=beam
-4, 0, 4, 0, n
*BOUNDARY
beam_mid, 1
*FOUNDATION, ELSET=beam, MODULUS=4, DIRECTION=90, NAME=bed
*CLOAD
beam_mid, FY, -1e-4
*TRACK
w0, beam_mid, UY, -1
*PATH, CONTROL=LOAD
increment = 0.25
steps = 4
DECK
{
  echo "*SECTION, NAME=beam, STIFFNESS"; echo "1e4, 2"
  echo "*LINE, ELSET=beam, SECTION=beam"; echo "0, 0, 10, 0, 9999"
  echo "*BOUNDARY"; echo "beam_start, FIXED"
  echo "*TRACK"; echo "w, beam_end, UY, -1"
  for ((k = 1; k <= 300; k++)); do
    printf '%s\n' "*STEP" "*CLOAD" "beam_end, FY, -1e-6" "*PATH, CONTROL=LOAD" "increment = 1" "lambda_max = 1" \
      "*END STEP"
  done
} > steps.inp
# paths: 120 path steps of the same cantilever, whose deck fits in about 60 MB; under 103 and 108 MB the
# analysis starts and runs out of memory after some 55 to 75 steps (each step's model holds the earlier
# steps' load patterns: 240 kB more per step), the exit-1 case with rows kept (measured: at the band
# matrix of the next analysis step, steps 56 and 67 with the Debug build, 63 and 73 with the Release
# one; before the rows were moved instead of copied, at the support reactions of steps 57 and 67, and
# a SIGSEGV there before those were checked).
head -n 8 steps.inp > paths.inp
for ((k = 1; k <= 120; k++)); do
  printf '%s\n' "*STEP" "*CLOAD" "beam_end, FY, -1e-6" "*PATH, CONTROL=LOAD" "increment = 1" "lambda_max = 1" \
    "*END STEP" >> paths.inp
done

# imperfect: Walker's arch (tests/regression/decks/walker_arch_full_imperfect_computed.inp) of 2,000
# elements, its imperfection computed by a first run to its first bifurcation
cat > imperfect.inp <<'DECK'
*PARAMETER
R = 100
alpha = 10
EI = 1.4
EA = 420
n = 2000
rise = R*(1 - cosd(alpha))
*SECTION, NAME=arch, STIFFNESS
EA, EI
*ARC, ELSET=arch, SECTION=arch
0, 0, R, 90 + alpha, 90 - alpha, n
*IMPERFECTION, BIFURCATION=1
1e-3
*BOUNDARY
arch_start, PINNED
arch_end, PINNED
*CLOAD
arch_mid, FY, -EI/R**2
*TRACK
w_crown, arch_mid, UY, -1
*PATH, CONTROL=ARCLENGTH, ITERATION=CHAN
increment = 5
steps = 12
lambda_max = 200
DECK
# switch: the pinned strut on a tensionless bed (tests/regression/decks/strut_on_tensionless_bed_switch.inp)
# of 2,000 elements, onto its secondary branch at the lift-off bifurcation
cat > switch.inp <<'DECK'
*PARAMETER
n = 2000
*SECTION, NAME=s, STIFFNESS
1e4, 1
*LINE, ELSET=strut, SECTION=s
0, 0, 10, 0, n
*BOUNDARY
strut_start, PINNED
strut_end, ROLLER_X
*FOUNDATION, ELSET=strut, MODULUS=1, DIRECTION=90, NAME=bed
*CLOAD
strut_end, FX, -1
*TRACK
w_mid, strut_mid, UY
*OUTPUT, MODES
*PATH, SWITCH=1
increment = 0.01
max_increment = 1e5
steps = 6
lambda_max = 0.5
DECK

# contract BINARY DECK LIMIT_MB: the run's outcome is one the contract allows; prints it
contract() {
  local bin=$1 deck=$2 limit_mb=$3 rc=0 err what="$2 under $3 MB ($1)"
  rm -rf "out_$deck"
  ( ulimit -v $((limit_mb * 1024)); exec "$bin" "$deck.inp" -o "out_$deck" -q ) > "$deck.out" 2> "$deck.err" || rc=$?
  err=$(head -c 2000 "$deck.err")
  if grep -Eqi "runtime error|segmentation|backtrace|signal|fortran|error termination|^at line|(^|[^a-z])nan([^a-z]|$)" "$deck.err" "$deck.out"; then
    fail "$what: exit $rc, a crash or the runtime's text: $err"
  fi
  case $rc in
    0)
      [ ! -s "$deck.err" ] || fail "$what: exit 0 with a message: $err"
      [ -s "out_$deck/$deck.path" ] || fail "$what: exit 0 without $deck.path" ;;
    2)
      # one line, and under it the deck's line and a caret when the message has a column
      [ "$(wc -l < "$deck.err")" -le 3 ] || fail "$what: exit 2 with more than a message and its excerpt: $err"
      head -n 1 "$deck.err" | grep -Eq "^error: $deck\.inp(:[0-9]+(:[0-9]+)?)?: (the model does not fit in memory: (cannot allocate .+ \([0-9.]+ [kMGT]?B\): the system refused it \(stat [0-9]+\)|its analysis .+ would need about [0-9.]+ [kMGT]?B; [0-9.]+ [kMGT]?B available .+)|expected a number of elements whose analysis fits in memory: .+)$" \
        || fail "$what: exit 2 with a message that does not name what did not fit: $err"
      if [ -d "out_$deck" ] && [ -n "$(ls -A "out_$deck")" ]; then fail "$what: exit 2 left files: $(ls -A "out_$deck")"; fi ;;
    1)
      echo "$err" | grep -Eq "analysis failed: out of memory: cannot allocate .+ \([0-9.]+ [kMGT]?B\): the system refused it \(stat [0-9]+\)" \
        || fail "$what: exit 1 without the out-of-memory message: $err"
      if [ -f "out_$deck/$deck.path" ]; then
        # the rows kept are complete: as many fields as the header, the last line ended
        [ -z "$(tail -c 1 "out_$deck/$deck.path")" ] || fail "$what: the last row of $deck.path is cut"
        awk 'NR == 1 { n = NF } /^#/ { next } NF != n { exit 1 }' "out_$deck/$deck.path" \
          || fail "$what: a row of $deck.path is incomplete"
      fi ;;
    *) fail "$what: exit $rc (a signal or an exit code outside the contract): $err" ;;
  esac
  echo "$what: exit $rc ${err:0:160}"
}

for bin in "$uniarc" "${others[@]}"; do
  if ldd "$bin" 2>/dev/null | grep -q libasan; then continue; fi
  for ((limit = 30; limit <= 110; limit += 8)); do contract "$bin" bed $limit; done
  for ((limit = 50; limit <= 140; limit += 10)); do contract "$bin" steps $limit; done
  for limit in 103 108; do contract "$bin" paths $limit; done
  # far from the edges: the outcome itself
  contract "$bin" bed 30 > /dev/null
  grep -q "expected a number of elements whose analysis fits in memory" bed.err \
    || fail "bed under 30 MB ($bin): not refused at its element count: $(head -c 400 bed.err)"
  contract "$bin" bed 300 > /dev/null
  [ -s out_bed/bed.path ] && [ ! -s bed.err ] || fail "bed under 300 MB ($bin): did not run: $(head -c 400 bed.err)"
  # the header and the rows of λ = 0, 0.25, ..., 1
  [ "$(grep -vc '^#' out_bed/bed.path)" = 6 ] || fail "bed under 300 MB ($bin): not the 5 rows of its 4 steps"
  contract "$bin" steps 90 > /dev/null
  grep -Eq "^error: steps\.inp:[0-9]+: the model does not fit in memory: cannot allocate the (load pattern|supports)" steps.err \
    || fail "steps under 90 MB ($bin): not refused while its steps are read: $(head -c 400 steps.err)"
  for ((limit = 30; limit <= 46; limit += 2)); do contract "$bin" imperfect $limit; done
  for ((limit = 36; limit <= 52; limit += 4)); do contract "$bin" switch $limit; done
  contract "$bin" imperfect 300 > /dev/null
  [ -s out_imperfect/imperfect.crit ] && grep -q '^limit_max ' out_imperfect/imperfect.crit \
    || fail "imperfect under 300 MB ($bin): no limit point of the imperfect arch: $(head -c 400 imperfect.err)"
  contract "$bin" switch 300 > /dev/null
  grep -q '^branch_switch ' out_switch/switch.crit && [ -s out_switch/switch.modes ] \
    || fail "switch under 300 MB ($bin): no branch switch with its mode: $(head -c 400 switch.err)"
done
echo "PASS"
