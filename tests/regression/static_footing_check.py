#!/usr/bin/env python3
"""A rigid footing on a tensionless Winkler or Pasternak bed under *STATIC (issue 16: the static contact
LCP with a Pasternak bed, the equilibrium of a nearly rigid floating member), against closed forms.

Usage: static_footing_check.py --uniarc BIN --deck DECK --out DIR --case G:e [--case G:e]...

For each case (shear layer G_p = G, eccentricity e) the deck (decks/static_stiff_footing.inp: a footing
of length L, EI = 1e6, on a bed of modulus k that goes on beyond both ends, a load P at e) is run with
-D G=... -D e=... and its single row is checked:

- equilibrium of the whole footing (the fault: a stiff floating beam balanced 0.998 of its load): the
  bed's reactions (STEM.contact) sum to P and their moment about the middle to P e, to 1e-9 relative
  (round-off of a refined solve is about 1e-14; the unrefined solve left 1e-5 here);
- the settlements w(x) of every node (STEM.shape, -uy) against the rigid footing w0 + theta x in contact.
  The bed is lumped to the nodes (tributary lengths h, h/2 at the ends), so the closed forms take the
  lumped sums: sum l_i = L and sum l_i x_i^2 = L^3/12 + L h^2/6 (the trapezoidal rule of x^2, exact
  with its error term). With the whole footing in contact:
    Winkler (G = 0):  w0 = P/(k L),                 theta = P e / (k I),  I = L^3/12 + L h^2/6
    Pasternak:        w0 = P/(k L + 2 sqrt(k G)),   theta = P e / (k I + sqrt(k G) L^2/2 + G L)
  (derivation in docs/theory.md §3.6: beyond each end the bed's surface decays as exp(-|x|/l),
  l = sqrt(G/k), and its shear layer pulls the footing's end with sqrt(k G) w(end) -/+ G theta; the
  discrete bed's end spring sqrt(k G) and its shear terms G/h (d_i - d_j) reproduce these exactly for a
  linear w, so the lumped formulas are exact for the model). The footing's own flexibility
  (k L^4/EI = 1.6e-5) is the difference: rtol 1e-6 of the largest settlement (measured 5e-8 to 4.4e-7).
- Winkler with lift-off (e > L/6): the rigid footing on the lumped tensionless springs, solved here by
  an active-set loop over the nodes (an independent solution of the same discrete model, rtol 1e-6 as
  above), and the continuous closed form: contact length 3 (L/2 - e), largest settlement
  2 P / (3 k (L/2 - e)), within the lumping (one node spacing h of the contact length; w_max to 2 h/c).
- Pasternak with lift-off: the same active-set loop on the discrete Pasternak bed (its tridiagonal
  stiffness with the end springs, docs/theory.md §3.10), the bed's surface free where it leaves the
  footing; rtol 1e-6.
"""
import argparse
import math
import shutil
import subprocess
import sys

import numpy as np


