#!/usr/bin/env python3
"""Sweep of extreme physical parameters: every deck of input/ and tests/regression/decks/ run with one of
its *PARAMETER values overridden (`-D NAME=VALUE`) by an extreme value, judged by the exit-code contract.

A run is a (deck, parameter, value): the deck's *PARAMETER names that are physical quantities (PHYSICAL:
stiffnesses, loads, lengths, gaps, temperatures, amplitudes — not counts or switches), each with every
value of VALUES (0, +-1e300, 1e-300, 1e+-100, +-1e150, 1e-150). Each run must keep the contract of
docs/contracts.md as tests/fuzz/uniarc_fuzz.py judges it: exit code 0, 1 or 2 (no signal — the Debug
build's floating-point traps end a run with SIGFPE — and no Fortran runtime error); on exit 2 a message
`error: DECK:LINE:COL: ...` (or `error: DECK: ...`) and no output; on exit 0 or 1 complete rows of
finite numbers. Decks marked `** fuzz: skip` (built to overflow, or long) and the two long decks
many_generators.inp and long_cantilever_run.inp are left out.

The runs are shuffled by SEED and run until the time budget is spent (a run started before the budget
ends is finished), so that a short budget samples every kind of parameter; a budget that covers the
whole list runs every run once.

    scripts/extreme_parameters.py UNIARC BUDGET_SECONDS SEED OUTDIR [--jobs J] [--timeout S]
                                  [--parameters P q ...] [--values 1e100 ...] [--decks GLOB ...]

Prints each run that broke the contract as it ends (`PROBLEM ...`) and a summary; writes OUTDIR/runs.tsv
(one line a run: exit code, deck, override, problems, first line of stderr) and OUTDIR/summary.txt. A run
is reproduced with `UNIARC DECK -o OUT -D NAME=VALUE`. Meant to run by hand (about an hour for the whole
list on the Debug build with two jobs), not in the suite. Exit status 0 if no run broke the contract,
1 if some did, 2 on a usage error. Standard library only.
"""

import argparse
import collections
import concurrent.futures
import fnmatch
import os
import random
import re
import shutil
import sys
import tempfile
import time

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
sys.path.insert(0, os.path.join(REPO, 'tests', 'fuzz'))
import uniarc_fuzz  # noqa: E402  (the contract's judge and the runner with its resource limits)

CORPUS = ['input', os.path.join('tests', 'regression', 'decks')]
LONG_DECKS = {'many_generators.inp', 'long_cantilever_run.inp'}

# The *PARAMETER names of the decks that stand for physical quantities. Counts (n, steps), angles of a
# geometry's layout and switches are left alone: their extremes are resource limits or integer checks,
# tested elsewhere (tests/bad_decks, the fuzzer).
PHYSICAL = {'EI', 'EA', 'k', 'P', 'q', 'dT', 'dT_d', 'qu', 'kt', 'G', 'K', 'F', 'w', 'g0', 'gap', 'E', 'A',
            'I', 'ks', 'k_joint', 'K_R', 'K_T', 'K0', 'GAs', 'kGA', 'ku', 'Gp', 'L', 'R', 'h', 'M', 'M0', 'My',
            'tu', 'delta', 'H', 'P1', 'P2', 'q2', 'gamma', 't', 'd', 'b', 'a', 'amplitude', 'imperfection',
            'eps', 'up', 'T'}
VALUES = ['1e300', '-1e300', '1e-300', '0', '1e100', '1e-100', '1e150', '1e-150']

PARAMETER_BLOCK = re.compile(r'^\*PARAMETER[^\n]*\n((?:(?!\*)[^\n]*\n)*)', re.M | re.I)


def deck_parameters(text):
    """Names given a value in the deck's first *PARAMETER block (comment lines skipped)."""
    block = PARAMETER_BLOCK.search(text)
    if not block:
        return []
    return [line.split('=')[0].strip() for line in block.group(1).split('\n')
            if '=' in line and not line.startswith('**')]


def runs_of(decks, parameters, values):
    runs = []
    for deck in decks:
        text = open(deck, errors='replace').read()
        if os.path.basename(deck) in LONG_DECKS or re.search(r'^\*\* fuzz: skip', text, re.M):
            continue
        for name in deck_parameters(text):
            if name in parameters:
                runs += [(deck, name, value) for value in values]
    return runs


