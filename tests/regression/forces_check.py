#!/usr/bin/env python3
"""Run uniarc on a deck with `*OUTPUT, FORCES` and check STEM.forces, STEM.contact and STEM.path by
column name against closed forms (docs/contracts.md).

Usage (one CTest per call):
  forces_check.py --uniarc BIN --deck DECK --out DIR [--define NAME=VALUE]... [--param NAME=VALUE]...
                  [--expect-forces COLUMN=EXPR:TOL]...   # every element row of the checked step
                  [--expect-contact COLUMN=EXPR:TOL]...  # every candidate row of the checked step
                  [--expect-contact-sum EXPR=VALUE:TOL]... # a sum over the candidate rows of the checked step
                  [--expect-path EXPR]...                # a condition true on every row of STEM.path
                  [--expect-steps TABLE=S1,S2,...]       # the steps written to STEM.TABLE, in order
                  [--step N]                             # the step checked (default: the last written)

EXPR is a Python expression of the row's columns (STEM.forces: N_start, V_start, ..., element; the
column lambda is `lam` there, lambda being a word of Python;
STEM.contact: gap, reaction, length, pressure, s, ...), of the --param names, and of the initial and
current position of the row's nodes read from STEM.shape: `x_start`, `y_start`, `x_end`, `y_end`
(initial coordinates of an element's two nodes) and `x0`, `y0`, `ux`, `uy` (a candidate's node at the
checked step; that step must be a snapshot of STEM.shape, e.g. the last). The math module's names are
there too. A COLUMN=EXPR:TOL holds when |column - EXPR| <= TOL * max(1, max over the rows of |EXPR|):
a tolerance relative to the size of the expected values of the column (absolute for values below 1).
An EXPR=VALUE:TOL of --expect-contact-sum holds when the sum of EXPR over the candidate rows of the
checked step is VALUE to TOL * max(1, |VALUE|) (the resultant of the medium's forces, for equilibrium).

The tables are read as their users read them, by name: numpy.genfromtxt(names=True, dtype=None) and
pandas.read_csv(sep=r'\\s+', comment='#'), which must agree; every table's format (column names, the
provenance lines, counts as integers) is checked as uniarc_check.py checks it.
"""
import argparse
import math
import os
import sys

import numpy as np
import pandas as pd

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uniarc_check import check_table_format, run_uniarc  # noqa: E402


def read_by_name(path):
    """The table at `path` as pandas reads it, after checking that numpy reads the same columns."""
    frame = pd.read_csv(path, sep=r'\s+', comment='#')
    array = np.genfromtxt(path, names=True, dtype=None, encoding=None)
    if list(array.dtype.names) != list(frame.columns):
        raise SystemExit(f'{path}: numpy names {array.dtype.names} != pandas columns {list(frame.columns)}')
    if len(np.atleast_1d(array)) != len(frame):
        raise SystemExit(f'{path}: numpy reads {len(np.atleast_1d(array))} rows, pandas {len(frame)}')
    return frame


def parse_expectation(text):
    column, rest = text.split('=', 1)
    expression, tolerance = rest.rsplit(':', 1)
    return column.strip(), expression, float(tolerance)