def table(path):
    return np.genfromtxt(path, names=True, dtype=None, encoding=None, comments='#')


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def rigid_footing(x, lengths, k, g, p, e):
    """The rigid footing w = w0 + theta x on the discrete tensionless bed (lumped springs k l_i, shear
    layer G/h between neighbours, end springs sqrt(k G)) by an active set: unknowns w0, theta and the
    surface deflections d; a node in contact has d_i = w0 + theta x_i, a free one r_i = 0."""
    n = len(x)
    bed = np.diag(k*lengths)
    for i in range(n - 1):
        h = x[i + 1] - x[i]
        if g > 0:
            bed[i, i] += g/h
            bed[i + 1, i + 1] += g/h
            bed[i, i + 1] -= g/h
            bed[i + 1, i] -= g/h
    bed[0, 0] += math.sqrt(k*g)
    bed[-1, -1] += math.sqrt(k*g)
    contact = np.ones(n, dtype=bool)
    for _ in range(4*n):
        # unknowns: d (n), w0, theta, r (n); rows: bed equilibrium K d = r, contact/free, footing P and P e
        size = 2*n + 2
        a = np.zeros((size, size))
        b = np.zeros(size)
        a[:n, :n] = bed
        a[:n, n + 2:] = -np.eye(n)
        for i in range(n):
            row = n + i
            if contact[i]:
                a[row, i] = 1.0
                a[row, n] = -1.0
                a[row, n + 1] = -x[i]
            else:
                a[row, n + 2 + i] = 1.0
        a[2*n, n + 2:] = 1.0
        b[2*n] = p
        a[2*n + 1, n + 2:] = x
        b[2*n + 1] = p*e
        solution = np.linalg.solve(a, b)
        d, w0, theta, r = solution[:n], solution[n], solution[n + 1], solution[n + 2:]
        gap = d - (w0 + theta*x)
        new = contact.copy()
        new[contact & (r < 0)] = False
        new[~contact & (gap < 0)] = True
        if (new == contact).all():
            return w0, theta, contact
        if (new & contact).sum() == contact.sum() and new.sum() > contact.sum():
            contact = new
        else:
            # drop the most negative reaction first, then admit the worst penetration
            if (contact & (r < 0)).any():
                i = np.argmin(np.where(contact, r, np.inf))
                contact[i] = False
            else:
                i = np.argmin(np.where(~contact, gap, np.inf))
                contact[i] = True
    fail('the active-set loop of the reference did not settle')


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--case', action='append', required=True)
    args = parser.parse_args()
    length, k, p = 2.0, 1.0, 1e-4
    for case in args.case:
        g, e = (float(v) for v in case.split(':'))
        out = f'{args.out}/G{g}_e{e}'
        shutil.rmtree(out, ignore_errors=True)
        finished = subprocess.run([args.uniarc, args.deck, '-o', out, '-q', '-D', f'G={g}', '-D', f'e={e}'],
                                  capture_output=True, text=True)
        sys.stdout.write(finished.stdout)
        sys.stderr.write(finished.stderr)
        if finished.returncode != 0:
            fail(f'G = {g}, e = {e}: exit code {finished.returncode}')
        stem = out + '/static_stiff_footing'
        contact = table(stem + '.contact')
        shape = table(stem + '.shape')
        x = np.asarray(shape['x0'], dtype=float)
        w = -np.asarray(shape['uy'], dtype=float)
        r = np.asarray(contact['reaction'], dtype=float)
        xc = np.asarray(contact['s'], dtype=float) - length/2
        lengths = np.asarray(contact['length'], dtype=float)
        force_error = abs(r.sum() - p)/p
        moment_error = abs((r*xc).sum() - p*e)/(p*length)
        print(f'G = {g}, e = {e}: sum of bed reactions / P - 1 = {force_error:.3e}, moment error {moment_error:.3e}')
        if force_error > 1e-9 or moment_error > 1e-9:
            fail(f'G = {g}, e = {e}: the bed reactions do not balance the load (force {force_error:.3e}, '
                 f'moment {moment_error:.3e}; 1e-9 accepted)')
        w0, theta, in_contact = rigid_footing(xc, lengths, k, g, p, e)
        h = length/(len(x) - 1)
        inertia = length**3/12 + length*h**2/6
        if in_contact.all():
            # the closed forms of the whole footing in contact (module docstring)
            closed_w0 = p/(k*length + 2*math.sqrt(k*g))
            closed_theta = p*e/(k*inertia + math.sqrt(k*g)*length**2/2 + g*length)
            if abs(closed_w0 - w0) > 1e-12*w0 or abs(closed_theta - theta) > 1e-10*max(abs(theta), w0):
                fail(f'G = {g}, e = {e}: the reference solution ({w0}, {theta}) is not the closed form '
                     f'({closed_w0}, {closed_theta})')
            print(f'  closed form: w0 = {closed_w0:.12e}, theta = {closed_theta:.12e}')
        expected = w0 + theta*x
        error = np.max(np.abs(w - expected))/np.max(np.abs(expected))
        print(f'  rigid footing: w0 = {w0:.12e}, theta = {theta:.12e}, {in_contact.sum()} of {len(x)} nodes '
              f'in contact; largest settlement error {error:.3e}')
        if error > 1e-6:
            fail(f'G = {g}, e = {e}: the settlements differ from the rigid footing by {error:.3e} (1e-6 accepted)')
        touching = r > 0
        if (touching != in_contact).any():
            fail(f'G = {g}, e = {e}: contact at nodes {np.flatnonzero(touching)}, the rigid footing has '
                 f'{np.flatnonzero(in_contact)}')
        if g == 0 and e > length/6:
            # the continuous rigid footing: triangular pressure over 3 (L/2 - e)
            c = 3*(length/2 - e)
            w_max = 2*p/(3*k*(length/2 - e))
            c_model = length/2 - (-w0/theta)
            print(f'  continuous: contact length {c:.6f} (model {c_model:.6f}), w_max {w_max:.6e} (model {w.max():.6e})')
            if abs(c_model - c) > h or abs(w.max() - w_max) > 2*h/c*w_max:
                fail(f'G = 0, e = {e}: the lift-off differs from the continuous closed form beyond the lumping')
    print('PASS')


if __name__ == '__main__':
    main()
