#!/usr/bin/env python3
"""Run uniarc on a deck and check its path file: the project's own numeric diff and value checks.

Usage (one CTest per call):
  uniarc_check.py --uniarc BIN --deck DECK --out DIR [--define NAME=VALUE]...
                  [--reference REF --rtol R --atol A]          # numeric diff of the whole path file
                  [--expect COLUMN=VALUE:RTOL]...               # value of a column in the last row
                  [--expect-exit N]

A numeric diff compares the header exactly and every number with |a - b| <= atol + rtol * |b|.
"""
import argparse
import os
import shutil
import subprocess
import sys


def read_table(path):
    """Column names and rows (lists of floats) of a uniarc table file."""
    with open(path) as handle:
        lines = handle.read().splitlines()
    if not lines or not lines[0].startswith('#'):
        raise SystemExit(f'{path}: no header line')
    names = lines[0][1:].split()
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        fields = line.split()
        try:
            rows.append([float(x) for x in fields])
        except ValueError:
            raise SystemExit(f'{path}:{number}: not a row of numbers: {line!r}')
        if len(fields) != len(names):
            raise SystemExit(f'{path}:{number}: {len(fields)} fields, header has {len(names)}')
    return names, rows


def numeric_diff(result, reference, rtol, atol):
    """List of differences between two table files beyond the tolerance."""
    names_r, rows_r = read_table(result)
    names_f, rows_f = read_table(reference)
    problems = []
    if names_r != names_f:
        problems.append(f'header differs:\n  got      {names_r}\n  expected {names_f}')
        return problems
    if len(rows_r) != len(rows_f):
        problems.append(f'{len(rows_r)} rows, reference has {len(rows_f)}')
    for i, (a_row, b_row) in enumerate(zip(rows_r, rows_f), start=1):
        for name, a, b in zip(names_r, a_row, b_row):
            if abs(a - b) > atol + rtol * abs(b):
                problems.append(f'row {i} column {name}: {a!r} vs reference {b!r}')
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--reference')
    parser.add_argument('--rtol', type=float, default=1e-8)
    parser.add_argument('--atol', type=float, default=1e-12)
    parser.add_argument('--expect', action='append', default=[])
    parser.add_argument('--expect-exit', type=int, default=0)
    args = parser.parse_args()

    shutil.rmtree(args.out, ignore_errors=True)
    command = [args.uniarc, args.deck, '-o', args.out, '-q']
    for definition in args.define:
        command += ['-D', definition]
    run = subprocess.run(command, capture_output=True, text=True)
    sys.stdout.write(run.stdout)
    sys.stderr.write(run.stderr)
    if run.returncode != args.expect_exit:
        print(f'FAIL: exit code {run.returncode}, expected {args.expect_exit}: {" ".join(command)}')
        return 1
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    path_file = os.path.join(args.out, stem + '.path')
    failures = []
    if args.reference:
        failures += numeric_diff(path_file, args.reference, args.rtol, args.atol)
    if args.expect:
        names, rows = read_table(path_file)
        if not rows:
            failures.append('path file has no rows')
        for expectation in args.expect:
            column, rest = expectation.split('=', 1)
            value, tolerance = (float(x) for x in rest.split(':'))
            if column not in names:
                failures.append(f'no column {column} in {names}')
                continue
            got = rows[-1][names.index(column)]
            error = abs(got - value) / max(abs(value), 1e-300)
            status = 'ok' if error <= tolerance else 'FAIL'
            print(f'{status}: {column} = {got!r}, expected {value!r}, relative error {error:.3e} '
                  f'(tolerance {tolerance:.1e})')
            if error > tolerance:
                failures.append(f'{column}: relative error {error:.3e} > {tolerance:.1e}')
    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
