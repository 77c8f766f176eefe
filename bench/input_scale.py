#!/usr/bin/env python3
"""Time uniarc on decks that are large in their input only (docs/benchmarks.md §6): a cantilever of 4
elements after N *PARAMETER lines (each built on the one before: p_i = p_(i-1) + 1, so every line looks
one name up), or after one comment line of M MiB (64 MiB: the longest line a deck may have). The analysis is the same tiny one in every deck, so
the time is that of reading the deck.

  bench/input_scale.py UNIARC [--parameters N ...] [--megabytes M ...] [--tracks N ...]
                       [--node-sets N ...] [--repeat K] [--timeout S] [--work DIR]

--tracks N: the cantilever with N *TRACK lines (N + 14 path columns); --node-sets N: after N *NSET
cards (issue 14: each new track or set name was compared with every earlier one).

Prints a Markdown table: the wall time and the CPU time (user + system, of the child) of the fastest
of K runs, and the peak memory (maximum resident set; it includes the few MiB of this script's own
pages at the fork, printed below the table). A run that exceeds S seconds is stopped and
reported as "> S s". The machine is shared: the CPU time is the firmer number.
"""
import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

CANTILEVER = ('*SECTION, NAME=s, STIFFNESS\n1e3, 1\n*LINE, ELSET=b, SECTION=s\n0, 0, 1, 0, 4\n'
              '*BOUNDARY\nb_start, FIXED\n*CLOAD\nb_end, FY, -P\n*TRACK\nw, b_end, UY\n')


def parameters_deck(path, n):
    """N chained *PARAMETER lines, then P = 3 and the cantilever; written in pieces, so that this
    process stays small (a child's peak memory counts its parent's pages at the fork)."""
    with open(path, 'w') as handle:
        handle.write('*PARAMETER\np1 = 1\n')
        for first in range(2, n + 1, 10000):
            handle.write(''.join(f'p{i} = p{i - 1} + 1\n' for i in range(first, min(first + 10000, n + 1))))
        handle.write(f'P = 3*p{n}/{n}\n' + CANTILEVER)


def tracks_deck(path, n):
    """The cantilever with N *TRACK lines t1..tN (every line a new name, checked against all earlier
    ones): the path file then has N + 14 columns, its header and rows built in every step."""
    with open(path, 'w') as handle:
        handle.write('*PARAMETER\nP = 3\n' + CANTILEVER)
        for first in range(1, n + 1, 10000):
            handle.write(''.join(f't{i}, b_end, UY\n' for i in range(first, min(first + 10000, n + 1))))


def node_sets_deck(path, n):
    """The cantilever after N *NSET cards s1..sN of all its 5 nodes (every card a new set name)."""
    with open(path, 'w') as handle:
        handle.write('*PARAMETER\nP = 3\n*NODE\n1, 0, 0\n2, 0.25, 0\n3, 0.5, 0\n4, 0.75, 0\n5, 1, 0\n')
        for first in range(1, n + 1, 10000):
            handle.write(''.join(f'*NSET, NSET=s{i}\n1, 2, 3, 4, 5\n'
                                 for i in range(first, min(first + 10000, n + 1))))
        handle.write(CANTILEVER)


def long_line_deck(path, megabytes):
    """A comment line of exactly M MiB ('** ' and x's), then P = 3 and the cantilever."""
    with open(path, 'w') as handle:
        handle.write('** ')
        chunk = 'x' * (1 << 20)
        for _ in range(megabytes - 1):
            handle.write(chunk)
        handle.write(chunk[3:] + '\n*PARAMETER\nP = 3\n' + CANTILEVER)


def time_run(uniarc, deck, out, timeout):
    """Wall seconds, CPU seconds (user + system) and peak resident MiB of one run (wait4 of this
    child alone), or None when it runs past the timeout."""
    shutil.rmtree(out, ignore_errors=True)
    with tempfile.TemporaryFile() as stderr:
        start = time.perf_counter()
        process = subprocess.Popen([uniarc, deck, '-o', out, '-q'], stdout=subprocess.DEVNULL, stderr=stderr)
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG)
            if pid != 0:
                break
            if time.perf_counter() - start > timeout:
                process.kill()
                os.wait4(process.pid, 0)
                return None
            time.sleep(0.005)
        wall = time.perf_counter() - start
        process.returncode = os.waitstatus_to_exitcode(status)
        if process.returncode != 0:
            stderr.seek(0)
            raise SystemExit(f'{deck}: exit code {process.returncode}: {stderr.read(500).decode()}')
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def measure(uniarc, deck, work, repeat, timeout):
    """The fastest of `repeat` runs (by CPU time) as table cells."""
    best = None
    for _ in range(repeat):
        result = time_run(uniarc, deck, os.path.join(work, 'out'), timeout)
        if result is None:
            return f'> {timeout:g} s', '-', '-'
        if best is None or result[1] < best[1]:
            best = result
    return f'{best[0]:.2f} s', f'{best[1]:.2f} s', f'{best[2]:.0f} MiB'


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('uniarc')
    parser.add_argument('--parameters', type=int, nargs='*', default=[16000, 50000, 200000, 1000000])
    parser.add_argument('--megabytes', type=int, nargs='*', default=[1, 4, 16, 64])
    parser.add_argument('--tracks', type=int, nargs='*', default=[])
    parser.add_argument('--node-sets', type=int, nargs='*', default=[])
    parser.add_argument('--repeat', type=int, default=3)
    parser.add_argument('--timeout', type=float, default=120.0)
    parser.add_argument('--work', default=None, help='scratch folder (default: a temporary one)')
    args = parser.parse_args()
    uniarc = os.path.abspath(args.uniarc)
    work = args.work or tempfile.mkdtemp(prefix='uniarc_input_scale_')
    os.makedirs(work, exist_ok=True)
    print('| deck | size | wall | CPU | peak memory |')
    print('|---|---|---|---|---|')
    cases = [('parameters', n, parameters_deck) for n in args.parameters] + \
            [('comment line', m, long_line_deck) for m in args.megabytes] + \
            [('tracks', n, tracks_deck) for n in args.tracks] + \
            [('node sets', n, node_sets_deck) for n in args.node_sets]
    for label, size, make in cases:
        deck = os.path.join(work, 'deck.inp')
        make(deck, size)
        megabytes = os.path.getsize(deck) / 2**20
        wall, cpu, memory = measure(uniarc, deck, work, args.repeat, args.timeout)
        what = f'{label} of {size} MiB' if label == 'comment line' else f'{size:,} {label}'
        print(f'| {what} | {megabytes:.1f} MiB | {wall} | {cpu} | {memory} |', flush=True)
        os.remove(deck)
    if args.work is None:
        shutil.rmtree(work, ignore_errors=True)
    print(f'\n(this script\'s own peak memory: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
