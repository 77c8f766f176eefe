#!/usr/bin/env python3
"""*IMPERFECTION (issue 11 item 5; docs/input.md): Walker's whole arch with its antisymmetric buckling
mode added to the geometry follows the asymmetric path smoothly, with a limit point below the perfect
arch's bifurcation load that tends to it as the amplitude goes to zero.

Runs --modes-deck (the perfect arch with *OUTPUT, MODES) and checks that the modes table committed
next to --deck (read by its *IMPERFECTION, FILE=) is the mode the program writes; then runs --deck
with -D amplitude=a for a = 1e-2, 1e-3, 1e-4 and checks, for each: no bifurcation row (the imperfect
path is smooth), a first limit_max below the bifurcation load, the crown displaced sideways there;
and that --computed-deck (the mode computed by the program in a first run, no FILE=) gives the same
limit; and across them: the limit loads rise towards the bifurcation load as a falls, and their distance
to it follows Koiter's (1945) law for an unstable-symmetric bifurcation, λ_c − λ_s ∝ a^(2/3)
(Thompson & Hunt 1973, ch. 3): consecutive ratios 10^(2/3) = 4.642.
"""
import argparse
import os
import shutil
import subprocess
import sys


def read_rows(path):
    with open(path) as handle:
        lines = handle.read().splitlines()
    names = lines[0].split()
    return names, [line.split() for line in lines[1:] if line.strip() and not line.startswith('#')]


def run(uniarc, deck, out, defines=()):
    shutil.rmtree(out, ignore_errors=True)
    command = [uniarc, deck, '-o', out, '-q']
    for definition in defines:
        command += ['-D', definition]
    result = subprocess.run(command, capture_output=True, text=True)
    sys.stdout.write(result.stdout)
    sys.stderr.write(result.stderr)
    if result.returncode != 0:
        raise SystemExit(f'{" ".join(command)}: exit code {result.returncode}')
    return os.path.join(out, os.path.splitext(os.path.basename(deck))[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True, help='the imperfect arch (its *IMPERFECTION reads MODES)')
    parser.add_argument('--modes-deck', required=True, help='the perfect arch with *OUTPUT, MODES')
    parser.add_argument('--modes', required=True, help='the modes table committed next to --deck')
    parser.add_argument('--computed-deck', required=True,
                        help='the same imperfect arch with the mode computed by the program (no FILE=)')
    parser.add_argument('--out', required=True)
    args = parser.parse_args()
    failures = []

    # The committed table is the program's own: the same mode to 1e-5 of its unit amplitude. Measured
    # 6.5e-7 between the Release build that wrote it and the Debug build: the inverse iteration stops
    # when its Rayleigh quotient has settled to 1e-4, not the vector, so the round-off of another
    # evaluation order shows in the mode's last digits well above the table's 13.
    fresh = run(args.uniarc, args.modes_deck, os.path.join(args.out, 'perfect')) + '.modes'
    names, committed = read_rows(args.modes)
    _, written = read_rows(fresh)
    columns = [names.index(c) for c in ('ux', 'uy')]
    if len(committed) != len(written):
        failures.append(f'{args.modes} has {len(committed)} rows, the program writes {len(written)}')
    else:
        worst = max(abs(float(a[c]) - float(b[c])) for a, b in zip(committed, written) for c in columns)
        if worst > 1e-5:
            failures.append(f'{args.modes} differs from the mode the program writes by {worst}')
    _, perfect_crit = read_rows(os.path.join(args.out, 'perfect', os.path.splitext(
        os.path.basename(args.modes_deck))[0] + '.crit'))
    lam_c = float(next(row[2] for row in perfect_crit if row[0] == 'bifurcation'))

    limits = []
    for amplitude in ('1e-2', '1e-3', '1e-4'):
        base = run(args.uniarc, args.deck, os.path.join(args.out, 'a' + amplitude), ['amplitude=' + amplitude])
        names, crit = read_rows(base + '.crit')
        kinds = [row[0] for row in crit]
        if any('bifurcation' in kind for kind in kinds):
            failures.append(f'amplitude {amplitude}: a bifurcation row on the imperfect path')
        if 'limit_max' not in kinds:
            failures.append(f'amplitude {amplitude}: no limit point')
            continue
        row = dict(zip(names, crit[kinds.index('limit_max')]))
        lam = float(row['lambda'])
        if not lam < lam_c:
            failures.append(f'amplitude {amplitude}: limit {lam} not below the bifurcation {lam_c}')
        # The asymmetric path: the crown has moved sideways at the limit (more than 1e-3 of the rise,
        # 1.519: the symmetric path has none).
        if not abs(float(row['u_crown'])) > 1.5e-3:
            failures.append(f'amplitude {amplitude}: crown sideways only {row["u_crown"]} at the limit')
        limits.append(lam)
        # The mode computed in a first run of the program itself (*IMPERFECTION without FILE=) is the
        # one of the table: the same limit load. Measured equal to all 13 digits in one build; across
        # builds the mode differs by 6.5e-7 (above), which moves the limit far less than 1e-6.
        computed = run(args.uniarc, args.computed_deck, os.path.join(args.out, 'c' + amplitude),
                       ['amplitude=' + amplitude])
        names_c, crit_c = read_rows(computed + '.crit')
        lam_computed = next((float(r[names_c.index('lambda')]) for r in crit_c if r[0] == 'limit_max'), None)
        if lam_computed is None or abs(lam_computed - lam) > 1e-6 * lam:
            failures.append(f'amplitude {amplitude}: the computed mode gives the limit {lam_computed}, '
                            f'the table\'s {lam}')
        print(f'amplitude {amplitude}: limit_max {lam:.6f}, {lam_c - lam:.6f} below the bifurcation '
              f'{lam_c:.6f}, u_crown {float(row["u_crown"]):.4e}')
    if len(limits) == 3:
        if not limits[0] < limits[1] < limits[2]:
            failures.append(f'the limits {limits} do not rise towards {lam_c} as the amplitude falls')
        gaps = [lam_c - lam for lam in limits]
        # Measured 4.659 and 4.649 against 10^(2/3) = 4.642: the law is the leading term of an
        # expansion in a^(1/3); its next term is 0.4 % at a = 1e-2. 2 % allows it.
        for k in range(2):
            ratio = gaps[k] / gaps[k + 1]
            print(f'Koiter: gap ratio {ratio:.4f} (10^(2/3) = {10 ** (2 / 3):.4f})')
            if abs(ratio / 10 ** (2 / 3) - 1) > 2e-2:
                failures.append(f'gap ratio {ratio} is not 10^(2/3) to 2 %')
    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
