#!/usr/bin/env python3
"""Run uniarc on two decks and check that chosen columns of the last rows of their path files agree.

Usage (one CTest per call):
  agree_check.py --uniarc BIN --deck A --deck B --out DIR --column NAME:RTOL [--column ...]
                 [--define NAME=VALUE]... [--define-first NAME=VALUE]... [--all-rows]

NAME may be `NAME_A=NAME_B` where the two decks write the quantity under different names (a moving
obstacle's `reaction_sum` against a jack's `prescribed_force`).

Used where two analyses must land on the same state: a *STATIC deck with contact (the linear contact
LCP) and the same structure under a load-controlled *PATH to lambda = 1 at a load so small that the
geometric nonlinearity is below the tolerance (docs/testing.md). The check fails when either run does
not exit 0, when a column is missing, or when |a - b| > RTOL * max(|a|, |b|). With --all-rows every
row is compared (the two path files must have as many rows): two runs that must trace the same path
step for step, a structure and its mirror image. --define-first goes to the first deck only (a
parameter of the path deck that the static one does not have: where the path stops).
"""
import argparse
import os
import sys

from uniarc_check import read_table, run_uniarc


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', action='append', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--column', action='append', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--define-first', action='append', default=[])
    parser.add_argument('--all-rows', action='store_true')
    args = parser.parse_args()
    if len(args.deck) != 2:
        raise SystemExit('agree_check.py: give exactly two --deck')
    tables = []
    for index, deck in enumerate(args.deck):
        out = os.path.join(args.out, str(index))
        command, run = run_uniarc(args.uniarc, deck, out, args.define + (args.define_first if index == 0 else []))
        if run.returncode != 0:
            raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
        stem = os.path.splitext(os.path.basename(deck))[0]
        names, rows = read_table(os.path.join(out, stem + '.path'))
        tables.append([dict(zip(names, row)) for row in (rows if args.all_rows else rows[-1:])])
    problems = []
    if len(tables[0]) != len(tables[1]):
        problems.append(f'{len(tables[0])} rows against {len(tables[1])}')
    for row_a, row_b in zip(*tables):
        for spec in args.column:
            name, rtol = spec.split(':')
            name_a, _, name_b = name.partition('=')
            name_b = name_b or name_a
            if name_a not in row_a or name_b not in row_b:
                problems.append(f'column {name} missing')
                continue
            a, b = row_a[name_a], row_b[name_b]
            scale = max(abs(a), abs(b))
            ok = abs(a - b) <= float(rtol) * scale
            print(f'{name}: {a!r} vs {b!r} (relative {abs(a - b) / scale if scale else 0.0:.3g}, allowed {rtol})')
            if not ok:
                problems.append(f'{name} differs: {a!r} vs {b!r}')
    if problems:
        print('FAIL: ' + '; '.join(problems))
        sys.exit(1)
    print('ok')


if __name__ == '__main__':
    main()
