#!/usr/bin/env bash
# A lock path OUTDIR/STEM.lock taken by something that is not a regular file — a FIFO, a directory, a
# dangling symbolic link — is refused at once: exit code 2, a message naming the path and what it is,
# no result file (docs/contracts.md, "Output directory"). Before issue 14 a FIFO blocked the run forever
# in the open() that read the lock's process id, SIGTERM notwithstanding. `timeout` is only a safety net
# (a hang ends the test as a failure instead of blocking the suite); the assertions are the exit code
# and the message.
#   test_lock_not_regular.sh UNIARC WORKDIR
set -u
uniarc=$1
work=$2
rm -rf "$work" && mkdir -p "$work"
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
deck=$source_dir/input/walker_arch.inp
failures=0

check() {   # check KIND: OUTDIR holds walker_arch.lock of that kind; expect exit 2 and the message
   local kind=$1 out=$work/$1 status message
   mkdir -p "$out"
   ls -A "$out" > "$work/$kind.before"
   timeout -k 5 30 "$uniarc" "$deck" -o "$out" -q 2> "$work/$kind.err"
   status=$?
   message=$(cat "$work/$kind.err")
   if [ "$status" -ne 2 ]; then
      echo "FAIL ($kind): exit code $status, expected 2 (124 or 137: the run hung); stderr: $message"
      failures=$((failures + 1))
   fi
   if ! grep -qF "error: $out/walker_arch.lock exists and is a $2, not the lock file of a uniarc run" \
         "$work/$kind.err"; then
      echo "FAIL ($kind): message does not name the lock and what it is: $message"
      failures=$((failures + 1))
   fi
   if ! ls -A "$out" | diff -q "$work/$kind.before" - > /dev/null; then
      echo "FAIL ($kind): files were left in $out: $(ls -A "$out")"
      failures=$((failures + 1))
   fi
}

mkdir -p "$work/fifo" && mkfifo "$work/fifo/walker_arch.lock"
check fifo FIFO
mkdir -p "$work/directory/walker_arch.lock"
check directory directory
mkdir -p "$work/link" && ln -s "$work/link/nowhere" "$work/link/walker_arch.lock"
check link 'symbolic link'

if [ "$failures" -ne 0 ]; then
   echo "$failures failure(s)"
   exit 1
fi
echo "every lock that is not a regular file refused with exit code 2"
