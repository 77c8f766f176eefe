#!/usr/bin/env python3
"""A long free-free beam on a tensionless Pasternak bed under a central point load: uniarc against the
closed-form solution of the infinite beam (docs/theory.md §3.10, "Closed form: the infinite beam on a
tensionless bed").

Usage (one CTest per call):
  pasternak_closed_form_check.py --uniarc BIN --deck DECK --out DIR --gp G [--gp G]...
                                 --meshes N_COARSE N_FINE [tolerances, below]

The deck must define L, n, EI, k, G, P (*PARAMETER; n and G are set with -D), have its bed below the
beam (DIRECTION=90), *OUTPUT, FORCES, and track w0 and w_end, the deflections under the load and at an
end (positive into the bed).

The closed form. In the contact zone |x| < a the beam and the bed's surface move together:
EI w'''' - G w'' + k w = 0. Outside, the beam carries nothing and is straight (M = V = 0 on a free
unloaded part), and the surface decays as w(a) exp(-(|x| - a)/l), l = sqrt(G/k). The matching
conditions at x = a (derived in docs/theory.md §3.10 from the gap and the sign of the reaction) are
w''(a) = w'''(a) = 0 and w'(a) = -w(a)/l (no concentrated reaction: the surface leaves the beam with
the beam's slope). With s = a - |x| and mu1, mu2 the roots with positive real part of
EI mu^4 - G mu^2 + k = 0,

    U(s) = [mu2^2 (l cosh mu1 s + sinh(mu1 s)/mu1) - mu1^2 (l cosh mu2 s + sinh(mu2 s)/mu2)] / (mu2^2 - mu1^2)

solves the beam's equation with U(0) = l, U'(0) = 1, U''(0) = U'''(0) = 0 (real for complex roots, and
G = 0 is Winkler's bed with l = 0). w = c U(a - |x|): a is the first positive root of U'(a) = 0
(w'(0) = 0), found here by bracketing on a grid of 1e-3/mu and scipy's brentq; the shear at the load,
2 EI w'''(0+) = P, gives c = -P/(2 EI U'''(a)); then w0 = c U(a), w(a) = c l, w'(a) = -c. a does not
depend on P. The closed form is checked against itself before it is used: the pressure
k w - G w'' >= 0 over the contact, w(a) >= 0, and with G = 0 Winkler's a = pi/(2 beta) and
w0 = P beta coth(pi/2)/(2k) to 1e-12.

The beam of the deck is finite with free ends, and its bed goes on past both ends (docs/theory.md
§3.10: the end spring sqrt(k G) is the exact semi-infinite bed): as its straight parts carry nothing,
the infinite beam's solution is this beam's exact solution as long as L/2 > a.

Checks, on the finer mesh (h = L/n) unless said; the tolerances are given by the caller
(tests/regression/CMakeLists.txt, where each is justified by the errors measured on its meshes):
- w0 within --w0-rtol of the closed form (uniarc's error falls as h^2);
- the Richardson value w0 + (w0 - w0_coarse)/3 within --richardson-rtol (both meshes' errors O(h^2);
  the contact edge sits on a node, which adds an error that is not smooth in h);
- the contact half-length (s_contact_2 - s_contact_1)/2 within one element h of a (the discrete edges
  are nodes), in one contact region;
- w_end within --end-rtol (it carries the slope at the edge over L/2 - a);
- the beam's deflection at every node within --shape-atol of the closed form, relative to the largest
  |w| of the beam;
- the bed's surface beyond the contact, from STEM.contact (gap = uy + w_b for the bed below), within
  --surface-atol * w0 of w(a) exp(-(|x| - a)/l) (0 for G = 0);
- no concentrated reaction at the contact edge: each outermost contact node's reaction at most
  --edge-factor (default 1.1) times its tributary length times the closed form's largest pressure
  within one element of the edge, max(k w(a), p(|x_edge| - h)) (the pressure grows inward by |p'| h,
  3 % of k w(a) per element at h = 0.02 on G = 2, hence 10 %); a concentrated force F at the edge
  would be a reaction F whatever h, so the check fails as h -> 0.
Exit 1 on any failure.
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy.optimize import brentq

from pasternak_check import deck_parameters
from uniarc_check import read_table, run_uniarc


class ClosedForm:
    """The infinite beam on a tensionless Pasternak bed under P at x = 0 (module docstring)."""

    def __init__(self, EI, k, G, P):
        self.EI, self.k, self.G, self.P = EI, k, G, P
        self.ell = math.sqrt(G / k)
        roots = np.roots([EI, 0.0, -G, 0.0, k]).astype(complex)
        roots = sorted((r for r in roots if r.real > 0), key=lambda r: (r.imag, r.real))
        if len(roots) != 2 or abs(roots[0] - roots[1]) < 1e-6 * abs(roots[0]):
            raise SystemExit(f'FAIL: G = {G}: the roots mu1, mu2 {roots} must be distinct '
                             '(G^2 = 4 EI k is the double root, not handled here)')
        self.mu1, self.mu2 = roots
        s = 1e-3 / abs(self.mu1)
        grid = np.arange(s, 50.0 / abs(self.mu1), s)
        values = self.derivative(grid, 1)
        change = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))
        if len(change) == 0:
            raise SystemExit(f'FAIL: G = {G}: U\'(a) has no root: no lift-off')
        i = change[0]
        self.a = brentq(lambda x: self.derivative(x, 1), grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15)
        self.c = -P / (2 * EI * self.derivative(self.a, 3))
        self.w0 = self.c * self.derivative(self.a, 0)

    def derivative(self, s, order):
        """d^order U / ds^order at s (real)."""
        m1, m2, ell = self.mu1, self.mu2, self.ell
        s = np.asarray(s, dtype=float)

        def part(m):   # (l cosh m s + sinh(m s)/m) differentiated `order` times
            even = np.cosh(m * s) if order % 2 == 0 else np.sinh(m * s)
            odd = np.sinh(m * s) if order % 2 == 0 else np.cosh(m * s)
            return m**order * (ell * even + odd / m)

        value = (m2**2 * part(m1) - m1**2 * part(m2)) / (m2**2 - m1**2)
        return value.real

    def w(self, x):
        """The beam's deflection (into the bed) at x (any real)."""
        x = np.abs(np.asarray(x, dtype=float))
        inside = self.c * self.derivative(np.clip(self.a - x, 0.0, None), 0)
        outside = self.c * self.ell - self.c * (x - self.a)
        return np.where(x <= self.a, inside, outside)

    def pressure(self, x):
        """k w - G w'' in the contact (w(x) = c U(a - |x|), so w'' = c U'')."""
        s = self.a - np.abs(np.asarray(x, dtype=float))
        return self.k * self.c * self.derivative(s, 0) - self.G * self.c * self.derivative(s, 2)

    def surface(self, x):
        """The bed's surface beyond the contact, w(a) exp(-(|x| - a)/l); 0 on Winkler's bed."""
        x = np.abs(np.asarray(x, dtype=float))
        if self.ell == 0:
            return np.zeros_like(x)
        return self.c * self.ell * np.exp(-(x - self.a) / self.ell)