def check_rows(label, frame, expectations, environment_of):
    failures = []
    for column, expression, tolerance in expectations:
        if column not in frame.columns:
            failures.append(f'{label}: no column {column} in {list(frame.columns)}')
            continue
        expected = [float(eval(expression, vars(math), environment_of(row))) for row in frame.to_dict('records')]
        got = frame[column].to_numpy(dtype=float)
        scale = max([1.0] + [abs(x) for x in expected])
        worst = max(abs(g - e) for g, e in zip(got, expected))
        ok = worst <= tolerance * scale
        print(f'{"ok" if ok else "FAIL"}: {label} {column} = {expression} over {len(got)} rows: largest '
              f'difference {worst:.3e} (tolerance {tolerance:.1e} x {scale:.3e})')
        if not ok:
            failures.append(f'{label} {column}: difference {worst:.3e} > {tolerance:.1e} x {scale:.3e}')
    return failures


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--param', action='append', default=[])
    parser.add_argument('--expect-forces', action='append', default=[])
    parser.add_argument('--expect-contact', action='append', default=[])
    parser.add_argument('--expect-contact-sum', action='append', default=[])
    parser.add_argument('--expect-path', action='append', default=[])
    parser.add_argument('--expect-steps', action='append', default=[])
    parser.add_argument('--step', type=int)
    args = parser.parse_args()

    command, run = run_uniarc(args.uniarc, args.deck, args.out, args.define)
    if run.returncode != 0:
        print(f'FAIL: exit code {run.returncode}: {" ".join(command)}')
        return 1
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    base = os.path.join(args.out, stem)
    params = {}
    for definition in args.param:
        name, value = definition.split('=', 1)
        params[name] = float(eval(value, vars(math), dict(params)))
    failures = []
    for extension in ('forces', 'contact', 'path'):
        if os.path.exists(f'{base}.{extension}'):
            with open(f'{base}.{extension}') as handle:
                failures += check_table_format(f'{base}.{extension}', handle.read(), args.deck, args.define)

    for text in args.expect_steps:
        table, steps = text.split('=', 1)
        wanted = [int(x) for x in steps.split(',')]
        written = list(dict.fromkeys(read_by_name(f'{base}.{table}')['step']))
        status = 'ok' if written == wanted else 'FAIL'
        print(f'{status}: steps of {stem}.{table}: {written}, expected {wanted}')
        if written != wanted:
            failures.append(f'{stem}.{table} has the steps {written}, not {wanted}')

    if args.expect_forces or args.expect_contact or args.expect_contact_sum:
        forces = read_by_name(f'{base}.forces')
        step = args.step if args.step is not None else int(forces['step'].iloc[-1])
        shape = read_by_name(f'{base}.shape')
        initial = {int(r.node): (r.x0, r.y0) for r in shape.itertuples(index=False)}
        current = {int(r.node): (r.ux, r.uy) for r in shape[shape['step'] == step].itertuples(index=False)}

        def row_values(row):
            values = dict(params, **row)
            values['lam'] = row['lambda']
            return values

        def element_environment(row):
            values = row_values(row)
            values.update(x_start=initial[row['node_start']][0], y_start=initial[row['node_start']][1],
                          x_end=initial[row['node_end']][0], y_end=initial[row['node_end']][1])
            return values

        def candidate_environment(row):
            values = row_values(row)
            values.update(x0=initial[row['node']][0], y0=initial[row['node']][1])
            if row['node'] in current:
                values.update(ux=current[row['node']][0], uy=current[row['node']][1])
            return values

        if args.expect_forces:
            rows = forces[forces['step'] == step]
            if rows.empty:
                failures.append(f'no rows of step {step} in {stem}.forces')
            else:
                failures += check_rows(f'{stem}.forces step {step}', rows,
                                       [parse_expectation(t) for t in args.expect_forces], element_environment)
        if args.expect_contact:
            contact = read_by_name(f'{base}.contact')
            rows = contact[contact['step'] == step]
            if rows.empty:
                failures.append(f'no rows of step {step} in {stem}.contact')
            else:
                failures += check_rows(f'{stem}.contact step {step}', rows,
                                       [parse_expectation(t) for t in args.expect_contact], candidate_environment)
        for text in args.expect_contact_sum:
            expression, rest = text.rsplit('=', 1)
            value, tolerance = (float(eval(x, vars(math), dict(params))) for x in rest.rsplit(':', 1))
            contact = read_by_name(f'{base}.contact')
            rows = contact[contact['step'] == step]
            total = sum(float(eval(expression, vars(math), candidate_environment(row)))
                        for row in rows.to_dict('records'))
            ok = not rows.empty and abs(total - value) <= tolerance * max(1.0, abs(value))
            print(f'{"ok" if ok else "FAIL"}: {stem}.contact step {step}: sum of {expression} over {len(rows)} rows '
                  f'= {total:.12g}, expected {value:.12g} (tolerance {tolerance:.1e})')
            if not ok:
                failures.append(f'{stem}.contact sum of {expression} = {total:.12g}, not {value:.12g}')

    if args.expect_path:
        path = read_by_name(f'{base}.path')
        for condition in args.expect_path:
            bad = [int(row['step']) for row in path.to_dict('records')
                   if not eval(condition, vars(math), dict(params, lam=row['lambda'], **row))]
            print(f'{"ok" if not bad else "FAIL"}: {stem}.path: {condition} on {len(path)} rows')
            if bad:
                failures.append(f'{stem}.path: {condition} fails at steps {bad[:10]}')

    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
