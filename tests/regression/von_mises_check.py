#!/usr/bin/env python3
"""Von Mises truss (two corotational bars, apex load) against its closed form.

Runs tests/regression/decks/von_mises_truss.inp with the half span a, rise h and axial stiffness EA
given here (passed to the deck with -D, so that deck and closed form cannot disagree) and checks:

- every converged point (w, lambda) of the path lies on the closed form P(w): docs/theory.md §1.8,
  equilibrium of the deformed apex,
      P(w) = 2 EA (L0 - L)/L0 * (h - w)/L,   L = sqrt(a^2 + (h - w)^2),   L0 = sqrt(a^2 + h^2);
  the corotational truss is exact for this problem (no discretisation), and the y-component of the
  residual at the apex is exactly lambda - P(w), which Newton's test bounds by
  force_tolerance * max(|lambda R|, first increment * |R|) (docs/theory.md §2.1, force_tolerance =
  1e-8, |R| = 1). Tolerance: 1e-8 * max(|lambda|, P_lim), P_lim >= the first increment;
- the limit loads (STEM.crit): exactly one limit_max and one limit_min, no bifurcation (the symmetric
  two-bar truss has no other critical point while it is shallow), lambda = +P_lim and -P_lim with
      L_lim^3 = a^2 L0,   y_lim = sqrt(L_lim^2 - a^2),   P_lim = 2 EA y_lim (1/L_lim - 1/L0),
  at w = h - y_lim and h + y_lim. A limit point is placed between two converged steps by the cubic
  Hermite interpolant of lambda(s) (docs/theory.md §2.2), an O(ds^4) error: 7e-9 of P_lim with this
  deck's steps, while the nearest converged steps are 7e-4 and 4e-5 of P_lim below it; tolerance 1e-6
  of P_lim. w at a flat extremum is fixed to about the square root of that (7e-8 of h measured):
  tolerance 1e-5 of h;
- stability: no negative pivot of the tangent before the first limit point or after the second, one
  between them (the snap-through branch is unstable under load control);
- the path goes past the inverted position w = 2h to the deck's stop, w/h = 2.5.
"""
import argparse
import math
import sys

from uniarc_check import read_table, read_events, run_uniarc


def closed_form(a, h, ea):
    """The load P(w) and the limit point (P_lim, w of the maximum, w of the minimum)."""
    initial_length = math.hypot(a, h)

    def load(w):
        length = math.hypot(a, h - w)
        return 2.0 * ea * (initial_length - length) / initial_length * (h - w) / length

    limit_length = (a * a * initial_length) ** (1.0 / 3.0)
    limit_rise = math.sqrt(limit_length ** 2 - a * a)
    limit_load = 2.0 * ea * limit_rise * (1.0 / limit_length - 1.0 / initial_length)
    return load, limit_load, h - limit_rise, h + limit_rise


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--half-span', type=float, default=1.0)
    parser.add_argument('--rise', type=float, default=0.1)
    parser.add_argument('--ea', type=float, default=1.0e4)
    args = parser.parse_args()
    a, h, ea = args.half_span, args.rise, args.ea
    load, limit_load, w_max, w_min = closed_form(a, h, ea)

    _, run = run_uniarc(args.uniarc, args.deck, args.out, [f'a={a!r}', f'h={h!r}', f'EA={ea!r}'])
    if run.returncode != 0:
        print(f'FAIL: uniarc exited with {run.returncode}')
        return 1
    stem = args.deck.replace('\\', '/').split('/')[-1].rsplit('.', 1)[0]
    names, rows = read_table(f'{args.out}/{stem}.path')
    lam, w, neg = (names.index(column) for column in ('lambda', 'w', 'neg_pivots'))
    problems = []

    worst = 0.0
    for row in rows:
        error = abs(row[lam] - load(row[w])) / max(abs(row[lam]), limit_load)
        worst = max(worst, error)
        if error > 1e-8:
            problems.append(f'step {row[0]:.0f}: lambda = {row[lam]!r}, closed form P(w = {row[w]!r}) = '
                            f'{load(row[w])!r} (relative error {error:.2e} > 1e-8)')
        expected_negative = 1 if w_max < row[w] < w_min else 0
        if row[neg] != expected_negative:
            problems.append(f'step {row[0]:.0f}: w = {row[w]!r}, {row[neg]:.0f} negative pivots, '
                            f'expected {expected_negative}')
    print(f'{len(rows)} points, worst relative distance to the closed form {worst:.2e}')
    if max(row[w] for row in rows) < 2.5 * h * (1.0 - 1e-12):
        problems.append(f'the path stops at w = {max(row[w] for row in rows)!r}, before 2.5 h')

    crit_names, events = read_events(f'{args.out}/{stem}.crit')
    kinds = [kind for kind, _ in events]
    if kinds != ['limit_max', 'limit_min']:
        problems.append(f'critical points {kinds}, expected [limit_max, limit_min]')
    else:
        for (kind, numbers), expected_load, expected_w in zip(events, (limit_load, -limit_load), (w_max, w_min)):
            got_load = numbers[crit_names.index('lambda')]
            got_w = numbers[crit_names.index('w')]
            print(f'{kind}: lambda = {got_load!r} (closed form {expected_load!r}, '
                  f'{abs(got_load - expected_load) / limit_load:.1e}), w = {got_w!r} '
                  f'(closed form {expected_w!r}, {abs(got_w - expected_w) / h:.1e} of h)')
            if abs(got_load - expected_load) > 1e-6 * limit_load:
                problems.append(f'{kind}: lambda = {got_load!r}, closed form {expected_load!r} (1e-6)')
            if abs(got_w - expected_w) > 1e-5 * h:
                problems.append(f'{kind}: w = {got_w!r}, closed form {expected_w!r} (1e-5 h)')

    for problem in problems:
        print('FAIL: ' + problem)
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