def read_contact(path):
    """STEM.contact's column names and rows, its word column `medium` dropped (read_table reads
    numbers only)."""
    with open(path) as handle:
        lines = [line.split() for line in handle.read().splitlines() if line and not line.startswith('#')]
    names = lines[0]
    drop = names.index('medium')
    keep = [i for i in range(len(names)) if i != drop]
    return [names[i] for i in keep], [[float(row[i]) for i in keep] for row in lines[1:]]


def self_check(cf):
    """The closed form's own conditions (module docstring); problems as text."""
    problems = []
    x = np.linspace(0.0, cf.a, 2001)
    p = cf.pressure(x)
    if p.min() < -1e-12 * abs(p).max():
        problems.append(f'closed form G = {cf.G}: negative pressure {p.min()} in the contact')
    if cf.c * cf.ell < 0 or cf.c <= 0:
        problems.append(f'closed form G = {cf.G}: w(a) = {cf.c * cf.ell} < 0 or slope >= 0')
    if cf.G == 0:
        beta = (cf.k / (4 * cf.EI)) ** 0.25
        a_w = math.pi / (2 * beta)
        w0_w = cf.P * beta / (2 * cf.k) / math.tanh(math.pi / 2)
        print(f'closed form G = 0 against Winkler: a {cf.a!r} vs pi/(2 beta) {a_w!r}; '
              f'w0 {cf.w0!r} vs P beta coth(pi/2)/(2k) {w0_w!r}')
        if abs(cf.a - a_w) > 1e-12 * a_w or abs(cf.w0 - w0_w) > 1e-12 * w0_w:
            problems.append('closed form G = 0 is not Winkler\'s')
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--gp', action='append', type=float, required=True)
    parser.add_argument('--meshes', type=int, nargs=2, required=True)
    parser.add_argument('--w0-rtol', type=float, required=True)
    parser.add_argument('--richardson-rtol', type=float, required=True)
    parser.add_argument('--end-rtol', type=float, required=True)
    parser.add_argument('--shape-atol', type=float, required=True)
    parser.add_argument('--surface-atol', type=float, required=True)
    parser.add_argument('--edge-factor', type=float, default=1.1)
    args = parser.parse_args()
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    params = deck_parameters(args.deck)
    L, EI, k, P = params['L'], params['EI'], params['k'], params['P']
    problems = []
    for G in args.gp:
        cf = ClosedForm(EI, k, G, P)
        problems += self_check(cf)
        print(f'G = {G}: closed form a = {cf.a!r}, w0 = {cf.w0!r}, w(a) = {cf.c * cf.ell!r}, '
              f'w\'(a) = {-cf.c!r}, w_end = {float(cf.w(L / 2))!r}')
        if not cf.a < L / 2:
            problems.append(f'G = {G}: the contact {cf.a} reaches the beam\'s ends')
            continue
        results = {}
        for n in args.meshes:
            out = os.path.join(args.out, f'G{G!r}_n{n}')
            command, run = run_uniarc(args.uniarc, args.deck, out, [f'G={G!r}', f'n={n}'])
            if run.returncode != 0:
                raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
            names, rows = read_table(os.path.join(out, stem + '.path'))
            results[n] = (dict(zip(names, rows[-1])), out)
        (coarse, _), (fine, out) = results[args.meshes[0]], results[args.meshes[1]]
        n = args.meshes[1]
        h = L / n

        def compare(label, got, want, tol, scale):
            error = abs(got - want) / scale
            print(f'G = {G}, n = {n}: {label} {got!r} vs closed form {want!r} '
                  f'(error {error:.3g}, allowed {tol:.3g})')
            if not error <= tol:
                problems.append(f'{label} at G = {G}')

        def largest(label, error, tol, scale):
            print(f'G = {G}, n = {n}: largest {label} {error!r} ({error / scale:.3g} of {scale!r}, '
                  f'allowed {tol:.3g})')
            if not error <= tol * scale:
                problems.append(f'{label} at G = {G}')

        compare('w0', fine['w0'], cf.w0, args.w0_rtol, abs(cf.w0))
        compare('w0 (Richardson)', fine['w0'] + (fine['w0'] - coarse['w0']) / 3, cf.w0,
                args.richardson_rtol, abs(cf.w0))
        compare('contact half-length', (fine['s_contact_2'] - fine['s_contact_1']) / 2, cf.a, 1.0, h)
        if fine['contact_regions'] != 1:
            problems.append(f'{fine["contact_regions"]} contact regions at G = {G}')
        compare('w_end', fine['w_end'], float(cf.w(L / 2)), args.end_rtol, abs(cf.w(L / 2)))
        shape_names, shape_rows = read_table(os.path.join(out, stem + '.shape'))
        shape = np.array(shape_rows)
        col = {name: i for i, name in enumerate(shape_names)}
        last = shape[shape[:, col['step']] == shape[:, col['step']].max()]
        x, uy = last[:, col['x0']], last[:, col['uy']]
        largest('deflection error over the nodes', np.abs(-uy - cf.w(x)).max(), args.shape_atol,
                np.abs(cf.w(x)).max())
        contact_names, contact_rows = read_contact(os.path.join(out, stem + '.contact'))
        contact = np.array(contact_rows)
        cc = {name: i for i, name in enumerate(contact_names)}
        contact = contact[contact[:, cc['step']] == contact[:, cc['step']].max()]
        nodes = contact[:, cc['node']].astype(int)
        uy_of = dict(zip(last[:, col['node']].astype(int), uy))
        x_of = dict(zip(last[:, col['node']].astype(int), x))
        xc = np.array([x_of[i] for i in nodes])
        reaction = contact[:, cc['reaction']]
        touching = reaction > 0
        lifted = ~touching
        surface = contact[lifted, cc['gap']] - np.array([uy_of[i] for i in nodes[lifted]])
        largest('surface error beyond the contact', np.abs(surface - cf.surface(xc[lifted])).max(),
                args.surface_atol, abs(cf.w0))
        edge = np.flatnonzero(touching)[[0, -1]]
        for i in edge:
            x_edge = min(abs(xc[i]), cf.a)
            bound = max(cf.k * cf.c * cf.ell, float(cf.pressure(max(x_edge - h, 0.0))))
            bound *= contact[i, cc['length']]
            print(f'G = {G}, n = {n}: edge node {nodes[i]} (x = {xc[i]!r}) reaction {reaction[i]!r}, '
                  f'bound {args.edge_factor} x {bound!r}')
            if not reaction[i] <= args.edge_factor * bound:
                problems.append(f'a concentrated reaction at the contact edge, node {nodes[i]}, G = {G}')
    if problems:
        print('FAIL: ' + '; '.join(problems))
        sys.exit(1)
    print('ok')


if __name__ == '__main__':
    main()
