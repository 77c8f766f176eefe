#!/usr/bin/env python3
"""A free-free beam on a tensionless Pasternak bed under a central point load: uniarc against an
independent finite-difference solution of the same problem (numpy).

Usage (one CTest per call):
  pasternak_check.py --uniarc BIN --deck DECK --out DIR [--gp G]... [--fd-nodes N]
                     [--w0-rtol R] [--compare-winkler]

The deck must define the parameters L, n, EI, k, G, P (the beam's length, its number of elements, its
bending stiffness, the bed's Winkler modulus and shear-layer stiffness, the load) and track w0 and
w_end, the deflections under the load and at an end (positive into the bed); uniarc is run once per --gp with -D G=value.

The reference is computed here from the continuum problem, with a discretisation of its own (not
uniarc's finite elements, nor its end condition of the bed):
- the beam: the finite-difference bending energy sum EI h/2 ((w[i-1] - 2 w[i] + w[i+1])/h^2)^2 over
  the interior nodes (free ends: no moment, no shear, as the natural conditions of that energy);
- the bed: the surface deflection d on a grid that runs on beyond both ends of the beam for 6
  characteristic lengths l = sqrt(G/k) with a free far end (the semi-infinite bed represented
  explicitly, not by an end stiffness), energy sum k/2 d^2 (trapezoidal weights) + G/2 (d')^2 h;
- contact: the gap d - w >= 0 at every node of the beam, the reaction >= 0, complementarity: the
  minimum of the energy under these bounds, found by the primal-dual active-set method (Hintermueller,
  Ito & Kunisch, SIAM J. Optim. 13, 2002) on the KKT system, solved densely.

The reference's w0 is extrapolated from --fd-nodes and half as many intervals (Richardson, both
errors O(h^2): measured on this beam at 100/200/400 intervals, the differences fall by 3.96 and 3.98 at
G = 0 and 2; the extrapolations from 100/200 and from 200/400 agree within 2e-6 relative).

Checks: uniarc's w0 against the reference's within --w0-rtol; the contact region's half-length
(s_contact_2 - s_contact_1)/2 from the path file against the reference's within one element of each
mesh (the contact edges are nodes in both); w_end within --end-rtol (the ends' uplift moves with the
contact edge, which both meshes resolve to a node: over n = 80, 160, 320 uniarc's w_end changes by 2.3e-3
and 6e-4 relative at G = 2, the reference's over 100, 200, 400 intervals by 3e-4 and 8e-5, and the two
differ by 6e-4 at n = 160, N = 200); and with --compare-winkler, that the first --gp (0: Winkler's bed)
has the longer contact (so the shorter separated ends) and the larger uplift of the ends than the
others, in uniarc and in the reference alike. Exit 1 on any failure.
"""
import argparse
import os
import sys

import numpy as np

from uniarc_check import read_table, run_uniarc


