#!/usr/bin/env python3
"""Run uniarc on a deck and check its path file: the project's own numeric diff and value checks.

Usage (one CTest per call):
  uniarc_check.py --uniarc BIN --deck DECK --out DIR [--define NAME=VALUE]...
                  [--reference REF --rtol R --atol A]          # numeric diff of the whole path file
                  [--expect COLUMN=VALUE:RTOL]...               # value of a column in the last row
                  [--expect COLUMN=LOW..HIGH]...                # or its range
                  [--expect-exit N]
                  [--expect-row-where KEY=VALUE:COLUMN=EXPECTED:RTOL]... [--where-exact]
                  [--expect-max COLUMN>=VALUE]... [--expect-min COLUMN<=VALUE]...
                  [--expect-snap-back COLUMN]...
                  [--expect-crit KIND[#k]=EXPECTED]...            # lambda of the k-th event of a kind
                  [--expect-crit-column KIND[#k]:COLUMN=EXPECTED]...
                  [--expect-crit-step-name KIND[#k]=NAME]...     # the step_name of an event (decks with *STEP)
                  [--expect-crit-count KIND=N]... [--expect-crit-before KIND[#k]<KIND[#j]]...
                  [--expect-crit-path KIND[#k]:COLUMN=EXPECTED]...  # a path column at an event
                  [--expect-all COLUMN<=VALUE]...                   # every row of a column bounded
                  [--expect-all COLUMN>=VALUE]...                   # (from above or from below)
                  [--expect-all-ratio NUM/DEN=VALUE:RTOL]...        # NUM/DEN on every row (DEN != 0)
                  [--expect-proportional COLUMN=F:RTOL]...          # every row: COLUMN = F lambda, within
                                                                    # RTOL of the largest |F lambda| (equilibrium)
                  [--expect-affine COLUMN=A,B:ATOL]...              # every row: |COLUMN - (A + B lambda)| <= ATOL
                  [--expect-stderr TEXT]...                         # text the run writes to stderr
                  [--reject-stderr TEXT]...                         # text it must not write there
                  [--expect-stdout TEXT]... [--reject-stdout TEXT]...  # the same of stdout (the run is
                                                                    # then not quiet: its closing lines)

A numeric diff compares the header exactly and every number with |a - b| <= atol + rtol * |b|.
EXPECTED is VALUE:RTOL (relative error at most RTOL) or LOW..HIGH (a range of published values).

--expect-row-where interpolates COLUMN linearly at the first place along the path where KEY (a column,
e.g. lambda) reaches VALUE (KEY=VALUE#n: the n-th place, e.g. the same load on the unstable branch); with --where-exact a row must have KEY = VALUE (to 1e-12 relative), as in a
load-controlled run that is meant to stop exactly at the tabulated loads.
--expect-max / --expect-min bound the largest / smallest value of a column along the whole path.
--expect-snap-back COLUMN asks for a snap-back seen in COLUMN: a row where COLUMN has a strict local
maximum while lambda falls through it (rows before and after), i.e. the path turns back in that
displacement with the load still decreasing.
STEM.crit events are counted per kind in file order, #1 (the default) being the first; the tracked
columns of an event are those of the path file. --expect-crit-before checks the order along the path
(the fractional step numbers) of two events that must both be present.
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys


def read_table(path):
    """Column names and rows (lists of floats) of a uniarc table file: the names on the first line,
    then `#` comment lines (the provenance) and rows (docs/contracts.md)."""
    with open(path) as handle:
        lines = handle.read().splitlines()
    if not lines or not lines[0].strip() or lines[0].startswith('#'):
        raise SystemExit(f'{path}: no header line of column names')
    names = lines[0].split()
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip() or line.startswith('#'):
            continue
        fields = line.split()
        try:
            rows.append([float(x) for x in fields])
        except ValueError:
            raise SystemExit(f'{path}:{number}: not a row of numbers: {line!r}')
        if len(fields) != len(names):
            raise SystemExit(f'{path}:{number}: {len(fields)} fields, header has {len(names)}')
    return names, rows


def run_uniarc(uniarc, deck, out, defines, quiet=True):
    """Run uniarc on a deck into a fresh OUTDIR (it creates the folder and its parents) with -D
    overrides, quietly (-q) unless told; echo its output; return the command and the finished process."""
    shutil.rmtree(out, ignore_errors=True)
    command = [uniarc, deck, '-o', out] + (['-q'] if quiet else [])
    for definition in defines:
        command += ['-D', definition]
    run = subprocess.run(command, capture_output=True, text=True)
    sys.stdout.write(run.stdout)
    sys.stderr.write(run.stderr)
    return command, run


def numeric_diff(result, reference, rtol, atol):
    """List of differences between two table files beyond the tolerance."""
    names_r, rows_r = read_table(result)
    names_f, rows_f = read_table(reference)
    problems = []
    if names_r != names_f:
        problems.append(f'header differs:\n  got      {names_r}\n  expected {names_f}')
        return problems
    if len(rows_r) != len(rows_f):
        problems.append(f'{len(rows_r)} rows, reference has {len(rows_f)}')
    for i, (a_row, b_row) in enumerate(zip(rows_r, rows_f), start=1):
        for name, a, b in zip(names_r, a_row, b_row):
            if abs(a - b) > atol + rtol * abs(b):
                problems.append(f'row {i} column {name}: {a!r} vs reference {b!r}')
    return problems


def parse_expected(text):
    """(low, high, description) of an EXPECTED: `VALUE:RTOL` or `LOW..HIGH`."""
    if '..' in text:
        low, high = (float(x) for x in text.split('..'))
        return min(low, high), max(low, high), f'in [{min(low, high)!r}, {max(low, high)!r}]'
    value, tolerance = (float(x) for x in text.split(':'))
    spread = tolerance * abs(value)
    return value - spread, value + spread, f'{value!r} to {tolerance:.1e} relative'


def check_value(label, got, expected_text):
    """Messages (status line, failure or None) for one value against an EXPECTED."""
    low, high, description = parse_expected(expected_text)
    ok = low <= got <= high
    if '..' not in expected_text:
        value = float(expected_text.split(':')[0])
        description += f' (relative error {abs(got - value) / max(abs(value), 1e-300):.3e})'
    print(f'{"ok" if ok else "FAIL"}: {label} = {got!r}, expected {description}')
    return None if ok else f'{label} = {got!r} not {description}'


def split_event(text):
    """(kind, k) of `KIND` or `KIND#k`, k counted from 1."""
    if '#' in text:
        kind, k = text.split('#', 1)
        return kind.strip(), int(k)
    return text.strip(), 1


def number_or_text(field):
    """A field of a table row as a float, or as its text when it is not a number (a name)."""
    try:
        return float(field)
    except ValueError:
        return field


def read_events(path):
    """Column names (after `kind`) and the events of a STEM.crit file as (kind, [numbers])."""
    with open(path) as handle:
        lines = handle.read().splitlines()
    if not lines or not lines[0].strip() or lines[0].startswith('#'):
        raise SystemExit(f'{path}: no header line of column names')
    names = lines[0].split()[1:]
    events = []
    for number, line in enumerate(lines[1:], start=2):
        fields = line.split()
        if not fields or line.startswith('#'):
            continue
        if len(fields) != len(names) + 1:
            raise SystemExit(f'{path}:{number}: {len(fields)} fields, header has {len(names) + 1}')
        # a deck with steps ends each row with the step's name (text, docs/contracts.md): kept as text
        events.append((fields[0], [number_or_text(x) for x in fields[1:]]))
    return names, events


def find_event(events, kind, k):
    """The k-th event of a kind (numbers), or None."""
    matching = [numbers for event_kind, numbers in events if event_kind == kind]
    return matching[k - 1] if len(matching) >= k else None


def value_where(names, rows, key, target, exact, occurrence=1):
    """Values of the row where `key` reaches `target` the n-th time (interpolated), or an error message."""
    index = names.index(key)
    for i, row in enumerate(rows):
        if abs(row[index] - target) <= 1e-12 * max(abs(target), 1.0):
            return row, None
    if exact:
        return None, f'no row with {key} = {target!r} exactly'
    found = 0
    for before, after in zip(rows, rows[1:]):
        a, b = before[index], after[index]
        if (a - target) * (b - target) < 0.0:
            found += 1
            if found == occurrence:
                t = (target - a) / (b - a)
                return [x + t * (y - x) for x, y in zip(before, after)], None
    return None, f'{key} reaches {target!r} only {found} times, not {occurrence}'


def check_path_features(args, names, rows):
    """Failures of the --expect-row-where, --expect-max/min and --expect-snap-back checks."""
    failures = []
    for expectation in args.expect_row_where:
        where, rest = expectation.split(':', 1)
        key, target = where.split('=', 1)
        occurrence = 1
        if '#' in target:
            target, occurrence = target.split('#')
            occurrence = int(occurrence)
        column, expected = rest.split('=', 1)
        for name in (key, column):
            if name not in names:
                failures.append(f'no column {name} in {names}')
        if failures:
            continue
        row, problem = value_where(names, rows, key, float(target), args.where_exact, occurrence)
        if problem:
            print('FAIL:', problem)
            failures.append(problem)
            continue
        failure = check_value(f'{column} at {key} = {target}', row[names.index(column)], expected)
        if failure:
            failures.append(failure)
    for expectation, is_max in [(e, True) for e in args.expect_max] + [(e, False) for e in args.expect_min]:
        column, bound = expectation.split('>=' if is_max else '<=')
        if column not in names:
            failures.append(f'no column {column} in {names}')
            continue
        values = [row[names.index(column)] for row in rows]
        extreme = max(values) if is_max else min(values)
        ok = extreme >= float(bound) if is_max else extreme <= float(bound)
        label = f'{"max" if is_max else "min"} of {column} = {extreme!r}, expected {"≥" if is_max else "≤"} {bound}'
        print(f'{"ok" if ok else "FAIL"}: {label}')
        if not ok:
            failures.append(label)
    for expectation in args.expect_all:
        if '>=' in expectation:
            column, bound = expectation.split('>=')
            if column not in names:
                failures.append(f'no column {column} in {names}')
                continue
            smallest = min(row[names.index(column)] for row in rows)
            ok = smallest >= float(bound)
            print(f'{"ok" if ok else "FAIL"}: every {column} >= {bound} (smallest {smallest!r})')
            if not ok:
                failures.append(f'{column} reaches {smallest!r} < {bound}')
            continue
        column, bound = expectation.split('<=')
        if column not in names:
            failures.append(f'no column {column} in {names}')
            continue
        largest = max(row[names.index(column)] for row in rows)
        ok = largest <= float(bound)
        print(f'{"ok" if ok else "FAIL"}: every {column} <= {bound} (largest {largest!r})')
        if not ok:
            failures.append(f'{column} reaches {largest!r} > {bound}')
    for expectation in args.expect_all_ratio:
        # e.g. reaction_sum/lambda=200:1e-6: an equilibrium every written row must satisfy
        ratio, expected = expectation.split('=')
        numerator, denominator = ratio.split('/')
        value, tolerance = (float(x) for x in expected.split(':'))
        if numerator not in names or denominator not in names:
            failures.append(f'no column {numerator} or {denominator} in {names}')
            continue
        worst, worst_step = 0.0, None
        for row in rows:
            den = row[names.index(denominator)]
            if den == 0.0:
                continue
            error = abs(row[names.index(numerator)] / den - value) / abs(value)
            if error >= worst:
                worst, worst_step = error, row[names.index('step')]
        ok = worst <= tolerance
        print(f'{"ok" if ok else "FAIL"}: every {ratio} = {value!r} (worst relative error {worst:.3e} at step '
              f'{worst_step}, tolerance {tolerance:.1e})')
        if not ok:
            failures.append(f'{ratio}: relative error {worst:.3e} > {tolerance:.1e} at step {worst_step}')
    for expectation in args.expect_proportional:
        column, rest = expectation.split('=')
        factor, rtol = (float(v) for v in rest.split(':'))
        if column not in names or 'lambda' not in names:
            failures.append(f'no column {column} or lambda in {names}')
            continue
        expected = [factor*row[names.index('lambda')] for row in rows]
        unit = max(abs(v) for v in expected) or 1.0
        worst = max(abs(row[names.index(column)] - v) for row, v in zip(rows, expected))/unit
        ok = worst <= rtol
        print(f'{"ok" if ok else "FAIL"}: every {column} = {factor} lambda, largest difference {worst:.3e} of '
              f'{unit:.6e} (tolerance {rtol})')
        if not ok:
            failures.append(f'{column} differs from {factor} lambda by {worst:.3e} (relative)')
    for expectation in args.expect_affine:
        # e.g. w=-0.5,-0.01:1e-6: a closed form A + B lambda that every written row must satisfy
        column, rest = expectation.split('=')
        coefficients, atol = rest.split(':')
        a, b = (float(v) for v in coefficients.split(','))
        atol = float(atol)
        if column not in names or 'lambda' not in names:
            failures.append(f'no column {column} or lambda in {names}')
            continue
        errors = [(abs(row[names.index(column)] - (a + b*row[names.index('lambda')])), row[names.index('step')])
                  for row in rows]
        worst, worst_step = max(errors)
        ok = worst <= atol
        print(f'{"ok" if ok else "FAIL"}: every {column} = {a!r} + {b!r} lambda, largest difference {worst:.3e} '
              f'at step {worst_step:g} (tolerance {atol:.1e})')
        if not ok:
            failures.append(f'{column} differs from {a} + {b} lambda by {worst:.3e} at step {worst_step:g}')
    for column in args.expect_snap_back:
        if column not in names:
            failures.append(f'no column {column} in {names}')
            continue
        c = [row[names.index(column)] for row in rows]
        lam = [row[names.index('lambda')] for row in rows]
        turns = [i for i in range(1, len(rows) - 1)
                 if c[i - 1] < c[i] > c[i + 1] and lam[i - 1] > lam[i] > lam[i + 1]]
        if turns:
            i = turns[0]
            print(f'ok: snap-back in {column}: maximum {c[i]!r} at step {rows[i][0]:g} (lambda {lam[i]!r}), '
                  f'then {c[i + 1]!r} with lambda falling to {lam[i + 1]!r}')
        else:
            failures.append(f'no snap-back in {column}: no local maximum with lambda falling through it')
    return failures


def check_events(args, crit_file, path_names=None, path_rows=None):
    """Failures of the --expect-crit* checks on STEM.crit."""
    failures = []
    names, events = read_events(crit_file)
    for expectation in args.expect_crit_path:
        left, expected = expectation.split('=', 1)
        event, column = left.rsplit(':', 1)
        kind, k = split_event(event)
        numbers = find_event(events, kind, k)
        if numbers is None or path_names is None or column not in path_names:
            failures.append(f'no event {kind}#{k} or no path column {column}')
            continue
        # the path column between the two steps around the event, at the event's fraction
        position = numbers[names.index('step')]
        steps = [row[0] for row in path_rows]
        after = next((i for i, step in enumerate(steps) if step >= position), len(steps) - 1)
        before = max(after - 1, 0)
        span = steps[after] - steps[before]
        t = (position - steps[before]) / span if span > 0 else 0.0
        index = path_names.index(column)
        value = path_rows[before][index] + t * (path_rows[after][index] - path_rows[before][index])
        failure = check_value(f'{column} of the path at {kind}#{k}', value, expected)
        if failure:
            failures.append(failure)
    print(f'{crit_file}: ' + (', '.join(f'{kind} at lambda {numbers[1]:.6g}' for kind, numbers in events)
                              or 'no events'))
    for expectation in args.expect_crit:
        event, expected = expectation.split('=', 1)
        kind, k = split_event(event)
        numbers = find_event(events, kind, k)
        if numbers is None:
            failures.append(f'no event {kind}#{k} in {crit_file}')
            continue
        failure = check_value(f'lambda of {kind}#{k}', numbers[names.index('lambda')], expected)
        if failure:
            failures.append(failure)
    for expectation in args.expect_crit_step_name:
        event, expected = expectation.split('=', 1)
        kind, k = split_event(event)
        numbers = find_event(events, kind, k)
        if numbers is None or 'step_name' not in names:
            failures.append(f'no event {kind}#{k} or no column step_name in {crit_file}')
            continue
        got = numbers[names.index('step_name')]
        print(f'{"ok" if got == expected else "FAIL"}: step_name at {kind}#{k} = {got!r}, expected {expected!r}')
        if got != expected:
            failures.append(f'step_name at {kind}#{k} = {got!r}, not {expected!r}')
    for expectation in args.expect_crit_column:
        left, expected = expectation.split('=', 1)
        event, column = left.rsplit(':', 1)
        kind, k = split_event(event)
        numbers = find_event(events, kind, k)
        if numbers is None or column not in names:
            failures.append(f'no event {kind}#{k} or no column {column} in {crit_file}')
            continue
        failure = check_value(f'{column} at {kind}#{k}', numbers[names.index(column)], expected)
        if failure:
            failures.append(failure)
    for expectation in args.expect_crit_count:
        kind, count = expectation.split('=')
        found = sum(1 for event_kind, _ in events if event_kind == kind)
        print(f'{"ok" if found == int(count) else "FAIL"}: {found} events {kind}, expected {count}')
        if found != int(count):
            failures.append(f'{found} events {kind}, expected {count}')
    for expectation in args.expect_crit_before:
        first, second = (split_event(x) for x in expectation.split('<'))
        a, b = find_event(events, *first), find_event(events, *second)
        if a is None or b is None:
            failures.append(f'{expectation}: an event is missing')
            continue
        step = names.index('step')
        ok = a[step] < b[step]
        print(f'{"ok" if ok else "FAIL"}: {first[0]}#{first[1]} at step {a[step]:.4f} (lambda {a[1]:.6g}) '
              f'{"before" if ok else "not before"} {second[0]}#{second[1]} at step {b[step]:.4f} '
              f'(lambda {b[1]:.6g})')
        if not ok:
            failures.append(f'{expectation}: wrong order')
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--reference')
    parser.add_argument('--rtol', type=float, default=1e-8)
    parser.add_argument('--atol', type=float, default=1e-12)
    parser.add_argument('--expect', action='append', default=[])
    parser.add_argument('--expect-exit', type=int, default=0)
    parser.add_argument('--expect-row-where', action='append', default=[])
    parser.add_argument('--where-exact', action='store_true')
    parser.add_argument('--expect-max', action='append', default=[])
    parser.add_argument('--expect-min', action='append', default=[])
    parser.add_argument('--expect-snap-back', action='append', default=[])
    parser.add_argument('--expect-crit', action='append', default=[])
    parser.add_argument('--expect-crit-column', action='append', default=[])
    parser.add_argument('--expect-crit-step-name', action='append', default=[])
    parser.add_argument('--expect-crit-count', action='append', default=[])
    parser.add_argument('--expect-crit-before', action='append', default=[])
    parser.add_argument('--expect-crit-path', action='append', default=[])
    parser.add_argument('--expect-all', action='append', default=[])
    parser.add_argument('--expect-all-ratio', action='append', default=[])
    parser.add_argument('--expect-proportional', action='append', default=[])
    parser.add_argument('--expect-affine', action='append', default=[])
    parser.add_argument('--expect-stderr', action='append', default=[])
    parser.add_argument('--expect-modes-min', action='append', default=[])
    parser.add_argument('--expect-no-return', action='append', default=[])
    parser.add_argument('--expect-no-walk-back', action='append', default=[],
                        help='COLUMN,COLUMN,...: no row goes back along the path traced by earlier rows '
                             '(check_no_walk_back)')
    parser.add_argument('--expect-free-span', action='append', default=[])
    parser.add_argument('--expect-count-explained', action='store_true',
                        help='every change of the neg_pivots column between two rows of the path has a row of '
                             'STEM.crit between those steps')
    parser.add_argument('--expect-mirror-reactions', action='append', default=[])
    parser.add_argument('--reject-stderr', action='append', default=[])
    parser.add_argument('--expect-stdout', action='append', default=[])
    parser.add_argument('--reject-stdout', action='append', default=[])
    args = parser.parse_args()

    command, run = run_uniarc(args.uniarc, args.deck, args.out, args.define,
                              quiet=not (args.expect_stdout or args.reject_stdout))
    if run.returncode != args.expect_exit:
        print(f'FAIL: exit code {run.returncode}, expected {args.expect_exit}: {" ".join(command)}')
        return 1
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    path_file = os.path.join(args.out, stem + '.path')
    failures = []
    for text in args.expect_stderr:
        if text not in run.stderr:
            failures.append(f'stderr does not contain {text!r}')
    for text in args.reject_stderr:
        if text in run.stderr:
            failures.append(f'stderr contains {text!r}, which is not the cause')
    for text in args.expect_stdout:
        if text not in run.stdout:
            failures.append(f'stdout does not contain {text!r}')
    for text in args.reject_stdout:
        if text in run.stdout:
            failures.append(f'stdout contains {text!r}')
    if args.reference:
        failures += numeric_diff(path_file, args.reference, args.rtol, args.atol)
    if args.expect:
        names, rows = read_table(path_file)
        if not rows:
            failures.append('path file has no rows')
        for expectation in args.expect:
            column, rest = expectation.split('=', 1)
            if column not in names:
                failures.append(f'no column {column} in {names}')
                continue
            if '..' in rest:
                # LOW..HIGH: a bound, e.g. on a count (a one-row static path has no --expect-all)
                failure = check_value(column, rows[-1][names.index(column)], rest)
                if failure:
                    failures.append(failure)
                continue
            value, tolerance = (float(x) for x in rest.split(':'))
            got = rows[-1][names.index(column)]
            error = abs(got - value) / max(abs(value), 1e-300)
            status = 'ok' if error <= tolerance else 'FAIL'
            print(f'{status}: {column} = {got!r}, expected {value!r}, relative error {error:.3e} '
                  f'(tolerance {tolerance:.1e})')
            if error > tolerance:
                failures.append(f'{column}: relative error {error:.3e} > {tolerance:.1e}')
    if (args.expect_row_where or args.expect_max or args.expect_min or args.expect_snap_back or args.expect_all
            or args.expect_all_ratio or args.expect_proportional or args.expect_affine):
        names, rows = read_table(path_file)
        if len(rows) < 2:
            failures.append('path file has fewer than two rows')
        else:
            failures += check_path_features(args, names, rows)
    if args.expect_no_return:
        names, rows = read_table(path_file)
        failures += check_no_return(args.expect_no_return, names, rows)
    for expectation in args.expect_no_walk_back:
        names, rows = read_table(path_file)
        failures += check_no_walk_back(expectation.split(','), names, rows)
    for expectation in args.expect_modes_min:
        failures += check_modes_min(expectation, os.path.join(args.out, stem + '.modes'))
    for expectation in args.expect_free_span:
        failures += check_free_span(expectation, os.path.join(args.out, stem + '.contact'))
    for expectation in args.expect_mirror_reactions:
        failures += check_mirror_reactions(expectation, os.path.join(args.out, stem + '.contact'))
    if (args.expect_crit or args.expect_crit_column or args.expect_crit_count or args.expect_crit_before
            or args.expect_crit_path or args.expect_crit_step_name):
        path_names, path_rows = read_table(path_file)
        failures += check_events(args, os.path.join(args.out, stem + '.crit'), path_names, path_rows)
    crit_file = os.path.join(args.out, stem + '.crit')
    if args.expect_exit in (0, 1) and os.path.exists(crit_file) and os.path.exists(path_file):
        failures += check_limits_bracketed(path_file, crit_file)
    if args.expect_count_explained:
        failures += check_count_explained(path_file, crit_file)
    # On every run: no result file shows a negative zero (pandas and gnuplot users see '-0'), and
    # every table has its provenance lines and its counts written as integers.
    for name in sorted(os.listdir(args.out)) if os.path.isdir(args.out) else []:
        if name.startswith(stem + '.') and name.split('.')[-1] in ('path', 'crit', 'shape', 'surface', 'forces',
                                                                    'contact', 'modes'):
            with open(os.path.join(args.out, name)) as f:
                text = f.read()
            if '-0.000000000000E+000' in text:
                failures.append('%s has a negative zero' % name)
            failures += check_table_format(os.path.join(args.out, name), text, args.deck, args.define)
    # On every run: STEM.crit lists its rows in path order (docs/contracts.md), their step column not
    # decreasing.
    if os.path.exists(crit_file):
        with open(crit_file) as f:
            positions = [float(line.split()[1]) for line in f.read().splitlines()[1:]
                         if line.strip() and not line.startswith('#')]
        for earlier, later in zip(positions, positions[1:]):
            if later < earlier:
                failures.append(f'{stem}.crit is not in path order: step {later!r} after {earlier!r}')
    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


def check_modes_min(expectation, modes_file):
    """--expect-modes-min COLUMN=VALUE: STEM.modes has rows, and COLUMN is at least VALUE on every one
    (a mode on the admissible cone of a bed pushing along +y: uy >= -round-off at every node, none of
    it pressing into the bed)."""
    column, value = expectation.split('=', 1)
    value = float(value)
    if not os.path.exists(modes_file):
        return [f'no {modes_file}']
    with open(modes_file) as handle:
        lines = [line for line in handle.read().splitlines() if line.strip()]
    names = lines[0].split()
    if column not in names:
        return [f'no column {column} in {modes_file}']
    rows = [line.split() for line in lines[1:] if not line.startswith('#')]
    if not rows:
        return [f'{modes_file} has no rows']
    least = min(float(row[names.index(column)]) for row in rows)
    print(f'{"ok" if least >= value else "FAIL"}: least {column} of the modes = {least!r}, expected >= {value!r}')
    return [] if least >= value else [f'{column} of a mode is {least!r} < {value!r}']


def check_no_return(columns, names, rows):
    """--expect-no-return COLUMN: past the largest lambda of the last analysis step, COLUMN never
    decreases from one row to the next (a post-buckling trace whose buckle only grows; a row going back
    along the traced path shows it shrinking)."""
    failures = []
    if 'analysis_step' in names:
        last = max(row[names.index('analysis_step')] for row in rows)
        rows = [row for row in rows if row[names.index('analysis_step')] == last]
    if len(rows) < 2:
        return ['fewer than two rows in the last analysis step']
    peak = max(range(len(rows)), key=lambda i: rows[i][names.index('lambda')])
    for column in columns:
        if column not in names:
            failures.append(f'no column {column} in {names}')
            continue
        c = [row[names.index(column)] for row in rows[peak:]]
        back = [i for i in range(1, len(c)) if c[i] < c[i - 1]]
        if back:
            i = back[0] + peak
            failures.append(f'{column} decreases past the largest lambda: {rows[i - 1][names.index(column)]!r} at step '
                            f'{rows[i - 1][0]:g}, {rows[i][names.index(column)]!r} at step {rows[i][0]:g}')
        else:
            print(f'ok: {column} does not decrease over the {len(c)} rows from the largest lambda '
                  f'(step {rows[peak][0]:g}) on')
    return failures


def check_no_walk_back(columns, names, rows):
    """--expect-no-walk-back lambda,COLUMN,...: no row revisits an earlier row's state in reverse (issue
    11, Deliver 3). In the space of the given columns, each scaled by its range over the path, two
    consecutive steps (rows i-1 -> i and i -> i+1) each land on an earlier segment (rows j -> j+1, ending
    before the step's start) and run against it: the step's chord makes a cosine below -0.9 with the
    segment's, the landing row lies within 0.15 of the segment's length of it (its projection
    between -0.15 and 1.15 of the way along), and the step's start lies so on that segment or on one traced
    after it. 0.15 is the sagitta share of the solver's own retrace test
    (uniarc_path_trace.f90): a step's arc leaves its chord by at most 0.05 of its length away from folds.
    Not a fold: past a limit point lambda turns and the displacements go on (or the other way at a
    snap-back), so the step is not against the earlier one in every column; only a path retracing itself
    is. Two steps in a row, so that a single crossing of two pieces in the projection does not count.
    Opt-in, for paths that must not come back: on the few tracked columns a path of many loops meets its
    own projection (arch_above_long_path), and a load history that unloads goes back by design."""
    for column in columns:
        if column not in names:
            return [f'no column {column} in {names}']
    index = [names.index(column) for column in columns]
    scale = []
    for k in index:
        values = [row[k] for row in rows]
        scale.append(max(values) - min(values))
    used = [m for m in range(len(index)) if scale[m] > 0.0]
    points = [[row[index[m]]/scale[m] for m in used] for row in rows]

    def dot(a, b):
        return sum(x*y for x, y in zip(a, b))

    def minus(a, b):
        return [x - y for x, y in zip(a, b)]

    def tube(p, last):
        """The earlier segments (rows j -> j+1, j + 1 <= last) whose tube holds the point p, with their
        chords."""
        found = []
        for j in range(0, last):
            chord = minus(points[j + 1], points[j])
            length2 = dot(chord, chord)
            if length2 == 0.0:
                continue
            offset = minus(p, points[j])
            t = dot(offset, chord)/length2
            if t < -0.15 or t > 1.15:
                continue
            normal = [o - t*c for o, c in zip(offset, chord)]
            if dot(normal, normal) <= 0.15**2*length2:
                found.append((j, chord))
        return found

    def landing(i):
        """The first row of the earlier segment that the step into row i runs back along, or None: the
        step's end lies on a segment whose chord it runs against, and its start on that segment or on
        one traced after it (a step that only crosses the old path starts away from it)."""
        step = minus(points[i], points[i - 1])
        size_step = dot(step, step) ** 0.5
        if size_step == 0.0:
            return None
        starts = [j for j, _ in tube(points[i - 1], i - 2)]
        if not starts:
            return None
        for j, chord in tube(points[i], i - 2):
            if dot(step, chord) <= -0.9*size_step*dot(chord, chord) ** 0.5 and max(starts) >= j:
                return j
        return None

    previous = None
    for i in range(2, len(points)):
        j = landing(i)
        if j is not None and previous is not None:
            return [f'the path walks back: the steps to rows {rows[i - 1][0]:g} and {rows[i][0]:g} '
                    f'(lambda {rows[i][names.index("lambda")]!r}) go back along the rows from step '
                    f'{rows[previous][0]:g} and {rows[j][0]:g} traced before']
        previous = j
    print(f'ok: no step of the {len(rows)} rows goes back along the path traced before ({",".join(columns)})')
    return []


def check_mirror_reactions(expectation, contact_file):
    """--expect-mirror-reactions N:TOL on STEM.contact (*OUTPUT, FORCES, EVERY=1): at every step of the
    last analysis step the reactions of the candidates at nodes i and N + 1 - i agree within TOL times
    the step's largest reaction (a mirror-symmetric structure traced on its symmetric path: a step that
    changed one contact of a mirror pair and not the other shows as a difference of the order of the
    reactions)."""
    spec, tolerance = expectation.split(':')
    mirror, tolerance = int(spec), float(tolerance)
    if not os.path.exists(contact_file):
        return [f'no {contact_file}']
    with open(contact_file) as f:
        lines = [line.split() for line in f.read().splitlines() if line.strip() and not line.startswith('#')]
    names = lines[0]
    col = {n: names.index(n) for n in ('step', 'node', 'reaction', 'analysis_step')}
    rows = [fields for fields in lines[1:]]
    last = max(float(r[col['analysis_step']]) for r in rows)
    steps = {}
    for r in rows:
        if float(r[col['analysis_step']]) == last:
            steps.setdefault(float(r[col['step']]), {})[int(r[col['node']])] = float(r[col['reaction']])
    worst, worst_step = 0.0, None
    for step, reactions in sorted(steps.items()):
        largest = max(abs(v) for v in reactions.values())
        if largest == 0.0:
            continue
        for node, reaction in reactions.items():
            if mirror + 1 - node not in reactions:
                return [f'step {step:g}: node {node} has no mirror image {mirror + 1 - node} among the candidates']
            difference = abs(reaction - reactions[mirror + 1 - node])/largest
            if difference > worst:
                worst, worst_step = difference, step
    ok = worst <= tolerance
    where = f' at step {worst_step:g}' if worst_step is not None else ''
    print(f'{"ok" if ok else "FAIL"}: reactions of nodes i and {mirror + 1} - i at the {len(steps)} steps of analysis '
          f'step {last:g} (worst difference {worst:.3e} of the largest{where}, tolerance {tolerance:.1e})')
    return [] if ok else [f'mirror reactions differ by {worst:.3e} of the largest{where}']


def check_free_span(expectation, contact_file):
    """--expect-free-span LAMBDA_MAX,EI,H,S_MID[,LAMBDA_MIN]=VALUE:TOL on STEM.contact (*OUTPUT, FORCES,
    EVERY=1): at every step of the last analysis step past its largest lambda (post-buckling) with
    LAMBDA_MIN <= lambda <= LAMBDA_MAX, the lifted span L between the
    innermost candidates with a reaction on either side of S_MID (their coordinates s), plus H (the
    lift-off point lies between that node and the next free one on each side: half of 2H on average),
    gives lambda L^2/EI = VALUE within TOL (relative)."""
    spec, target = expectation.split('=')
    fields = [float(v) for v in spec.split(',')]
    lam_max, ei, h, s_mid = fields[:4]
    lam_min = fields[4] if len(fields) > 4 else -float('inf')
    value, tolerance = (float(v) for v in target.split(':'))
    if not os.path.exists(contact_file):
        return [f'no {contact_file}']
    with open(contact_file) as f:
        lines = [line.split() for line in f.read().splitlines() if line.strip() and not line.startswith('#')]
    names = lines[0]
    col = {n: names.index(n) for n in ('step', 'lambda', 's', 'reaction', 'analysis_step')}
    # the medium column is a name: only the numeric columns used are read
    rows = [[float(fields[i]) if i in col.values() else 0.0 for i in range(len(fields))] for fields in lines[1:]]
    if not rows:
        return [f'no rows in {contact_file}']
    last = max(row[col['analysis_step']] for row in rows)
    rows = [row for row in rows if row[col['analysis_step']] == last]
    peak = max(rows, key=lambda row: row[col['lambda']])[col['step']]
    steps = {}
    for row in rows:
        if row[col['step']] > peak and lam_min <= row[col['lambda']] <= lam_max:
            steps.setdefault(row[col['step']], []).append(row)
    if not steps:
        return [f'no step with lambda <= {lam_max:g} in {contact_file}']
    worst, worst_step, worst_value = 0.0, None, None
    for step, cands in sorted(steps.items()):
        s_left = [r[col['s']] for r in cands if r[col['reaction']] > 0.0 and r[col['s']] < s_mid]
        s_right = [r[col['s']] for r in cands if r[col['reaction']] > 0.0 and r[col['s']] > s_mid]
        if not s_left or not s_right:
            return [f'step {step:g}: no contact on one side of s = {s_mid:g}']
        span = min(s_right) - max(s_left) + h
        got = cands[0][col['lambda']]*span**2/ei
        error = abs(got - value)/value
        if error >= worst:
            worst, worst_step, worst_value = error, step, got
    ok = worst <= tolerance
    print(f'{"ok" if ok else "FAIL"}: lambda L^2/EI = {value!r} at the {len(steps)} steps with lambda <= {lam_max:g} '
          f'(worst {worst_value!r} at step {worst_step:g}, relative error {worst:.3e}, tolerance {tolerance:.1e})')
    return [] if ok else [f'lambda L^2/EI: relative error {worst:.3e} > {tolerance:.1e} at step {worst_step:g}']


INTEGER_COLUMNS = ('step', 'node', 'n_contact', 'contact_regions', 'lcp_pivots', 'iterations', 'neg_pivots',
                   'candidate', 'rigid', 'element', 'node_start', 'node_end', 'bifurcation')


def check_table_format(path, text, deck, defines):
    """docs/contracts.md: the column names on line 1, then the four provenance lines (`# uniarc
    VERSION`, `# deck: DECK`, `# defines: NAME=VALUE ...` or `none`, `# utc: ISO 8601 Z`), then rows
    whose count columns are integers (STEM.crit's step is fractional: events lie between steps)."""
    failures = []
    lines = text.splitlines()
    name = os.path.basename(path)
    if len(lines) < 5:
        return [f'{name}: fewer than 5 lines']
    names = lines[0].split()
    expected = [r'# uniarc \d+\.\d+\.\d+', '# deck: ' + re.escape(deck),
                '# defines: ' + (re.escape(' '.join(d.replace(' ', '') for d in defines)) if defines else 'none'),
                r'# utc: \d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ']
    for number, pattern in enumerate(expected, start=2):
        if not re.fullmatch(pattern, lines[number - 1]):
            failures.append(f'{name}:{number}: {lines[number - 1]!r} is not the provenance line {pattern!r}')
    counts = [i for i, column in enumerate(names)
              if (column in INTEGER_COLUMNS or column.startswith(('n_contact_', 'contact_regions_')))
              and not (column == 'step' and name.endswith(('.crit', '.modes')))]
    for number, line in enumerate(lines[5:], start=6):
        fields = line.split()
        if line.startswith('#') or not fields:
            continue
        bad = [names[i] for i in counts if i < len(fields) and not re.fullmatch(r'-?\d+', fields[i])]
        if bad:
            failures.append(f'{name}:{number}: the counts {bad} are not integers: {line!r}')
            break
    return failures


def check_limits_bracketed(path_file, crit_file):
    """Every run: every critical row lies on the path between the converged steps around it
    (docs/contracts.md, STEM.crit). A limit_max is not below those steps, a limit_min not above them
    (an extremum of lambda between two converged points bounds both); a contact_corner, where lambda
    turns at a corner, is not strictly between them either. Every other row (bifurcation,
    unilateral_bifurcation, contact_stability, contact_branching, contact events, bearing_collapse)
    has its lambda within the range of its two neighbours, widened to the lambda of a limit or corner
    row of the same interval (the only place lambda can turn inside it), and each tracked column
    within the range of the neighbours' values (the tracked values are those of a state between them).
    A row at a whole step may end the interval before it or start the one after. contact_start and
    contact_lost rows too: a contact_start located by re-solving the step is an equilibrium state of
    the path between them (uniarc_path_contact_start); otherwise their lambda, read along the tangent
    of the piece leading to them, is placed at the converged state where the set is seen changed when
    that tangent leaves the interval (uniarc_critical_points, find_contact_events). Not a branch_switch row, whose interval
    joins two branches; with analysis steps (*STEP) a row is compared with the rows of its own
    analysis step (the crit file's analysis_step), whose lambdas are one path's. The tracked columns
    of a contact_start row (and of a contact_corner at its position) are exempt: they are those of the
    state where the contact closes, the kink of the path at which a tracked quantity may turn (the
    cantilever pressed onto an oblique ellipse, cantilever_on_ellipse.inp: u_tip shortens to
    -5.979e-9 at the touch, then the reaction's horizontal part pushes it back to -5.806e-9 at the
    next step, from -2.490e-9 at the step before). The files carry 13 significant digits, so comparisons allow 1e-12 relative."""
    failures = []
    path_names, path_rows = read_table(path_file)
    by_step = {int(round(row[0])): row for row in path_rows}
    names, events = read_events(crit_file)
    lam_path = path_names.index('lambda')
    stage = path_names.index('analysis_step') if 'analysis_step' in path_names else None
    columns = [(names.index(n), path_names.index(n)) for n in names
               if n in path_names and n not in ('step', 'lambda', 'analysis_step', 'step_name')]
    turning = ('limit_max', 'limit_min', 'contact_corner')
    skipped = ('branch_switch',)

    def slack(*values):
        return 1e-12 * max([abs(v) for v in values] + [1e-300])

    event_stage = names.index('analysis_step') if 'analysis_step' in names else None

    def neighbours(position, numbers):
        # a row at a whole step may end the interval before it (fraction 1) or start the next (fraction 0)
        steps = {math.floor(position), math.ceil(position)}
        if math.floor(position) == math.ceil(position):
            steps |= {int(position) - 1, int(position) + 1}
        if stage is not None and event_stage is not None and isinstance(numbers[event_stage], float):
            # the rows of the event's own analysis step (*STEP): at a step's end the path file has the
            # last row of one analysis step and the first of the next under one step number
            return [row for row in path_rows
                    if int(round(row[0])) in steps and row[stage] == numbers[event_stage]]
        rows = [by_step[k] for k in sorted(steps) if k in by_step]
        if stage is not None and len({row[stage] for row in rows}) > 1:
            return []
        return rows

    starts = {numbers[names.index('step')] for kind, numbers in events if kind == 'contact_start'}
    turns = {}
    for kind, numbers in events:
        if kind in turning:
            position = numbers[names.index('step')]
            turns.setdefault(math.floor(position), []).append(numbers[names.index('lambda')])
    for kind, numbers in events:
        if kind in skipped:
            continue
        position, value = numbers[names.index('step')], numbers[names.index('lambda')]
        rows = neighbours(position, numbers)
        if not rows:
            continue
        around = [row[lam_path] for row in rows]
        tol = slack(value, *around)
        if kind == 'limit_max' and any(value < x - tol for x in around):
            failures.append(f'limit_max at step {position:g}: lambda {value!r} below a converged neighbour {around}')
        elif kind == 'limit_min' and any(value > x + tol for x in around):
            failures.append(f'limit_min at step {position:g}: lambda {value!r} above a converged neighbour {around}')
        elif kind == 'contact_corner' and min(around) + tol < value < max(around) - tol:
            failures.append(f'contact_corner at step {position:g}: lambda {value!r} strictly between its neighbours '
                            f'{around}, where lambda does not turn')
        elif kind not in turning:
            low = min(around + turns.get(math.floor(position), []))
            high = max(around + turns.get(math.floor(position), []))
            if value < low - tol or value > high + tol:
                failures.append(f'{kind} at step {position:g}: lambda {value!r} outside [{low!r}, {high!r}], the '
                                f'range of its converged neighbours {around}: not a state of the path between them')
        if kind == 'contact_start' or (kind == 'contact_corner' and position in starts):
            continue
        for crit_column, path_column in columns:
            got = numbers[crit_column]
            if not isinstance(got, float):
                continue
            values = [row[path_column] for row in rows]
            tol = slack(got, *values)
            if got < min(values) - tol or got > max(values) + tol:
                failures.append(f'{kind} at step {position:g}: {names[crit_column]} {got!r} outside the range of '
                                f'its converged neighbours {values}')
    return failures


def check_count_explained(path_file, crit_file):
    """Every change of the stability count (the path's neg_pivots column) between two consecutive rows
    is explained by an event of STEM.crit located between those two steps (a limit point, a
    bifurcation of either kind, a contact event: docs/contracts.md, STEM.crit)."""
    failures = []
    path_names, path_rows = read_table(path_file)
    column = path_names.index('neg_pivots')
    names, events = read_events(crit_file)
    positions = [numbers[names.index('step')] for _, numbers in events]
    for a, b in zip(path_rows, path_rows[1:]):
        if a[column] == b[column]:
            continue
        if not any(a[0] <= position <= b[0] for position in positions):
            failures.append(f'neg_pivots changes from {a[column]:g} to {b[column]:g} between steps {a[0]:g} and '
                            f'{b[0]:g} with no row of {os.path.basename(crit_file)} there')
    return failures


if __name__ == '__main__':
    sys.exit(main())
