#!/usr/bin/env python3
"""Independent reference for the first step of a long cantilever on a tensionless Winkler bed.

The model of the deck that exhausted Lemke's pivot cap (docs/benchmarks.md §11): a cantilever
EA = 1e4, EI = 1, length L, n elements, clamped at x = 0, on a tensionless Winkler bed of modulus
k = 1 below it (SIDE=RIGHT of a line along +x), tip load F_y = -P with P = 1e-4 (the first step of
CONTROL=LOAD, increment 1e-4, from the unloaded state, where the problem is linear).

The same discrete problem is built here from textbook pieces, not from uniarc's code:
- Euler-Bernoulli frame elements (axial EA/h, cubic Hermite bending), 3 DOFs per node;
- the bed lumped to the nodes as uniarc documents it (docs/theory.md: spring k x tributary length,
  h inside, h/2 at the tip), one candidate per free node;
- the LCP in reactions (the paper's Eqs. 24-32): w = q + M r, M = A K^-1 A^T + diag(1/k_i),
  q = A K^-1 F, w gap, r >= 0, w >= 0, r.w = 0;
- M is symmetric positive definite, so the LCP is the convex QP min 1/2 r'Mr + q'r, r >= 0, solved
  as a non-negative least-squares problem on the Cholesky factor (scipy.optimize.nnls,
  Lawson & Hanson 1974);
- the contact set found is then certified: the bonded springs of that set only, one exact solve
  of the stiffness equations, every reaction of the set positive and every other node lifted.

Prints the contact set, the reaction sum and largest reaction, the tip deflection and the smallest
lift, to compare with a run of uniarc (path file: n_contact, reaction_max, reaction_sum).

Usage: /usr/bin/python3 bench/beam_bed_lcp_reference.py N [L]     (numpy and scipy needed;
dense O(N^2) memory: N up to a few thousand).
"""

import sys

import numpy as np
import scipy.linalg as sl
import scipy.optimize as so


def main():
    n = int(sys.argv[1])
    length = float(sys.argv[2]) if len(sys.argv) > 2 else 1000.0
    ea, ei, k, p = 1.0e4, 1.0, 1.0, 1.0e-4
    h = length/n
    ndof = 3*(n + 1)
    stiffness = np.zeros((ndof, ndof))
    a, b, c, d, e = ea/h, 12*ei/h**3, 6*ei/h**2, 4*ei/h, 2*ei/h
    element = np.zeros((6, 6))
    element[np.ix_([0, 3], [0, 3])] = [[a, -a], [-a, a]]
    element[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = [[b, c, -b, c], [c, d, -c, e], [-b, -c, b, -c],
                                                   [c, e, -c, d]]
    for el in range(n):
        idx = list(range(3*el, 3*el + 6))
        stiffness[np.ix_(idx, idx)] += element
    free = list(range(3, ndof))                       # node 0 clamped
    kf = stiffness[np.ix_(free, free)]
    load = np.zeros(ndof)
    load[3*n + 1] = -p
    load = load[free]
    vdof = [3*i + 1 - 3 for i in range(1, n + 1)]     # v of nodes 1..n among the free DOFs
    tributary = np.full(n, h)
    tributary[-1] = h/2
    springs = k*tributary
    factor = sl.cho_factor(kf)
    unit = np.zeros((len(free), n))
    unit[vdof, range(n)] = 1.0
    m = sl.cho_solve(factor, unit)[vdof, :] + np.diag(1/springs)
    q = sl.cho_solve(factor, load)[vdof]
    chol = np.linalg.cholesky(m)
    r, _ = so.nnls(chol.T, -sl.solve_triangular(chol, q, lower=True), maxiter=50*n)
    contact = np.nonzero(r > 0)[0]
    # certification of the set: bonded springs on it, one exact solve
    ks = kf.copy()
    for i in contact:
        ks[vdof[i], vdof[i]] += springs[i]
    u = np.linalg.solve(ks, load)
    v = u[vdof]
    reaction = np.zeros(n)
    reaction[contact] = -springs[contact]*v[contact]
    lifted = np.delete(v, contact)
    print('n = %d, L = %g, cond(M) = %.3e' % (n, length, np.linalg.cond(m)))
    print('contact nodes (1 = next to the clamp):', (contact + 1).tolist())
    print('certified: smallest reaction in contact %.6e, smallest lift elsewhere %.6e (%.3e of the '
          'largest deflection)' % (reaction[contact].min(), lifted.min(), lifted.min()/abs(v).max()))
    print('reaction_sum %.12e  reaction_max %.12e  tip v %.12e' % (reaction.sum(), reaction.max(), v[-1]))
    ok = reaction[contact].min() > 0 and lifted.min() > 0
    print('set is the solution of the LCP:', ok)
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
