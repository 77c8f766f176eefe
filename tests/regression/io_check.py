#!/usr/bin/env python3
"""What a run leaves in OUTDIR when the result files cannot be written, or OUTDIR is in use
(docs/contracts.md, "Result files on failure").

  io_check.py --uniarc EXE --deck DECK --out DIR --file-size-limit KIB [--expect-file NAME]
      A run whose files outgrow a file size limit (RLIMIT_FSIZE, `ulimit -f`; no root needed): writes
      past it fail with EFBIG, as on a full file system. Expects exit code 1, a message naming the
      result file and the system's words ("File too large"), and OUTDIR left without any file of the
      run: no final name, no lock, no work directory. The same run without the limit must succeed and
      write a file larger than the limit (else the check would prove nothing). With --expect-file
      the message must name OUTDIR/NAME, the file that meets the limit first.

  io_check.py --uniarc EXE --deck DECK --out DIR --lock
      OUTDIR/STEM.lock made by hand, as another run would hold it: the run must refuse with exit code 2
      and the documented message, write nothing and leave the lock alone. Once the lock is removed the
      same run succeeds and leaves neither a lock nor a work directory.

  io_check.py --uniarc EXE --deck DECK --out DIR --unusable-outdir
      OUTDIR below a regular file (DIR/file/results), which no one can create: exit code 2 (bad input,
      issue 14: it was 1), "cannot create output directory DIR/file/results: Not a directory", and the
      analysis never starts (no output on stdout).

  io_check.py --uniarc EXE --deck DECK --out DIR --stems
      OUTDIR shared with other files of like names: (1) a copy of DECK named STEM.path, and one named
      STEM.modes, in OUTDIR, and a deck walker.inp beside a link STEM.path to it: refused with exit code
      2 ("expected a deck whose file is not one of its own result files"), the deck unchanged (a run replaced the first with its path table and removed
      the second as a stale result); (2) the VTK snapshots STEM_mode_NNNN.vtp of a deck STEM_mode beside
      a run of STEM: all kept (they were removed as modes of STEM); (3) a lock STEM.lock that names the
      run's own process id on this host (a container's PID namespace gives a killed run's id to the
      next one): taken over as stale, the run succeeds (it refused, "another uniarc run (pid 1)").
"""
import argparse
import os
import resource
import shutil
import subprocess
import sys


def run(uniarc, deck, out, limit_bytes=None):
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))
    return subprocess.run([uniarc, deck, '-o', out, '-q'], capture_output=True, text=True, timeout=600,
                          preexec_fn=limit if limit_bytes is not None else None)


def fresh(directory):
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)


def check_file_size_limit(args, stem, failures):
    reference = os.path.join(args.out, 'unlimited')
    fresh(reference)
    result = run(args.uniarc, args.deck, reference)
    if result.returncode != 0:
        failures.append(f'the run without a limit exited with {result.returncode}: {result.stderr}')
        return
    largest = max(os.path.getsize(os.path.join(reference, name)) for name in os.listdir(reference))
    limit_bytes = args.file_size_limit * 1024
    if largest <= limit_bytes:
        failures.append(f'no result file outgrows {limit_bytes} bytes (largest {largest}): choose a smaller limit')
        return

    limited = os.path.join(args.out, 'limited')
    fresh(limited)
    result = run(args.uniarc, args.deck, limited, limit_bytes)
    print(result.stderr, end='')
    if result.returncode != 1:
        failures.append(f'exit code {result.returncode}, expected 1')
    expected = f'error: cannot write {limited}/{args.expect_file or stem + "."}'
    if expected not in result.stderr:
        failures.append(f'stderr lacks "{expected}" (a message naming the result file)')
    if 'File too large' not in result.stderr:
        failures.append('stderr lacks the system\'s words "File too large"')
    left = sorted(os.listdir(limited))
    if left:
        failures.append(f'OUTDIR keeps files of the failed run: {left}')


def check_lock(args, stem, failures):
    out = os.path.join(args.out, 'locked')
    fresh(out)
    lock = os.path.join(out, stem + '.lock')
    with open(lock, 'w') as file:
        file.write('pid 4242\n')
    result = run(args.uniarc, args.deck, out)
    print(result.stderr, end='')
    if result.returncode != 2:
        failures.append(f'exit code {result.returncode} with the lock held, expected 2')
    expected = (f'error: {lock} exists: another uniarc run (pid 4242) is writing the results of {stem} '
                f'into {out}, or one was killed before it ended; remove {lock} once no run is using it')
    if expected not in result.stderr:
        failures.append(f'stderr lacks "{expected}"')
    left = sorted(os.listdir(out))
    if left != [stem + '.lock']:
        failures.append(f'OUTDIR should hold the lock only, holds {left}')
    elif open(lock).read() != 'pid 4242\n':
        failures.append('the refused run changed the lock of the other run')

    os.remove(lock)
    result = run(args.uniarc, args.deck, out)
    if result.returncode != 0:
        failures.append(f'without the lock the run exited with {result.returncode}: {result.stderr}')
    left = sorted(os.listdir(out))
    stray = [name for name in left if name.endswith('.lock') or name.startswith('.')]
    if stray:
        failures.append(f'a successful run left {stray}')
    for suffix in ('.path', '.crit', '.shape'):
        if stem + suffix not in left:
            failures.append(f'a successful run did not write {stem + suffix}')


