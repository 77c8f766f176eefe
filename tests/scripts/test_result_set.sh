#!/usr/bin/env bash
# Interrupts, the result set and the lock (issue 14, review rev14b; docs/contracts.md, "Interrupts",
# "Result files", "Output directory"). One case per call:
#   in_step      SIGTERM 1 s into a run that spends long in one contact step (its implicit Lemke
#                solver): exit 143 within a few seconds, "interrupted by SIGTERM after step 0", the
#                row of step 0 only, no lock or work directory left. Before: the step ran on for
#                minutes, the signal unheeded until it ended.
#   hangup       the same with SIGHUP: exit 129, "interrupted by SIGHUP after step 0", nothing left.
#   cpu_limit    the same run under `ulimit -S -t 1`: exit 152, "interrupted by SIGXCPU", nothing left.
#   check        SIGTERM 0.5 s into `uniarc --check` of a deck that takes seconds to read: exit 143
#                and "interrupted by SIGTERM". Before: exit 0, "check passed".
#   after_end    SIGTERM once the last row of a path that ends by its stop rule is written, while the
#                run writes its last large files: exit 143 with "interrupted by SIGTERM", or 0 when
#                the signal came after the run said it was complete; never 143 without the message.
#   rename_dir   OUTDIR/STEM.shape is a directory: exit 1 and no file of the run moved (the earlier
#                STEM.path unchanged). Before: 2 of 3 files moved, a mixed set.
#   stale_files  a --csv run, then a plain one; an earlier run's VTK snapshots past the new run's last
#                step: the files of STEM the new run did not write are removed. Before: they stayed.
#   stale_lock   STEM.lock of a process of this host that no longer exists: taken over with a note
#                on stderr, exit 0; a lock of a live process is still refused (exit 2).
# `timeout` is only a safety net (a hang ends the test as a failure instead of blocking the suite); the
# signal goes to `timeout`, which passes it on and sends SIGKILL only -k 120 s later.
#   test_result_set.sh UNIARC WORKDIR CASE
set -u
uniarc=$1
work=$2
case_name=$3
rm -rf "$work" && mkdir -p "$work"
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
decks=$source_dir/tests/regression/decks
failures=0
fail() {
   echo "FAIL ($case_name): $*"
   failures=$((failures + 1))
}
wait_for_row_0() {   # until the run's work directory holds its path table with row 0 (at most 60 s):
   # the signal then falls in the long contact step after it, on a loaded machine too (a fixed 1 s
   # sleep could fall before step 0 was written)
   local k
   for k in $(seq 600); do
      if [ "$(cat "$1"/.long_contact_step.part.*/long_contact_step.path 2> /dev/null | grep -c '^ *[0-9]')" -ge 1 ]; then
         return
      fi
      sleep 0.1
   done
}
rows() {   # the number of data rows (lines starting with a digit) of a table
   grep -c '^ *[0-9]' "$1" 2> /dev/null || echo 0
}

case $case_name in
in_step)
   out=$work/out
   timeout -k 120 300 "$uniarc" "$decks/long_contact_step.inp" -o "$out" -q 2> "$work/err" &
   pid=$!
   wait_for_row_0 "$out"
   sent=$(date +%s.%N)
   kill -TERM $pid
   wait $pid
   status=$?
   took=$(echo "$(date +%s.%N) - $sent" | bc)
   cat "$work/err"
   [ "$status" -eq 143 ] || fail "exit code $status, expected 143 (124: the step ran on past the signal)"
   # A few seconds: the poll is once per Lemke pivot (two banded solves of this 3000-dof model) or Newton
   # iteration; 10 s leaves room for a loaded machine.
   if [ "$(echo "$took > 10" | bc)" -eq 1 ]; then fail "the run took $took s to end after the signal"; fi
   grep -q 'interrupted by SIGTERM after step 0' "$work/err" || fail 'stderr lacks "interrupted by SIGTERM after step 0"'
   [ "$(rows "$out/long_contact_step.path")" -eq 1 ] || fail "long_contact_step.path does not hold row 0 alone"
   ls -A "$out" | grep -q 'lock\|part' && fail "left behind: $(ls -A "$out")"
   ;;
