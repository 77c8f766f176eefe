#!/usr/bin/env python3
"""A Pasternak bed with G_p = 0 is Winkler's bed: the same deck with and without its Pasternak options
must give the same result files, line for line.

Usage (one CTest per call):
  winkler_twin_check.py --uniarc BIN --deck DECK --out DIR --strip TEXT [--define NAME=VALUE]...

The twin is DECK with TEXT (e.g. ', TYPE=PASTERNAK, GP=G') removed, written under DIR with the same
file name; both are run with the --define overrides (which must make G_p zero). Every result file of
the Pasternak run must have a twin whose lines equal its own, except the provenance lines ('#'), which
name the deck and the time. Exit 1 on the first difference.
"""
import argparse
import os
import sys

from uniarc_check import run_uniarc


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--strip', required=True)
    parser.add_argument('--define', action='append', default=[])
    args = parser.parse_args()
    with open(args.deck) as f:
        text = f.read()
    if args.strip not in text:
        raise SystemExit(f'FAIL: {args.strip!r} is not in {args.deck}')
    twin_dir = os.path.join(args.out, 'twin_deck')
    os.makedirs(twin_dir, exist_ok=True)
    twin = os.path.join(twin_dir, os.path.basename(args.deck))
    with open(twin, 'w') as f:
        f.write(text.replace(args.strip, ''))
    outs = []
    for index, deck in enumerate([args.deck, twin]):
        out = os.path.join(args.out, str(index))
        command, run = run_uniarc(args.uniarc, deck, out, args.define)
        if run.returncode != 0:
            raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
        outs.append(out)
    files = sorted(os.listdir(outs[0]))
    if files != sorted(os.listdir(outs[1])) or not files:
        raise SystemExit(f'FAIL: result files differ: {files} vs {sorted(os.listdir(outs[1]))}')
    compared = 0
    for name in files:
        lines = []
        for out in outs:
            with open(os.path.join(out, name)) as f:
                lines.append([line for line in f if not line.startswith('#')])
        if lines[0] != lines[1]:
            for number, (a, b) in enumerate(zip(*lines)):
                if a != b:
                    raise SystemExit(f'FAIL: {name} differs at data line {number + 1}:\n  {a}  {b}')
            raise SystemExit(f'FAIL: {name} has {len(lines[0])} vs {len(lines[1])} lines')
        compared += len(lines[0])
    print(f'{len(files)} result files, {compared} lines: identical')
    print('ok')


if __name__ == '__main__':
    main()
