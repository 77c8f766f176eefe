#!/usr/bin/env python3
"""Decks that are large, deep or not files at all (issue 14): uniarc reads them in linear time, bounds
them with messages, and refuses what is not a deck (docs/input.md, "Limits"; docs/contracts.md).

  input_check.py --uniarc EXE --out DIR --scale PARAMETERS MEGABYTES
      A cantilever (EI = 1, L = 1) after PARAMETERS *PARAMETER lines, each built on the one before
      (p_i = p_(i-1) + 1), a comment line of MEGABYTES MiB and a *PARAMETER line of an expression of
      about MEGABYTES/4 MiB that looks up thousands of the parameters (its value is 0); the tip load is
      3 p_N / N + s = 3, so the tip deflection is -P L^3/(3 EI) = -1. Expects exit code 0 and w = -1 to
      1e-12 (a linear analysis: round-off only). Speed is not asserted (docs/benchmarks.md measures it);
      the test must finish under CTest's timeout.

  input_check.py --uniarc EXE --out DIR --long-error-line MEGABYTES
      A data line of MEGABYTES MiB (a *PARAMETER expression) with an error at its end: exit code 2,
      the message `deck:LINE:COL:` with the exact column, the line shown as a window around it (stderr
      under 1 KiB: the whole line was echoed before), and nothing written into OUTDIR.

  input_check.py --uniarc EXE --out DIR --not-a-file
      A directory, /dev/null, /dev/zero and a FIFO given as the deck: each refused at once with exit
      code 2 and `PATH: expected a regular file as the deck, found a ...`, nothing written; a kernel
      file of reported size 0 (/proc/self/status) read to its end: refused at 1:1 as no card.

  input_check.py --uniarc EXE --out DIR --empty-outdir
      `-o ''` (which wrote the result files to /): exit code 2, `option -o needs a directory`, nothing
      written into the working directory.
"""
import argparse
import os
import shutil
import subprocess
import sys

CANTILEVER = ('*SECTION, NAME=s, STIFFNESS\n1e3, 1\n*LINE, ELSET=b, SECTION=s\n0, 0, 1, 0, 4\n'
              '*BOUNDARY\nb_start, FIXED\n*CLOAD\nb_end, FY, -P\n*TRACK\nw, b_end, UY\n')


def fresh(directory):
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)


def run(command, cwd=None, timeout=600):
    result = subprocess.run(command, capture_output=True, timeout=timeout, cwd=cwd)
    stderr = result.stderr.decode(errors='replace')
    print(f'$ {" ".join(command)}\nexit code {result.returncode}; stderr {len(result.stderr)} bytes:')
    print(stderr[:2000])
    return result.returncode, stderr


def last_value(path, column):
    with open(path) as handle:
        lines = [line for line in handle.read().splitlines() if line.strip()]
    names = lines[0][1:].split()
    return float(lines[-1].split()[names.index(column)])