def reference(L, EI, k, G, P, n_beam, extension_lengths=6.0):
    """w0, the contact half-length and the deflection of the beam's end w_end of the FD model in the
    module docstring (n_beam intervals; deflections positive into the bed)."""
    h = L / n_beam
    ell = np.sqrt(G / k) if G > 0 else 0.0
    n_ext = int(np.ceil(extension_lengths * ell / h)) if G > 0 else 0
    n_w = n_beam + 1
    n_d = n_beam + 1 + 2 * n_ext
    size = n_w + n_d
    K = np.zeros((size, size))
    # beam bending: curvature at interior nodes, D w = second differences
    D = np.zeros((n_beam - 1, n_w))
    for i in range(1, n_beam):
        D[i - 1, i - 1:i + 2] = [1.0 / h**2, -2.0 / h**2, 1.0 / h**2]
    K[:n_w, :n_w] = EI * h * D.T @ D
    # bed: Winkler part, trapezoidal weights
    weights = np.full(n_d, h)
    weights[0] = weights[-1] = h / 2
    for j in range(n_d):
        K[n_w + j, n_w + j] += k * weights[j]
    # bed: shear layer
    for j in range(n_d - 1):
        a, b = n_w + j, n_w + j + 1
        K[a, a] += G / h
        K[b, b] += G / h
        K[a, b] -= G / h
        K[b, a] -= G / h
    f = np.zeros(size)
    f[n_beam // 2] = P
    # gap at beam node i: d[n_ext + i] - w[i]
    C = np.zeros((n_w, size))
    for i in range(n_w):
        C[i, i] = -1.0
        C[i, n_w + n_ext + i] = 1.0
    active = np.ones(n_w, dtype=bool)
    c = k * h
    for _ in range(200):
        idx = np.flatnonzero(active)
        m = len(idx)
        A = np.zeros((size + m, size + m))
        A[:size, :size] = K
        A[:size, size:] = -C[idx].T
        A[size:, :size] = C[idx]
        rhs = np.concatenate([f, np.zeros(m)])
        solution = np.linalg.solve(A, rhs)
        x = solution[:size]
        reaction = np.zeros(n_w)
        reaction[idx] = solution[size:]
        gap = C @ x
        new_active = reaction - c * gap > 0
        if np.array_equal(new_active, active):
            break
        active = new_active
    else:
        raise SystemExit('FAIL: the reference active-set iteration did not settle in 200 iterations')
    if reaction.min() < -1e-9 * P or gap.min() < -1e-9 * abs(x[n_beam // 2]):
        raise SystemExit('FAIL: the reference solution violates complementarity')
    nodes = np.flatnonzero(active)
    half_length = (nodes.max() - nodes.min()) * h / 2
    return x[n_beam // 2], half_length, x[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--gp', action='append', type=float, required=True)
    parser.add_argument('--fd-nodes', type=int, default=200)
    parser.add_argument('--w0-rtol', type=float, default=2e-4)
    parser.add_argument('--end-rtol', type=float, default=2e-3)
    parser.add_argument('--compare-winkler', action='store_true')
    args = parser.parse_args()
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    problems = []
    lengths = []
    for index, G in enumerate(args.gp):
        out = os.path.join(args.out, str(index))
        command, run = run_uniarc(args.uniarc, args.deck, out, [f'G={G!r}'])
        if run.returncode != 0:
            raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}')
        names, rows = read_table(os.path.join(out, stem + '.path'))
        last = dict(zip(names, rows[-1]))
        # the deck's parameters, as uniarc printed them in the path file's provenance is not needed:
        # they are read from the deck's *PARAMETER lines
        params = deck_parameters(args.deck)
        params['G'] = G
        L, n = params['L'], int(params['n'])
        w0_fine, a_ref, end_ref = reference(L, params['EI'], params['k'], G, params['P'], args.fd_nodes)
        w0_coarse, _, _ = reference(L, params['EI'], params['k'], G, params['P'], args.fd_nodes // 2)
        w0_ref = w0_fine + (w0_fine - w0_coarse) / 3
        w0 = last['w0']
        a = (last['s_contact_2'] - last['s_contact_1']) / 2
        a_tol = L / n + L / args.fd_nodes
        end = last['w_end']
        print(f'G = {G}: w0 {w0!r} vs reference {w0_ref!r} (relative {abs(w0 - w0_ref) / abs(w0_ref):.3g}, '
              f'allowed {args.w0_rtol}); contact half-length {a!r} vs {a_ref!r} (allowed {a_tol:.3g})')
        if not abs(w0 - w0_ref) <= args.w0_rtol * abs(w0_ref):
            problems.append(f'w0 at G = {G}')
        if not abs(a - a_ref) <= a_tol:
            problems.append(f'contact half-length at G = {G}')
        print(f'G = {G}: w_end {end!r} vs reference {end_ref!r} (relative {abs(end - end_ref) / abs(end_ref):.3g}, '
              f'allowed {args.end_rtol})')
        if not abs(end - end_ref) <= args.end_rtol * abs(end_ref):
            problems.append(f'w_end at G = {G}')
        lengths.append((a, a_ref, end, end_ref))
    if args.compare_winkler:
        for (a, a_ref, end, end_ref), G in zip(lengths[1:], args.gp[1:]):
            print(f'contact half-length G = {args.gp[0]}: {lengths[0][0]!r} (reference {lengths[0][1]!r}); '
                  f'G = {G}: {a!r} (reference {a_ref!r})')
            if not (a < lengths[0][0] and a_ref < lengths[0][1]):
                problems.append(f'contact at G = {G} not shorter than at G = {args.gp[0]}')
            print(f'uplift of the ends G = {args.gp[0]}: {-lengths[0][2]!r} (reference {-lengths[0][3]!r}); '
                  f'G = {G}: {-end!r} (reference {-end_ref!r})')
            if not (0 < -end < -lengths[0][2] and 0 < -end_ref < -lengths[0][3]):
                problems.append(f'the ends at G = {G} not lifted less than at G = {args.gp[0]}')
    if problems:
        print('FAIL: ' + '; '.join(problems))
        sys.exit(1)
    print('ok')


def deck_parameters(deck):
    """NAME = number lines of the deck's *PARAMETER card (plain numbers only)."""
    values = {}
    inside = False
    with open(deck) as f:
        for line in f:
            text = line.strip()
            if text.startswith('**'):
                continue
            if text.startswith('*'):
                inside = text.upper().startswith('*PARAMETER')
                continue
            if inside and '=' in text:
                name, value = (part.strip() for part in text.split('=', 1))
                try:
                    values[name] = float(value)
                except ValueError:
                    pass
    return values


if __name__ == '__main__':
    main()