def check_unusable_outdir(args, stem, failures):
    fresh(args.out)
    blocker = os.path.join(args.out, 'file')
    with open(blocker, 'w') as file:
        file.write('not a directory\n')
    out = os.path.join(blocker, 'results')
    result = subprocess.run([args.uniarc, args.deck, '-o', out], capture_output=True, text=True, timeout=600)
    print(result.stderr, end='')
    if result.returncode != 2:
        failures.append(f'exit code {result.returncode}, expected 2')
    expected = f'error: cannot create output directory {out}: Not a directory'
    if expected not in result.stderr:
        failures.append(f'stderr lacks "{expected}"')
    if result.stdout:
        failures.append(f'the analysis ran before OUTDIR was checked: stdout {result.stdout!r}')
    if sorted(os.listdir(args.out)) != ['file']:
        failures.append(f'files written: {sorted(os.listdir(args.out))}')


def check_stems(args, stem, failures):
    out = os.path.join(args.out, 'stems')
    fresh(out)
    text = open(args.deck).read()
    for suffix in ('.path', '.modes'):
        deck = os.path.join(out, stem + suffix)
        with open(deck, 'w') as file:
            file.write(text)
        result = subprocess.run([args.uniarc, deck, '-o', out, '-q'], capture_output=True, text=True,
                                timeout=600)
        print(result.stderr, end='')
        if result.returncode != 2:
            failures.append(f'deck {stem + suffix}: exit code {result.returncode}, expected 2')
        expected = (f'error: {deck}: expected a deck whose file is not one of its own result files: the '
                    f'results of {stem} in {out} include {stem + suffix}, which is the deck')
        if expected not in result.stderr:
            failures.append(f'deck {stem + suffix}: stderr lacks "{expected}"')
        if not os.path.exists(deck) or open(deck).read() != text:
            failures.append(f'deck {stem + suffix}: changed or removed by its own run')
        if sorted(os.listdir(out)) != [stem + suffix]:
            failures.append(f'deck {stem + suffix}: files written {sorted(os.listdir(out))}')
        os.remove(deck)

    # the deck under its own name, and a link named as a result file pointing at it
    deck = os.path.join(out, stem + '.inp')
    with open(deck, 'w') as file:
        file.write(text)
    os.symlink(stem + '.inp', os.path.join(out, stem + '.crit'))
    result = subprocess.run([args.uniarc, deck, '-o', out, '-q'], capture_output=True, text=True, timeout=600)
    print(result.stderr, end='')
    if result.returncode != 2 or f'include {stem}.crit, which is the deck' not in result.stderr:
        failures.append(f'a link {stem}.crit to the deck: exit code {result.returncode}, {result.stderr!r}')
    if open(deck).read() != text:
        failures.append('a link to the deck: the deck was changed')
    os.remove(os.path.join(out, stem + '.crit'))
    os.remove(deck)

    others = [f'{stem}_mode_{k:04d}.vtp' for k in (0, 10, 1000)] + [f'{stem}_mode.pvd', f'{stem}_mode.path']
    for name in others:
        with open(os.path.join(out, name), 'w') as file:
            file.write('another deck\n')
    result = run(args.uniarc, args.deck, out)
    if result.returncode != 0:
        failures.append(f'beside another deck\'s files: exit code {result.returncode}: {result.stderr}')
    kept = [name for name in others if os.path.exists(os.path.join(out, name))]
    if kept != others:
        failures.append(f'another deck\'s files removed: {sorted(set(others) - set(kept))}')

    own = os.path.join(args.out, 'own_pid')
    fresh(own)
    lock = os.path.join(own, stem + '.lock')
    host = os.uname().nodename

    def lock_with_own_pid():
        with open(lock, 'w') as file:
            file.write(f'pid {os.getpid()}\nhost {host}\n')
    result = subprocess.run([args.uniarc, args.deck, '-o', own, '-q'], capture_output=True, text=True,
                            timeout=600, preexec_fn=lock_with_own_pid)
    print(result.stderr, end='')
    if result.returncode != 0:
        failures.append(f'a lock naming the run\'s own pid: exit code {result.returncode}, expected 0')
    if 'note: removed the stale lock' not in result.stderr:
        failures.append('a lock naming the run\'s own pid: no note of the stale lock taken over')
    if os.path.exists(lock):
        failures.append('a lock naming the run\'s own pid: the lock is left')


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument('--file-size-limit', type=int, metavar='KIB')
    mode.add_argument('--lock', action='store_true')
    mode.add_argument('--unusable-outdir', action='store_true')
    mode.add_argument('--stems', action='store_true')
    parser.add_argument('--expect-file', metavar='NAME')
    args = parser.parse_args()
    args.out = os.path.abspath(args.out)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    failures = []
    if args.lock:
        check_lock(args, stem, failures)
    elif args.unusable_outdir:
        check_unusable_outdir(args, stem, failures)
    elif args.stems:
        check_stems(args, stem, failures)
    else:
        check_file_size_limit(args, stem, failures)
    for failure in failures:
        print('FAIL:', failure)
    if failures:
        return 1
    print('OK')
    return 0


if __name__ == '__main__':
    sys.exit(main())
