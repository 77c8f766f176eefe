#!/usr/bin/env python3
"""Mesh convergence of the bending moment under a point load on a beam on a bonded Winkler bed
(Hetenyi 1946, Ch. II: M(0) = P/(4 beta), w(0) = P beta/(2k), beta = (k/4EI)^(1/4)).

Usage (one CTest per call):
  bed_forces_check.py --uniarc BIN --deck DECK --out DIR --meshes N1 N2 --moment M0 --deflection W0
                      --order P --order-tolerance T --rtol R

Runs DECK with -D n=N1 and -D n=N2 (N2 = 2 N1), reads the moment at the loaded node (M_end of the
element ending at the node of the path's track, the middle node `n/2 + 1`) from STEM.forces and w0 from
STEM.path, and checks for both M and w: the observed order log2(e1/e2) of the errors against the
closed form is P within T, and the Richardson value (e2 - (e1 - e2)/(2^P - 1) added to the closed
form) equals the closed form to R relative.
"""
import argparse
import math
import os
import subprocess
import sys

import numpy as np


def run(args, n):
    out = os.path.join(args.out, f'n{n}')
    os.makedirs(out, exist_ok=True)
    result = subprocess.run([args.uniarc, args.deck, '-o', out, '-q', '-D', f'n={n}'], capture_output=True,
                            text=True, check=False)
    if result.returncode != 0:
        raise SystemExit(f'uniarc -D n={n} exited with {result.returncode}: {result.stderr}')
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    forces = np.genfromtxt(os.path.join(out, stem + '.forces'), names=True, comments='#')
    path = np.atleast_1d(np.genfromtxt(os.path.join(out, stem + '.path'), names=True, comments='#'))
    middle = n // 2 + 1
    left = forces[forces['node_end'] == middle]
    right = forces[forces['node_start'] == middle]
    if len(left) != 1 or len(right) != 1:
        raise SystemExit(f'n={n}: no single element on each side of node {middle}')
    return float(left['M_end'][0]), float(right['M_start'][0]), float(path['w0'][-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--meshes', type=int, nargs=2, required=True)
    parser.add_argument('--moment', type=float, required=True)
    parser.add_argument('--deflection', type=float, required=True)
    parser.add_argument('--order', type=float, required=True)
    parser.add_argument('--order-tolerance', type=float, required=True)
    parser.add_argument('--rtol', type=float, required=True)
    args = parser.parse_args()
    coarse, fine = (run(args, n) for n in args.meshes)
    failures = []
    # the moment is continuous at the loaded node (the bed's shares of its two elements balance there)
    for n, (m_left, m_right, _) in zip(args.meshes, (coarse, fine)):
        if abs(m_left - m_right) > 1e-10 * abs(args.moment):
            failures.append(f'n={n}: M jumps at the loaded node: {m_left!r} | {m_right!r}')
    for name, exact, e1, e2 in (('M(0)', args.moment, coarse[0] - args.moment, fine[0] - args.moment),
                                ('w(0)', args.deflection, coarse[2] - args.deflection, fine[2] - args.deflection)):
        order = math.log2(abs(e1 / e2)) if e2 != 0.0 else float('inf')
        richardson = e2 - (e1 - e2) / (2.0 ** args.order - 1.0)
        print(f'{name}: errors {e1:.4e} (n={args.meshes[0]}), {e2:.4e} (n={args.meshes[1]}); observed order '
              f'{order:.3f}; Richardson value {exact + richardson:.12g} (closed form {exact!r})')
        if abs(order - args.order) > args.order_tolerance:
            failures.append(f'{name}: observed order {order:.3f}, expected {args.order} +- {args.order_tolerance}')
        if abs(richardson) > args.rtol * abs(exact):
            failures.append(f'{name}: Richardson value off the closed form by {abs(richardson) / abs(exact):.2e} '
                            f'relative, more than {args.rtol}')
    for failure in failures:
        print('FAIL: ' + failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
