#!/usr/bin/env python3
"""No silent jump near the near-bifurcation of a slightly imperfect structure (issue 11 item 3;
docs/theory.md §2.3): runs --deck once for each value of --parameter in --values (each a run of its
own, -D parameter=value) and checks, for each run: exit 0; exactly --limits-max limit_max rows and
--limits-min limit_min rows (a path that goes round a loop a second time reports its limits twice)
and no bifurcation row (an imperfect path has none: the jump onto the complementary path was reported
as one); the first limit_max within [--limit-low, --limit-high]; and no step that changes the sign of
--column (the critical mode's amplitude, the crown's sideways displacement) while λ keeps its sign,
both ends above --floor in magnitude (the jump from one side of the broken bifurcation to the other;
where λ changes sign a perturbation that is a load changes sign with it, and the path crosses zero
smoothly). Across the runs, with --values ordered by decreasing magnitude: the first limit_max rises
as the imperfection falls (Koiter 1945: towards the bifurcation load).
With --lambda-end, the last row's λ must be it (the path reached lambda_max).
"""
import argparse
import os
import shutil
import subprocess
import sys


def read_rows(path):
    with open(path) as handle:
        lines = handle.read().splitlines()
    names = lines[0].split()
    return names, [line.split() for line in lines[1:] if line.strip() and not line.startswith('#')]


def check_run(args, value, failures):
    """One run at parameter = value; returns its first limit_max or None."""
    out = os.path.join(args.out, f'{args.parameter}_{value}')
    shutil.rmtree(out, ignore_errors=True)
    command = [args.uniarc, args.deck, '-o', out, '-q', '-D', f'{args.parameter}={value}']
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    sys.stdout.write(result.stdout)
    sys.stderr.write(result.stderr)
    where = f'{args.parameter} = {value}'
    if result.returncode != 0:
        failures.append(f'{where}: exit code {result.returncode}')
        return None
    stem = os.path.join(out, os.path.splitext(os.path.basename(args.deck))[0])
    names, crit = read_rows(stem + '.crit')
    kinds = [row[0] for row in crit]
    counts = {kind: kinds.count(kind) for kind in ('limit_max', 'limit_min', 'bifurcation')}
    if counts['limit_max'] != args.limits_max:
        failures.append(f'{where}: {counts["limit_max"]} limit_max rows, expected {args.limits_max}')
    if counts['limit_min'] != args.limits_min:
        failures.append(f'{where}: {counts["limit_min"]} limit_min rows, expected {args.limits_min}')
    if counts['bifurcation']:
        failures.append(f'{where}: {counts["bifurcation"]} bifurcation rows on an imperfect path')
    first = None
    if counts['limit_max']:
        first = float(crit[kinds.index('limit_max')][names.index('lambda')])
        if not args.limit_low <= first <= args.limit_high:
            failures.append(f'{where}: limit_max {first} outside [{args.limit_low}, {args.limit_high}]')
    names, path = read_rows(stem + '.path')
    lam = names.index('lambda')
    column = names.index(args.column)
    flips = 0
    for a, b in zip(path, path[1:]):
        ua, ub = float(a[column]), float(b[column])
        la, lb = float(a[lam]), float(b[lam])
        if ua * ub < 0 and min(abs(ua), abs(ub)) > args.floor and la * lb > 0:
            flips += 1
            failures.append(f'{where}: {args.column} changes sign in one step, {ua:.4e} at step {a[0]} '
                            f'(lambda {la:.6f}) to {ub:.4e} at step {b[0]} (lambda {lb:.6f})')
    if args.lambda_end is not None and abs(float(path[-1][lam]) - args.lambda_end) > 1e-9 * abs(args.lambda_end):
        failures.append(f'{where}: the path ends at lambda {path[-1][lam]}, not {args.lambda_end}')
    print(f'{where}: limit_max {first}, rows {counts}, one-step sign changes of {args.column}: {flips}, '
          f'{len(path) - 1} steps')
    return first


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--parameter', required=True, help='the deck parameter of the imperfection')
    parser.add_argument('--values', required=True,
                        help='comma-separated, by decreasing magnitude (negative ones allowed: --values=1e-5,-1e-5)')
    parser.add_argument('--column', required=True, help='the tracked amplitude of the critical mode')
    parser.add_argument('--floor', type=float, required=True,
                        help='|column| below this at either end of a step is no sign to compare')
    parser.add_argument('--limits-max', type=int, default=1)
    parser.add_argument('--limits-min', type=int, default=0)
    parser.add_argument('--limit-low', type=float, required=True)
    parser.add_argument('--limit-high', type=float, required=True)
    parser.add_argument('--lambda-end', type=float)
    args = parser.parse_args()
    failures = []
    limits = []
    values = args.values.split(',')
    for value in values:
        limits.append(check_run(args, value, failures))
    known = [(v, lam) for v, lam in zip(values, limits) if lam is not None]
    for (va, la), (vb, lb) in zip(known, known[1:]):
        if abs(float(vb)) < abs(float(va)) and not lb > la:
            failures.append(f'limit_max {lb} at {args.parameter} = {vb} is not above {la} at {va}')
    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
