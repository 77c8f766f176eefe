#!/usr/bin/env python3
"""Soft and stiff media: an elastic obstacle of stiffness k from 1e-20 to 1e20 traces its path.

Runs tests/regression/decks/arch_plane_stiffness.inp (a shallow arch snapping onto an elastic flat
surface) with k = 1e-20, 1e-10, 1, 1e10, 1e20, the rigid surface (k = 0) and the surface out of reach
(gap = 1e6), and checks:
- every run exits 0 and keeps the complementarity residual (path column lcp_residual) <= 1e-8;
- k = 1e20 traces the rigid surface's path: the same steps, lambda and crown deflection within 1e-8
  relative (a spring of 1e20 shifts a gap by r/k ~ 1e-19 h, far below the Newton tolerance 1e-8 that
  bounds how far each converged state may lie from the exact path);
- k = 1e-20 traces the free arch's path: the same limit points (lambda within 1e-8 relative, for the
  same reason), and no critical point that the free arch has not (a contact start, where the arch
  touches the practically absent surface, is the only extra row allowed).
"""
import argparse
import sys

from uniarc_check import read_table, run_uniarc


def events(path):
    """(kind, lambda) of the rows of a .crit file."""
    names, rows = None, []
    with open(path) as handle:
        for line in handle:
            fields = line.split()
            if names is None:
                names = fields[1:]   # the header line: kind step lambda ...
                continue
            if fields and not line.startswith('#'):
                rows.append((fields[0], float(fields[names.index('lambda')])))
    return rows


def close(a, b, rtol):
    return abs(a - b) <= rtol * max(abs(a), abs(b), 1e-300)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    args = parser.parse_args()
    failures = []
    runs = {}
    cases = {'k=0': ['k=0'], 'free': ['gap=1e6']}
    for k in ('1e-20', '1e-10', '1', '1e10', '1e20'):
        cases['k=' + k] = ['k=' + k]
    for label, defines in cases.items():
        out = f'{args.out}/{label.replace("=", "_")}'
        command, run = run_uniarc(args.uniarc, args.deck, out, defines)
        if run.returncode != 0:
            failures.append(f'{label}: exit {run.returncode}: {run.stderr.strip()}')
            continue
        names, rows = read_table(f'{out}/arch_plane_stiffness.path')
        worst = max(row[names.index('lcp_residual')] for row in rows)
        if worst > 1e-8:
            failures.append(f'{label}: lcp_residual {worst:.3g} > 1e-8')
        runs[label] = (names, rows, events(f'{out}/arch_plane_stiffness.crit'))
        print(f'{label}: {len(rows) - 1} steps, events ' +
              ', '.join(f'{kind} {value:.10g}' for kind, value in runs[label][2]))

    if 'k=0' in runs and 'k=1e20' in runs:
        names, rigid, _ = runs['k=0']
        _, stiff, _ = runs['k=1e20']
        if len(rigid) != len(stiff):
            failures.append(f'k = 1e20: {len(stiff)} rows, the rigid surface {len(rigid)}')
        else:
            for column in ('lambda', 'w_crown_over_h'):
                j = names.index(column)
                for a, b in zip(rigid, stiff):
                    if not close(a[j], b[j], 1e-8) and max(abs(a[j]), abs(b[j])) > 1e-12:
                        failures.append(f'k = 1e20, step {b[0]:g}: {column} {b[j]!r}, rigid {a[j]!r}')
                        break
    if 'free' in runs and 'k=1e-20' in runs:
        free = [e for e in runs['free'][2]]
        soft = [e for e in runs['k=1e-20'][2] if e[0] != 'contact_start']
        if [kind for kind, _ in soft] != [kind for kind, _ in free]:
            failures.append(f'k = 1e-20: events {soft}, the free arch {free}')
        else:
            for (kind, a), (_, b) in zip(free, soft):
                if not close(a, b, 1e-8):
                    failures.append(f'k = 1e-20: {kind} at lambda {b!r}, the free arch {a!r}')
    for failure in failures:
        print('FAIL: ' + failure)
    print('stiffness limits: ' + ('FAILED' if failures else 'ok'))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
