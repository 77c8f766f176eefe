#!/usr/bin/env python3
"""Press, release, press again: a free ring on an elastic tensionless bed (issue 16, second review).

usage: ring_rest_check.py --uniarc BIN --deck DECK --out DIR [--define NAME=VALUE]...
                          [--rest-tol T] [--again-rtol R]

The deck has three analysis steps, each to lambda_max = 1: press (load control), release (load
control, the opposite load), press again (arc length). Ring and bed are elastic, so the path has no
history and each step's end has a closed form:

- end of the release (zero load): the ring undeformed where it started, every nodal displacement
  (ux, uy, rz) within --rest-tol of zero and every reaction within --again-rtol of the largest
  reaction at the end of the press (it rests on its bed at no force);
- end of the press again: the state of the end of the press, every nodal displacement within
  --again-rtol of the largest one there, every reaction within --again-rtol of the largest.

Besides: exit code 0; no row of STEM.path has |lambda| beyond 1 (+1e-12: the load limit lands on it
exactly); every analysis step ends at lambda = 1. Standard library only.
"""
import argparse
import math
import os
import shutil
import subprocess
import sys


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def read_rows(path):
    """Header names and the numeric rows of a whitespace table (comments '#', repeated headers and
    blank lines skipped); blocks: the rows split at blank lines."""
    names = None
    blocks = [[]]
    with open(path) as handle:
        for line in handle:
            text = line.strip()
            if not text:
                if blocks[-1]:
                    blocks.append([])
                continue
            if text.startswith('#'):
                continue
            fields = text.split()
            if fields[0] == 'step':
                names = fields
                continue
            blocks[-1].append([float(value) for value in fields])
    if not blocks[-1]:
        blocks.pop()
    if names is None:
        fail(f'{path}: no header row')
    return names, blocks


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--rest-tol', type=float, default=1e-8)
    parser.add_argument('--again-rtol', type=float, default=1e-7)
    args = parser.parse_args()

    shutil.rmtree(args.out, ignore_errors=True)
    command = [args.uniarc, args.deck, '-o', args.out, '-q']
    for definition in args.define:
        command += ['-D', definition]
    finished = subprocess.run(command, capture_output=True, text=True, timeout=300)
    sys.stdout.write(finished.stdout)
    sys.stderr.write(finished.stderr)
    if finished.returncode != 0:
        fail(f'exit code {finished.returncode}, expected 0')

    stem = os.path.splitext(os.path.basename(args.deck))[0]
    names, blocks = read_rows(os.path.join(args.out, stem + '.path'))
    rows = [row for block in blocks for row in block]
    column = {name: i for i, name in enumerate(names)}
    lam, step, analysis = column['lambda'], column['step'], column['analysis_step']
    for row in rows:
        if abs(row[lam]) > 1.0 + 1e-12:
            fail(f'path row of step {int(row[step])} (analysis step {int(row[analysis])}) at lambda = '
                 f'{row[lam]:.6e}, beyond lambda_max = 1')
    ends = {}
    for row in rows:
        ends[int(row[analysis])] = row
    if sorted(ends) != [1, 2, 3]:
        fail(f'analysis steps in the path: {sorted(ends)}, expected 1, 2, 3')
    for k in (1, 2, 3):
        if abs(ends[k][lam] - 1.0) > 1e-12:
            fail(f'analysis step {k} ended at lambda = {ends[k][lam]:.12e}, not at lambda_max = 1')

    shape_names, shape_blocks = read_rows(os.path.join(args.out, stem + '.shape'))
    s = {name: i for i, name in enumerate(shape_names)}

    def snapshot(end):
        for block in shape_blocks:
            if int(block[0][s['step']]) == int(end[step]) and abs(block[0][s['lambda']] - end[lam]) <= 1e-12:
                return ([max(abs(r[s['ux']]), abs(r[s['uy']]), abs(r[s['rz']])) for r in block],
                        [(r[s['ux']], r[s['uy']], r[s['rz']]) for r in block],
                        [r[s['reaction']] for r in block])
        fail(f'no shape snapshot of step {int(end[step])} at lambda = {end[lam]:.6e}')

    size_load, u_load, reaction_load = snapshot(ends[1])
    size_release, _, reaction_release = snapshot(ends[2])
    _, u_again, reaction_again = snapshot(ends[3])
    w_scale = max(size_load)
    r_scale = max(abs(r) for r in reaction_load)
    if not (w_scale > 0.0 and r_scale > 0.0):
        fail('the press moved nothing or carried nothing')

    rest = max(size_release)
    rest_reaction = max(abs(r) for r in reaction_release)/r_scale
    print(f'end of release: largest displacement {rest:.3e} (tolerance {args.rest_tol:.1e}), largest '
          f'reaction {rest_reaction:.3e} of the pressed one')
    if rest > args.rest_tol:
        fail('end of release: the ring is not back where it started')
    if rest_reaction > args.again_rtol:
        fail('end of release: a contact still carries a force at zero load')

    again = max(max(abs(a - b) for a, b in zip(ua, ub)) for ua, ub in zip(u_again, u_load))/w_scale
    again_reaction = max(abs(a - b) for a, b in zip(reaction_again, reaction_load))/r_scale
    print(f'end of pressing again: displacements {again:.3e}, reactions {again_reaction:.3e} of the end of '
          f'the press (tolerance {args.again_rtol:.1e})')
    if again > args.again_rtol or again_reaction > args.again_rtol:
        fail('end of pressing again: not the state of the end of the press')
    if not all(math.isfinite(v) for r in rows for v in r):
        fail('a path row is not finite')
    print('OK')


if __name__ == '__main__':
    main()
