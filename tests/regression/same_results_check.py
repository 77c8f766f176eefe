#!/usr/bin/env python3
"""Run uniarc on two decks and check that their result tables are the same, number for number.

Usage (one CTest per call):
  same_results_check.py --uniarc BIN --deck A --deck B --out DIR [--table path] [--table shape]...

Used where two ways of writing one model must give the same analysis bit for bit (docs/testing.md):
a section's weight per unit length taken by *DLOAD WEIGHT against the same weight written on the
load card; a section's coefficient of thermal expansion against the one written on *TEMPERATURE.
The tables (default: path and shape) must have the same column names and the same rows, compared as
text, the provenance lines (`#`, which name the deck) left out. Either run exiting non-zero fails.
"""
import argparse
import os
import sys

from uniarc_check import run_uniarc


def rows_of(path):
    """The table's header and rows as text, without its provenance lines."""
    with open(path) as handle:
        return [line for line in handle.read().splitlines() if not line.startswith('#')]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', action='append', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--table', action='append', default=[])
    args = parser.parse_args()
    if len(args.deck) != 2:
        raise SystemExit('same_results_check.py: give exactly two --deck')
    tables = args.table or ['path', 'shape']
    contents = []
    for index, deck in enumerate(args.deck):
        out = os.path.join(args.out, str(index))
        command, run = run_uniarc(args.uniarc, deck, out, [])
        if run.returncode != 0:
            raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
        stem = os.path.splitext(os.path.basename(deck))[0]
        contents.append({table: rows_of(os.path.join(out, f'{stem}.{table}')) for table in tables})
    problems = []
    for table in tables:
        a, b = contents[0][table], contents[1][table]
        if len(a) < 2:
            problems.append(f'{table}: no rows')
        elif a != b:
            first = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            problems.append(f'{table}: differs from row {first} ({len(a)} and {len(b)} lines)')
        else:
            print(f'{table}: {len(a) - 1} rows, the same')
    if problems:
        print('FAIL: ' + '; '.join(problems))
        sys.exit(1)
    print('ok')


if __name__ == '__main__':
    main()