hangup)
   # SIGHUP (the terminal closed) asks the run to stop as SIGTERM does (review of issue 14: it killed
   # the run, exit 129 without a word, the lock and work directory left)
   out=$work/out
   timeout -k 120 300 "$uniarc" "$decks/long_contact_step.inp" -o "$out" -q 2> "$work/err" &
   pid=$!
   wait_for_row_0 "$out"
   kill -HUP $pid
   wait $pid
   status=$?
   cat "$work/err"
   [ "$status" -eq 129 ] || fail "exit code $status, expected 129"
   grep -q 'interrupted by SIGHUP after step 0' "$work/err" || fail 'stderr lacks "interrupted by SIGHUP after step 0"'
   [ "$(rows "$out/long_contact_step.path")" -eq 1 ] || fail "long_contact_step.path does not hold row 0 alone"
   ls -A "$out" | grep -q 'lock\|part' && fail "left behind: $(ls -A "$out")"
   ;;
cpu_limit)
   # SIGXCPU of the soft CPU-time limit (`ulimit -S -t 1`) asks the run to stop; the kernel repeats it
   # every CPU-second past the limit, and the handler stays (review of issue 14: the second one killed
   # a run whose wind-down took more than a second)
   out=$work/out
   (ulimit -S -t 1; exec timeout -k 120 300 "$uniarc" "$decks/long_contact_step.inp" -o "$out" -q) 2> "$work/err"
   status=$?
   cat "$work/err"
   [ "$status" -eq 152 ] || fail "exit code $status, expected 152"
   grep -q 'interrupted by SIGXCPU' "$work/err" || fail 'stderr lacks "interrupted by SIGXCPU"'
   ls -A "$out" | grep -q 'lock\|part' && fail "left behind: $(ls -A "$out")"
   ;;
check)
   # 200000 parameters: about 2 s to read (Release build)
   deck=$work/many_parameters.inp
   {
      echo '*PARAMETER'
      seq 0 199999 | sed 's/.*/p& = &/'
      printf '*SECTION, NAME=s, STIFFNESS\n1e3, 1\n*LINE, ELSET=b, SECTION=s\n0, 0, 1, 0, 4\n'
      printf '*BOUNDARY\nb_start, FIXED\n*CLOAD\nb_end, FY, -1\n'
   } > "$deck"
   timeout -k 120 300 "$uniarc" --check "$deck" > "$work/out" 2> "$work/err" &
   pid=$!
   # until uniarc (timeout's child) catches SIGTERM (bit 15 of SigCgt in /proc), at most 6 s: a fixed
   # 0.5 s could fall before it had started on a loaded machine, and the default action killed it
   # without its message
   for _ in $(seq 600); do
      child=$(pgrep -P $pid | head -n 1)
      # (the child is uniarc once it has exec'd: before, it is a copy of timeout, which catches SIGTERM too)
      if [ -n "$child" ] && [ "$(cat /proc/$child/comm 2> /dev/null)" = uniarc ] && \
         [ $(( 0x$(awk '/^SigCgt/ {print $2}' /proc/$child/status 2> /dev/null || echo 0) & 0x4000 )) -ne 0 ]; then
         break
      fi
      sleep 0.01
   done
   sleep 0.05
   kill -TERM $pid
   wait $pid
   status=$?
   cat "$work/err"
   [ "$status" -eq 143 ] || fail "exit code $status, expected 143 (0: the check ignored the signal)"
   grep -q 'interrupted by SIGTERM' "$work/err" || fail 'stderr lacks "interrupted by SIGTERM"'
   grep -q 'check passed' "$work/out" && fail 'the check said it passed'
   ;;
after_end)
   out=$work/out
   part=
   timeout -k 120 300 "$uniarc" "$decks/long_finish.inp" -o "$out" -q 2> "$work/err" &
   pid=$!
   # the last row (step 2, the step limit) in the work directory: the path has ended by its stop rule
   for _ in $(seq 1 3000); do
      part=$(ls -d "$out"/.long_finish.part.* 2> /dev/null | head -1)
      if [ -n "$part" ] && grep -q '^ *2 ' "$part/long_finish.path" 2> /dev/null; then break; fi
      sleep 0.02
   done
   kill -0 $pid 2> /dev/null || fail 'the run ended before the signal could be sent (the test measures nothing)'
   kill -TERM $pid
   wait $pid
   status=$?
   cat "$work/err"
   if [ "$status" -eq 143 ]; then
      grep -q 'interrupted by SIGTERM after the path had ended' "$work/err" ||
         fail 'exit code 143 without "interrupted by SIGTERM after the path had ended"'
   elif [ "$status" -ne 0 ]; then
      fail "exit code $status, expected 143 with its message, or 0"
   fi
   [ "$(rows "$out/long_finish.path")" -eq 3 ] || fail "long_finish.path does not hold rows 0..2"
   ;;