def check_scale(args, failures):
    parameters, megabytes = args.scale
    work = os.path.join(args.out, 'scale')
    fresh(work)
    deck = os.path.join(work, 'scale.inp')
    terms = max(1, (megabytes << 20) // 4 // 24)   # '+p123456-p123456' is up to 24 characters
    with open(deck, 'w') as handle:
        handle.write('** ' + 'x' * (megabytes << 20) + '\n*PARAMETER\np1 = 1\n')
        handle.write(''.join(f'p{i} = p{i - 1} + 1\n' for i in range(2, parameters + 1)))
        step = max(1, parameters // terms)
        handle.write('s = 0' + ''.join(f'+p{k}-p{k}' for k in range(1, parameters + 1, step)) + '\n')
        handle.write(f'P = 3*p{parameters}/{parameters} + s\n' + CANTILEVER)
    out = os.path.join(work, 'out')
    code, stderr = run([args.uniarc, deck, '-o', out, '-q'])
    if code != 0:
        failures.append(f'exit code {code}, expected 0')
        return
    w = last_value(os.path.join(out, 'scale.path'), 'w')
    if abs(w + 1.0) > 1e-12:
        failures.append(f'tip deflection {w!r}, expected -1 (to 1e-12)')
    os.remove(deck)


def check_long_error_line(args, failures):
    work = os.path.join(args.out, 'long_error_line')
    fresh(work)
    deck = os.path.join(work, 'long_error_line.inp')
    expression = 'x = 0' + '+1' * ((args.long_error_line << 20) // 2)
    with open(deck, 'w') as handle:
        handle.write('*PARAMETER\n' + expression + '+\n' + CANTILEVER)
    out = os.path.join(work, 'out')
    os.makedirs(out)
    code, stderr = run([args.uniarc, deck, '-o', out])
    expected = (f'{deck}:2:{len(expression) + 2}: expected a number, a name or \'(\', '
                'found the end of the expression')
    if code != 2:
        failures.append(f'exit code {code}, expected 2')
    if expected not in stderr:
        failures.append(f'stderr lacks "{expected}"')
    if len(stderr) > 1024:
        failures.append(f'stderr has {len(stderr)} characters: the line is echoed whole')
    shown = stderr.splitlines()[1:2]
    if not shown or not shown[0].startswith('...') or len(shown[0]) > 130:
        failures.append('the line is not shown as a window around the column')
    if os.listdir(out):
        failures.append(f'OUTDIR is not empty: {os.listdir(out)}')
    os.remove(deck)


def check_not_a_file(args, failures):
    work = os.path.join(args.out, 'not_a_file')
    fresh(work)
    fifo = os.path.join(work, 'deck.fifo')
    os.mkfifo(fifo)
    out = os.path.join(work, 'out')
    os.makedirs(out)
    for path, kind in ((work, 'a directory'), ('/dev/null', 'a character device'),
                       ('/dev/zero', 'a character device'), (fifo, 'a FIFO')):
        # /dev/zero was read until killed, and a FIFO without a writer blocks an open: 60 s is plenty
        try:
            code, stderr = run([args.uniarc, path, '-o', out], timeout=60)
        except subprocess.TimeoutExpired:
            failures.append(f'{path}: still running after 60 s')
            continue
        expected = f'error: {path}: expected a regular file as the deck, found {kind}'
        if code != 2:
            failures.append(f'{path}: exit code {code}, expected 2')
        if expected not in stderr:
            failures.append(f'{path}: stderr lacks "{expected}"')
    # A kernel file reports a size of 0 although it has text (/proc): it is read to its end, not taken
    # for empty (it was refused as "expected at least one element"), so its first line is the error.
    # A /sys file reports a page (4096 bytes) for a few bytes of text: read to its end too (it was
    # "cannot read (End of file)").
    for kernel, start in (('/proc/self/status', 'Name:'), ('/sys/kernel/profiling', '')):
        if not os.path.exists(kernel):
            continue
        code, stderr = run([args.uniarc, kernel, '-o', out], timeout=60)
        expected = f"error: {kernel}:1:1: expected a card (a line starting with '*'), found '{start}"
        if code != 2:
            failures.append(f'{kernel}: exit code {code}, expected 2')
        if expected not in stderr:
            failures.append(f'{kernel}: stderr lacks "{expected}"')
    if os.listdir(out):
        failures.append(f'OUTDIR is not empty: {os.listdir(out)}')


def check_empty_outdir(args, failures, deck):
    work = os.path.join(args.out, 'empty_outdir')
    fresh(work)
    code, stderr = run([os.path.abspath(args.uniarc), deck, '-o', ''], cwd=work)
    if code != 2:
        failures.append(f'exit code {code}, expected 2')
    expected = "error: option -o needs a directory, found an empty argument"
    if expected not in stderr:
        failures.append(f'stderr lacks "{expected}"')
    if os.listdir(work):
        failures.append(f'files written: {os.listdir(work)}')


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--scale', nargs=2, type=int, metavar=('PARAMETERS', 'MEGABYTES'))
    parser.add_argument('--long-error-line', type=int, metavar='MEGABYTES')
    parser.add_argument('--not-a-file', action='store_true')
    parser.add_argument('--empty-outdir', metavar='DECK', help='a valid deck, run with -o \'\'')
    args = parser.parse_args()
    failures = []
    if args.scale:
        check_scale(args, failures)
    if args.long_error_line:
        check_long_error_line(args, failures)
    if args.not_a_file:
        check_not_a_file(args, failures)
    if args.empty_outdir:
        check_empty_outdir(args, failures, os.path.abspath(args.empty_outdir))
    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
