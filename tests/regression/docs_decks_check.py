#!/usr/bin/env python3
"""Run every complete deck shown in a Markdown page and check its exit code.

Usage: docs_decks_check.py --uniarc BIN --page docs/input.md --out DIR [--at-least N]

A complete deck is a fenced block whose info string is `deck` (```` ```deck ````); fragments of
decks use plain fences and are not run. Each deck is written to OUTDIR/<name>.inp, <name> being
`deck_<k>` for the k-th such block (from 1), or the word after `deck` (```` ```deck arch ````), and
run as shown (no -D). It must exit 0, or the code a line `** exit: N` of the deck gives. The check
fails when fewer than N decks are found (default 1), so that a page whose markers were lost does not
pass by running nothing.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

FENCE = re.compile(r'^```deck(?:[ \t]+(\w+))?[ \t]*\n(.*?)^```[ \t]*$', re.M | re.S)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--page', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--at-least', type=int, default=1)
    args = parser.parse_args()
    with open(args.page) as handle:
        text = handle.read()
    blocks = FENCE.findall(text)
    if len(blocks) < args.at_least:
        raise SystemExit(f'FAIL: {len(blocks)} deck blocks in {args.page}, expected at least {args.at_least}')
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    failures = []
    for k, (name, body) in enumerate(blocks, start=1):
        name = name or f'deck_{k}'
        deck = os.path.join(args.out, name + '.inp')
        with open(deck, 'w') as handle:
            handle.write(body)
        expected = 0
        match = re.search(r'^\*\*\s*exit:\s*(\d+)', body, re.M)
        if match:
            expected = int(match.group(1))
        run = subprocess.run([args.uniarc, deck, '-o', os.path.join(args.out, name), '-q'],
                             capture_output=True, text=True)
        status = 'ok' if run.returncode == expected else 'FAIL'
        print(f'{status}: {name} exited {run.returncode} (expected {expected})')
        if run.returncode != expected:
            sys.stdout.write(run.stdout)
            sys.stdout.write(run.stderr)
            failures.append(name)
    if failures:
        print('FAIL: ' + ', '.join(failures))
        sys.exit(1)
    print(f'ok: {len(blocks)} decks')


if __name__ == '__main__':
    main()
