#!/usr/bin/env python3
"""Run a load-controlled deck, then the displacement-controlled twin at the displacement it reached,
and check that the twin needs the load: a jack or a support moved by a prescribed displacement
(*BOUNDARY with a value, docs/input.md) against the same structure under a point load.

Usage (one CTest per call):
  jack_check.py --uniarc BIN --load-deck A --jack-deck B --out DIR --carry COLUMN=PARAMETER
                --expect COLUMN=VALUE:RTOL [--expect ...]

The last row of A's path file gives COLUMN (the displacement its load reached); B runs with
-D PARAMETER=that value; each --expect is checked on the last row of B's path file:
|got - VALUE| <= RTOL |VALUE|. Either run exiting non-zero fails.
"""
import argparse
import os
import sys

from uniarc_check import read_table, run_uniarc


def last_row(uniarc, deck, out, defines):
    """The last row of the deck's path file as a dict, after a run that must exit 0."""
    command, run = run_uniarc(uniarc, deck, out, defines)
    if run.returncode != 0:
        raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
    stem = os.path.splitext(os.path.basename(deck))[0]
    names, rows = read_table(os.path.join(out, stem + '.path'))
    return dict(zip(names, rows[-1]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--load-deck', required=True)
    parser.add_argument('--jack-deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--carry', required=True)
    parser.add_argument('--expect', action='append', required=True)
    args = parser.parse_args()
    column, parameter = args.carry.split('=')
    loaded = last_row(args.uniarc, args.load_deck, os.path.join(args.out, 'load'), [])
    value = loaded[column]
    print(f'{column} = {value!r} under the load (lambda = {loaded["lambda"]!r})')
    jacked = last_row(args.uniarc, args.jack_deck, os.path.join(args.out, 'jack'), [f'{parameter}={value!r}'])
    problems = []
    for spec in args.expect:
        name, rest = spec.split('=')
        expected, rtol = (float(x) for x in rest.split(':'))
        got = jacked[name]
        error = abs(got - expected) / abs(expected) if expected else abs(got)
        print(f'{name}: {got!r}, expected {expected!r} (relative {error:.3g}, allowed {rtol})')
        if error > rtol:
            problems.append(f'{name} = {got!r}, expected {expected!r}')
    if problems:
        print('FAIL: ' + '; '.join(problems))
        sys.exit(1)
    print('ok')


if __name__ == '__main__':
    main()
