#!/usr/bin/env python3
"""A free-free beam on a tensionless Winkler bed under its weight and a point load at its middle:
the closed form with lift-off, against uniarc's *STATIC (issue 13).

Usage (one CTest per call):
  tensionless_bed_check.py --uniarc BIN --deck DECK --out DIR --L 8 --EI 1 --k 4 --q 0.02 --P 1
                           --rtol-w0 R --rtol-end R [--define NAME=VALUE]...

The deck must track w0 (the middle's deflection, downward positive) and w_end (an end's). With w
downward positive and x from the middle (half length H = L/2; the load P/2 on each half), the beam
rests on the bed on 0 <= x <= a and is lifted beyond:

  in contact:  EI w'''' + k w = q,  w = q/k + e^{bx}(C1 cos bx + C2 sin bx) + e^{-bx}(C3 cos bx + C4 sin bx),
               b = (k / 4EI)^(1/4)   (Hetényi 1946, *Beams on Elastic Foundation*, §2: the bonded bed)
  lifted:      EI w'''' = q,        w = D0 + D1 x + D2 x^2 + D3 x^3 + q x^4 / (24 EI)

with w'(0) = 0 and EI w'''(0+) = P/2 (symmetry, the half load), w, w', w'', w''' continuous at x = a,
and a free end w''(H) = w'''(H) = 0: eight linear equations for C1..C4, D0..D3 at a given a. The
edge of contact is where the bed's reaction k w vanishes: a solves w(a) = 0 (scipy brentq on a
bracket where w(a) changes sign). The solution is admissible when w >= 0 on [0, a] (the bed pushes)
and w <= 0 on [a, H] (the beam above the bed's surface), checked on a fine grid. When the bonded
solution (a = H) is admissible there is no lift-off and that is the answer.
"""
import argparse
import os
import sys

import numpy as np
from scipy.optimize import brentq

from uniarc_check import read_table, run_uniarc


class Beam:
    def __init__(self, L, EI, k, q, P):
        self.H, self.EI, self.k, self.q, self.P = L / 2.0, EI, k, q, P
        self.b = (k / (4.0 * EI)) ** 0.25

    def contact_basis(self, x):
        """(4 derivative orders, 4 functions) of the homogeneous solutions of the bedded part."""
        table = np.zeros((4, 4))
        for j, sign in enumerate((1.0, -1.0)):
            z = self.b * complex(sign, 1.0)
            for m in range(4):
                value = z ** m * np.exp(z * x)
                table[m, 2 * j] = value.real        # e^{sign bx} cos bx
                table[m, 2 * j + 1] = value.imag    # e^{sign bx} sin bx
        return table

    def contact_particular(self, x):
        return np.array([self.q / self.k, 0.0, 0.0, 0.0])

    @staticmethod
    def free_basis(x):
        return np.array([[1.0, x, x ** 2, x ** 3], [0.0, 1.0, 2 * x, 3 * x ** 2], [0.0, 0.0, 2.0, 6 * x],
                         [0.0, 0.0, 0.0, 6.0]])

    def free_particular(self, x):
        c = self.q / self.EI
        return np.array([c * x ** 4 / 24, c * x ** 3 / 6, c * x ** 2 / 2, c * x])

    def coefficients(self, a):
        """C1..C4, D0..D3 for the edge of contact at a (a = H: the bonded beam, D unused)."""
        A = np.zeros((8, 8))
        rhs = np.zeros(8)
        at_mid = self.contact_basis(0.0)
        A[0, :4] = at_mid[1]
        rhs[0] = -self.contact_particular(0.0)[1]
        A[1, :4] = self.EI * at_mid[3]
        rhs[1] = self.P / 2 - self.EI * self.contact_particular(0.0)[3]
        edge_c, edge_f = self.contact_basis(a), self.free_basis(a)
        for m in range(4):
            A[2 + m, :4] = edge_c[m]
            A[2 + m, 4:] = -edge_f[m]
            rhs[2 + m] = self.free_particular(a)[m] - self.contact_particular(a)[m]
        end = self.free_basis(self.H)
        for row, m in ((6, 2), (7, 3)):
            A[row, 4:] = end[m]
            rhs[row] = -self.free_particular(self.H)[m]
        return np.linalg.solve(A, rhs)

    def deflection(self, a, x, c=None):
        c = self.coefficients(a) if c is None else c
        if x <= a:
            return float(self.contact_basis(x)[0] @ c[:4] + self.contact_particular(x)[0])
        return float(self.free_basis(x)[0] @ c[4:] + self.free_particular(x)[0])

    def admissible(self, a):
        c = self.coefficients(a)
        xs = np.linspace(0.0, self.H, 4001)
        w = np.array([self.deflection(a, x, c) for x in xs])
        scale = np.max(np.abs(w))
        return bool(np.all(w[xs <= a] >= -1e-12 * scale) and np.all(w[xs > a] <= 1e-12 * scale))

    def solve(self):
        """(a, w0, w_end) of the admissible solution."""
        if self.admissible(self.H):
            return self.H, self.deflection(self.H, 0.0), self.deflection(self.H, self.H)
        grid = np.linspace(1e-3 * self.H, self.H * (1 - 1e-9), 800)
        values = [self.deflection(a, a) for a in grid]
        for i in range(len(grid) - 1):
            if values[i] * values[i + 1] < 0:
                a = brentq(lambda s: self.deflection(s, s), grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15)
                if self.admissible(a):
                    return a, self.deflection(a, 0.0), self.deflection(a, self.H)
        raise SystemExit('FAIL: no admissible edge of contact found')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name in ('uniarc', 'deck', 'out'):
        parser.add_argument('--' + name)
    for name in ('L', 'EI', 'k', 'q', 'P', 'rtol-w0', 'rtol-end'):
        parser.add_argument('--' + name, type=float, required=True)
    parser.add_argument('--define', action='append', default=[])
    args = parser.parse_args()
    a, w0, w_end = Beam(args.L, args.EI, args.k, args.q, args.P).solve()
    print(f'closed form: lift-off at a = {a:.9f} from the middle, w0 = {w0:.12g}, w_end = {w_end:.12g}')
    if not args.uniarc:
        return 0
    command, run = run_uniarc(args.uniarc, args.deck, args.out, args.define)
    if run.returncode != 0:
        raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    names, rows = read_table(os.path.join(args.out, stem + '.path'))
    row = dict(zip(names, rows[-1]))
    problems = []
    for name, exact, rtol in (('w0', w0, args.rtol_w0), ('w_end', w_end, args.rtol_end)):
        error = abs(row[name] - exact) / abs(exact)
        print(f'{name}: uniarc {row[name]!r}, closed form {exact!r}, relative error {error:.3g} (allowed {rtol})')
        if not error <= rtol:
            problems.append(name)
    if problems:
        print('FAIL: ' + ', '.join(problems))
        return 1
    print('ok')
    return 0


if __name__ == '__main__':
    sys.exit(main())