rename_dir)
   out=$work/out
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q 2> "$work/err0" ||
      fail 'the first run failed'
   cp "$out/cantilever_tip_moment.path" "$work/path.before"
   rm "$out/cantilever_tip_moment.shape"
   mkdir "$out/cantilever_tip_moment.shape"
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q -D M=0.6 2> "$work/err"
   status=$?
   cat "$work/err"
   [ "$status" -eq 1 ] || fail "exit code $status, expected 1"
   grep -q 'cantilever_tip_moment.shape is a directory; no result file of this run was moved' "$work/err" ||
      fail 'the message does not say the directory and that nothing was moved'
   cmp -s "$work/path.before" "$out/cantilever_tip_moment.path" || fail 'the earlier .path was replaced'
   [ -e "$out/cantilever_tip_moment.crit" ] || fail 'the earlier .crit is gone'
   ls -A "$out" | grep -q 'lock\|part' && fail "left behind: $(ls -A "$out")"
   ;;
stale_files)
   out=$work/out
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q --csv 2> "$work/err0" ||
      fail 'the --csv run failed'
   [ -e "$out/cantilever_tip_moment.path.csv" ] || fail 'the --csv run wrote no .path.csv'
   # snapshots of an earlier, longer run (the deck writes none: any STEM_NNNN.vtp is not this run's)
   echo stale > "$out/cantilever_tip_moment_0999.vtp"
   echo stale > "$out/cantilever_tip_moment_mode_01.vtp"
   echo other > "$out/cantilever_tip_moment_notes.txt"
   echo other > "$out/cantilever_tip_moment_0999.vtp.bak"
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q 2> "$work/err" ||
      fail 'the plain run failed'
   cat "$work/err"
   for name in path.csv crit.csv shape.csv _0999.vtp _mode_01.vtp; do
      case $name in _*) file=cantilever_tip_moment$name ;; *) file=cantilever_tip_moment.$name ;; esac
      [ -e "$out/$file" ] && fail "$file of the earlier run is still there"
   done
   for file in cantilever_tip_moment.path cantilever_tip_moment.crit cantilever_tip_moment.shape \
      cantilever_tip_moment_notes.txt cantilever_tip_moment_0999.vtp.bak; do
      [ -e "$out/$file" ] || fail "$file is gone (the run's own, or not a name uniarc writes)"
   done
   ;;
stale_lock)
   out=$work/out
   mkdir -p "$out"
   # a process of this host that has ended: its pid is free (until reused; a reused pid is live and the
   # lock refused, which the test reports as a failure to take over: rerun)
   sh -c 'exit 0' &
   dead=$!
   wait $dead
   printf 'pid %s\nhost %s\n' "$dead" "$(hostname)" > "$out/cantilever_tip_moment.lock"
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q 2> "$work/err"
   status=$?
   cat "$work/err"
   [ "$status" -eq 0 ] || fail "exit code $status with a stale lock, expected 0"
   grep -q "note: removed the stale lock .*cantilever_tip_moment.lock of process $dead" "$work/err" ||
      fail 'no note of the stale lock taken over'
   [ -e "$out/cantilever_tip_moment.lock" ] && fail 'the lock was left'
   # a live process's lock (this shell's) is refused
   printf 'pid %s\nhost %s\n' "$$" "$(hostname)" > "$out/cantilever_tip_moment.lock"
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q 2> "$work/err2"
   status=$?
   [ "$status" -eq 2 ] || fail "exit code $status with a live lock, expected 2"
   grep -q 'exists: another uniarc run' "$work/err2" || fail 'the live lock was not refused'
   # another host's lock is refused even if its pid is free here
   printf 'pid %s\nhost %s\n' "$dead" "not-$(hostname)" > "$out/cantilever_tip_moment.lock"
   timeout -k 5 60 "$uniarc" "$decks/cantilever_tip_moment.inp" -o "$out" -q 2> /dev/null
   status=$?
   [ "$status" -eq 2 ] || fail "exit code $status with another host's lock, expected 2"
   ;;
*)
   echo "unknown case $case_name"
   exit 2
   ;;
esac

if [ "$failures" -ne 0 ]; then
   echo "$failures failure(s)"
   exit 1
fi
echo "ok: $case_name"
