#!/usr/bin/env python3
"""Mesh-convergence check of one tracked value against a closed form (docs/verification.md).

Runs uniarc with -D NAME=N for a sequence of meshes, each twice as fine as the last, takes COLUMN from
the last row of each path file, estimates the observed order of convergence p from the three finest
meshes, extrapolates (Richardson) and compares the extrapolated value with the closed form.

  convergence_check.py --uniarc BIN --deck DECK --out DIR --parameter n --meshes 8 16 32 64
                       --column ux_tip --exact VALUE --order 2 --order-tolerance 0.1 --rtol 1e-6
"""
import argparse
import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uniarc_check import read_table  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--parameter', required=True)
    parser.add_argument('--meshes', type=int, nargs='+', required=True)
    parser.add_argument('--column', required=True)
    parser.add_argument('--exact', type=float, required=True)
    parser.add_argument('--order', type=float, required=True)
    parser.add_argument('--order-tolerance', type=float, required=True)
    parser.add_argument('--rtol', type=float, required=True)
    args = parser.parse_args()

    stem = os.path.splitext(os.path.basename(args.deck))[0]
    values = []
    for n in args.meshes:
        out = os.path.join(args.out, f'{args.parameter}{n}')
        shutil.rmtree(out, ignore_errors=True)
        run = subprocess.run([args.uniarc, args.deck, '-o', out, '-q', '-D', f'{args.parameter}={n}'],
                             capture_output=True, text=True)
        if run.returncode != 0:
            print(run.stderr)
            print(f'FAIL: uniarc exited with {run.returncode} for {args.parameter}={n}')
            return 1
        names, rows = read_table(os.path.join(out, stem + '.path'))
        values.append(rows[-1][names.index(args.column)])
        print(f'{args.parameter} = {n:6d}: {args.column} = {values[-1]!r}  '
              f'(error {abs(values[-1] - args.exact) / abs(args.exact):.3e})')
    f1, f2, f3 = values[-3:]
    ratio = args.meshes[-1] / args.meshes[-2]
    order = math.log(abs((f1 - f2) / (f3 - f2)) if f3 != f2 else math.inf) / math.log(ratio)
    extrapolated = f3 + (f3 - f2) / (ratio ** order - 1.0)
    error = abs(extrapolated - args.exact) / abs(args.exact)
    print(f'observed order {order:.4f} (expected {args.order} ± {args.order_tolerance}); '
          f'extrapolated {extrapolated!r}, exact {args.exact!r}, relative error {error:.3e} '
          f'(tolerance {args.rtol:.1e})')
    failed = abs(order - args.order) > args.order_tolerance or error > args.rtol
    print('FAIL' if failed else 'ok')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
