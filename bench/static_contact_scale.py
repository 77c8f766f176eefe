#!/usr/bin/env python3
"""The contact LCP of *STATIC at scale: time and pivots against the number of elements.

Runs bench/decks/beam_wave_static.inp (a free beam on a tensionless bed, lifted off between the
troughs of a wave load; docs/benchmarks.md §9) for each size n, as *STATIC and as its *PATH,
CONTROL=LOAD variant of one step to lambda = 1 (written into the work directory), each run its own
process under `timeout`, and prints a Markdown table: wall time (the fastest of --repeat runs), the
final lambda, contacts, and the principal pivots of the contact LCP (the path file's lcp_pivots).
With --baseline BIN the same runs of a second build (e.g. the commit before) are put side by side.

Usage (from the repository root, Release builds):

    python3 bench/static_contact_scale.py --uniarc build/uniarc --sizes 1000 2000 5000 10000
    python3 bench/static_contact_scale.py --uniarc build/uniarc --baseline /tmp/old/build/uniarc

No timing is asserted anywhere: this prints measurements.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = os.path.join(HERE, 'decks', 'beam_wave_static.inp')
PATH_CARD = '*PATH, CONTROL=LOAD\nincrement = 1\nmax_increment = 1\niterations = 25\nsteps = 1\n'


def variants(workdir):
    """The *STATIC deck and its one-step load-controlled twin."""
    with open(DECK) as f:
        text = f.read()
    assert text.rstrip().endswith('*STATIC'), 'the deck must end with *STATIC'
    path_deck = os.path.join(workdir, 'beam_wave_path1.inp')
    with open(path_deck, 'w') as f:
        f.write(text.rstrip()[:-len('*STATIC')] + PATH_CARD)
    return {'*STATIC': DECK, '*PATH one step': path_deck}


def run(label, binary, deck, n, workdir, timeout, repeat):
    """(wall seconds of the fastest run, last row as a dict, or None; status text)."""
    best, row, status = None, None, 'ok'
    for attempt in range(repeat):
        out = os.path.join(workdir, f'{label}.{os.path.basename(deck)}.{n}.{attempt}')
        start = time.perf_counter()
        try:
            done = subprocess.run(['timeout', '-k', '5', str(timeout), binary, '-q', '-D', f'n={n}', deck,
                                   '-o', out], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        except OSError as error:
            return None, None, f'cannot run: {error}'
        wall = time.perf_counter() - start
        if done.returncode != 0:
            message = done.stderr.strip().splitlines()
            return wall, None, f'exit {done.returncode}: {message[-1] if message else ""}'
        best = wall if best is None else min(best, wall)
        stem = os.path.splitext(os.path.basename(deck))[0]
        with open(os.path.join(out, stem + '.path')) as f:
            lines = [line.split() for line in f if line.strip()]
        names = lines[0]
        rows = [line for line in lines[1:] if not line[0].startswith('#')]
        row = dict(zip(names, rows[-1]))
    return best, row, status


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--uniarc', default=os.path.join(os.path.dirname(HERE), 'build', 'uniarc'))
    parser.add_argument('--baseline', help='a second uniarc build, run side by side')
    parser.add_argument('--sizes', type=int, nargs='+', default=[1000, 2000, 5000, 10000])
    parser.add_argument('--repeat', type=int, default=1)
    parser.add_argument('--timeout', type=int, default=600)
    parser.add_argument('--workdir')
    args = parser.parse_args()
    workdir = args.workdir or tempfile.mkdtemp(prefix='static_contact_scale_')
    os.makedirs(workdir, exist_ok=True)
    builds = [('uniarc', args.uniarc)] + ([('baseline', args.baseline)] if args.baseline else [])
    print('| analysis | n | build | status | wall s | lambda | n_contact | lcp_pivots | pivots / candidate |')
    print('|---|---:|---|---|---:|---:|---:|---:|---:|')
    for analysis, deck in variants(workdir).items():
        for n in args.sizes:
            for label, binary in builds:
                wall, row, status = run(label, binary, deck, n, workdir, args.timeout, args.repeat)
                if row is None:
                    print(f'| {analysis} | {n} | {label} | {status} | {wall or 0:.2f} | — | — | — | — |')
                    continue
                pivots = int(row['lcp_pivots'])
                print(f'| {analysis} | {n} | {label} | {status} | {wall:.2f} | {float(row["lambda"]):.6g} | '
                      f'{row["n_contact"]} | {pivots} | {pivots / (n + 1):.2f} |')
            sys.stdout.flush()
    print(f'\nwork directory: {workdir}')


if __name__ == '__main__':
    main()