def run_one(args, index, deck, name, value):
    workdir = os.path.join(args.work, f'r{index:06d}')
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    shutil.copy(deck, workdir)
    # The deck's neighbours (a modes table of *IMPERFECTION, FILE=) linked beside its copy.
    folder = os.path.dirname(deck)
    for neighbour in os.listdir(folder):
        if not neighbour.endswith('.inp') and neighbour != 'out':
            os.symlink(os.path.join(folder, neighbour), os.path.join(workdir, neighbour))
    result = uniarc_fuzz.run_deck(os.path.join(args.work, 'uniarc'), os.path.join(workdir, os.path.basename(deck)), workdir,
                                  args.timeout, args.memory_mb, args.file_mb, [f'{name}={value}'])
    shutil.rmtree(workdir, ignore_errors=True)
    first = result['stderr_head'].strip().splitlines()
    result.update(deck=os.path.relpath(deck, REPO), define=f'{name}={value}', first=first[0][:200] if first else '')
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('uniarc', help='the uniarc executable (the Debug build finds the traps)')
    parser.add_argument('budget', type=float, help='time budget in seconds (no new run after it)')
    parser.add_argument('seed', type=int, help='seed of the order of the runs')
    parser.add_argument('outdir', help='folder for runs.tsv and summary.txt')
    parser.add_argument('--jobs', type=int, default=1)
    parser.add_argument('--timeout', type=float, default=90.0, help='seconds per run')
    parser.add_argument('--memory-mb', type=int, default=2048, help='address-space limit per run (0: none)')
    parser.add_argument('--file-mb', type=int, default=256, help='file-size limit per run (0: none)')
    parser.add_argument('--parameters', nargs='+', default=None, help='only these parameter names')
    parser.add_argument('--values', nargs='+', default=VALUES, help='the extreme values')
    parser.add_argument('--decks', nargs='+', default=None, help='only decks whose name matches a glob')
    args = parser.parse_args()
    args.uniarc = os.path.abspath(args.uniarc)
    if not os.access(args.uniarc, os.X_OK):
        parser.error(f'{args.uniarc} is not an executable')
    if args.budget <= 0 or args.jobs < 1 or args.timeout <= 0:
        parser.error('the budget, --jobs and --timeout must be positive')
    parameters = set(args.parameters) if args.parameters else PHYSICAL

    decks = []
    for folder in CORPUS:
        decks += sorted(os.path.join(REPO, folder, n) for n in os.listdir(os.path.join(REPO, folder))
                        if n.endswith('.inp'))
    if args.decks:
        decks = [d for d in decks if any(fnmatch.fnmatch(os.path.basename(d), g) for g in args.decks)]
    runs = runs_of(decks, parameters, args.values)
    random.Random(args.seed).shuffle(runs)
    os.makedirs(args.outdir, exist_ok=True)
    args.work = tempfile.mkdtemp(prefix='uniarc_extreme_')
    # The runs use a copy of the executable: a rebuild during a long sweep does not reach them.
    executable = os.path.join(args.work, 'uniarc')
    shutil.copy2(args.uniarc, executable)
    print(f'extreme parameters: {len(runs)} runs of {len(decks)} decks, seed {args.seed}, budget {args.budget:.0f} s, '
          f'{args.jobs} jobs, {args.uniarc}', flush=True)

    start = time.monotonic()
    results = []
    pending = iter(enumerate(runs))
    with open(os.path.join(args.outdir, 'runs.tsv'), 'w') as log, \
            concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        log.write('exit\tdeck\tdefine\tproblems\tstderr\n')
        active = set()

        def submit():
            if time.monotonic() - start > args.budget:
                return False
            item = next(pending, None)
            if item is None:
                return False
            index, (deck, name, value) = item
            active.add(pool.submit(run_one, args, index, deck, name, value))
            return True

        while len(active) < args.jobs and submit():
            pass
        while active:
            done, _ = concurrent.futures.wait(active, return_when=concurrent.futures.FIRST_COMPLETED)
            for future in done:
                active.discard(future)
                r = future.result()
                results.append(r)
                problems = '; '.join(f'{kind}: {detail}' for kind, detail in r['problems'])
                exit_code = 'timeout' if r['outcome'] == 'timeout' else r['returncode']
                line = f'{exit_code}\t{r["deck"]}\t-D {r["define"]}\t{problems}\t{r["first"]}'
                log.write(line + '\n')
                log.flush()
                if r['problems']:
                    print('PROBLEM', line, flush=True)
                submit()
    shutil.rmtree(args.work, ignore_errors=True)

    elapsed = time.monotonic() - start
    outcomes = collections.Counter(r['outcome'] for r in results)
    classes = collections.Counter(kind for r in results for kind, _ in r['problems'])
    failed = sum(1 for r in results if r['problems'])
    lines = [f'extreme parameters: {len(results)} of {len(runs)} runs in {elapsed:.0f} s (seed {args.seed}, '
             f'{args.jobs} jobs, {args.uniarc})',
             'outcomes: ' + ', '.join(f'{k} {v}' for k, v in sorted(outcomes.items())),
             f'runs that broke the contract: {failed}']
    lines += [f'  {count:6d}  {kind}' for kind, count in classes.most_common()]
    text = '\n'.join(lines)
    print(text)
    with open(os.path.join(args.outdir, 'summary.txt'), 'w') as f:
        f.write(text + '\n')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
