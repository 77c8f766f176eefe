#!/usr/bin/env python3
"""The bedded segmental lining under *STATIC against a model of its own: which contact sets are consistent.

The field deck input/segmental_lining_bedded.inp (a ring of 48 Timoshenko elements with rotational-spring
joints and a hinge, held by radial springs in compression only and tangential springs that act only where
the radial one is in contact, under the ground pressure as *DLOAD) has tangential springs that switch with
the contact set, so its static problem is not an LCP (docs/theory.md §3.8). This script builds the same
linear model in numpy from the deck's *PARAMETER and *RELEASE cards (with the -D overrides applied as
uniarc applies them), independently of uniarc's code:

- each element the linear Timoshenko beam (the exact stiffness with phi = 12 EI/(GAs L^2); Przemieniecki
  1968, §5.6), its end 1 at a joint on a rotation of its own tied to the node's by the joint's spring
  (no spring at a hinge);
- the pressure p = gamma (H - y)(K0 + (1 - K0) sin^2 theta) at each chord's midpoint, uniform on the
  chord, as its consistent nodal loads (p L/2 and p L^2/12 on the clamped member; uniarc's *DLOAD);
- at a node in the set a radial spring K_R h and a tangential one K_T h (h the chord: the lumped bed).

A set S is consistent when the solution with the springs of S has every node of S pressing into the
ground (outward radial displacement >= 0) and every other node off it (<= 0).

--expect solved: uniarc must exit 0; the set of its contact file (radial reactions > 0) must be
consistent in this model, and w_crown, w_invert, u_springing (the deck's tracks) must equal this model's
with that set. --expect-loop-cycles checks besides that the engineers' loop (solve, drop the pulling
nodes, add the penetrating ones, again) does not settle here, so the case needs uniarc's search.

--expect no-set: uniarc must exit 1 saying "no consistent contact set"; this model must find none
either: the engineers' loop cycles, the search by single changes from every node in contact cycles, no
set of one arc of nodes is consistent, nor any set reached by the same search from 200 random starts
(a fixed seed). That is evidence, not proof: the sets are 2^48.

    lining_sets_check.py --uniarc BIN --deck DECK --out DIR --expect solved|no-set [--define N=V]...
"""
import argparse
import math
import os
import re
import sys

import numpy as np

from uniarc_check import run_uniarc

N_ELEMENTS = 48
# the deck's tracks: w_crown = UY of node 13 (90 deg), w_invert = UY of node 37 (270 deg),
# u_springing = UX of node 1 (0 deg)
TRACKS = {'w_crown': (13, 1), 'w_invert': (37, 1), 'u_springing': (1, 0)}
# A set's sign conditions are tested to 1e-9 of the largest radial displacement (uniarc's own
# complementarity tolerance is 1e-8 of its units; this model's solve is round-off, ~1e-13).
SIGN_TOLERANCE = 1e-9
# The displacements of one linear model solved by two codes (LAPACK band and dense solves, condition
# number of K below ~1e9 here): measured agreement 1e-12 or better; 1e-9 of the largest.
DISPLACEMENT_TOLERANCE = 1e-9


def deck_cards(path, defines):
    """The deck's parameters (evaluated in order, -D replacing the expression where it is defined, as
    docs/input.md *PARAMETER says) and its *RELEASE lines (node, end, spring stiffness or None)."""
    overrides = {}
    for definition in defines:
        name, value = definition.split('=', 1)
        overrides[name.strip().lower()] = value
    values = {'pi': math.pi}
    releases = []
    card = None
    with open(path) as handle:
        for line in handle:
            text = line.strip()
            if not text or text.startswith('**'):
                continue
            if text.startswith('*'):
                card = text[1:].split(',')[0].strip().upper()
                continue
            if card == 'PARAMETER':
                name, expression = (part.strip() for part in text.split('=', 1))
                expression = overrides.pop(name.lower(), expression)
                values[name.lower()] = float(eval(expression.lower(), {'__builtins__': {}}, values))
            elif card == 'RELEASE':
                fields = [field.strip() for field in text.split(',')]
                stiffness = float(eval(fields[2].lower(), {'__builtins__': {}}, values)) if len(fields) > 2 else None
                releases.append((int(fields[0]), int(fields[1]), stiffness))
    if overrides:
        raise SystemExit(f'-D of no parameter of the deck: {sorted(overrides)}')
    return values, releases


def ring_model(p, releases):
    """The stiffness without the ground, the load vector, the radial (outward) and tangential unit
    vectors and the lumped spring constants of the ring."""
    n = N_ELEMENTS
    R = p['r']
    theta = 2.0 * math.pi * np.arange(n) / n
    xy = np.c_[R * np.cos(theta), R * np.sin(theta)]
    joint_dof = {}
    size = 3 * n
    for node, end, _ in releases:
        if end != 1:
            raise SystemExit('this model takes releases on end 1 of the element that starts at the node')
        joint_dof[node - 1] = size
        size += 1
    K = np.zeros((size, size))
    F = np.zeros(size)
    for e in range(n):
        a, b = e, (e + 1) % n
        d = xy[b] - xy[a]
        L = math.hypot(*d)
        c, s = d / L
        phi = 12.0 * p['ei'] / (p['gas'] * L * L)
        kb = p['ei'] / (L ** 3 * (1.0 + phi))
        local = np.zeros((6, 6))
        local[np.ix_([0, 3], [0, 3])] = p['ea'] / L * np.array([[1.0, -1.0], [-1.0, 1.0]])
        local[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = kb * np.array(
            [[12.0, 6 * L, -12.0, 6 * L], [6 * L, (4 + phi) * L * L, -6 * L, (2 - phi) * L * L],
             [-12.0, -6 * L, 12.0, -6 * L], [6 * L, (2 - phi) * L * L, -6 * L, (4 + phi) * L * L]])
        rotation = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        T = np.zeros((6, 6))
        T[:3, :3] = rotation
        T[3:, 3:] = rotation
        dofs = [3 * a, 3 * a + 1, joint_dof.get(a, 3 * a + 2), 3 * b, 3 * b + 1, 3 * b + 2]
        K[np.ix_(dofs, dofs)] += T.T @ local @ T
        mid = theta[e] + math.pi / n
        y = R * math.cos(math.pi / n) * math.sin(mid)
        q = p['gamma'] * (p['h'] - y) * (p['k0'] + (1.0 - p['k0']) * math.sin(mid) ** 2)
        # toward the centre: along the chord's left normal (local +y of a counter-clockwise chord)
        F[dofs] += T.T @ np.array([0.0, q * L / 2, q * L * L / 12, 0.0, q * L / 2, -q * L * L / 12])
    for node, _, stiffness in releases:
        if stiffness is not None:
            i, j = 3 * (node - 1) + 2, joint_dof[node - 1]
            K[np.ix_([i, j], [i, j])] += stiffness * np.array([[1.0, -1.0], [-1.0, 1.0]])
    chord = 2.0 * R * math.sin(math.pi / n)
    radial = np.c_[np.cos(theta), np.sin(theta)]
    tangential = np.c_[-np.sin(theta), np.cos(theta)]
    return dict(K=K, F=F, radial=radial, tangential=tangential, kr=p['k_r'] * chord, kt=p['k_t'] * chord)


def solve(model, in_set):
    """Displacements and the outward radial displacement of each node with the springs of `in_set`."""
    K = model['K'].copy()
    for i in np.nonzero(in_set)[0]:
        d = [3 * i, 3 * i + 1]
        K[np.ix_(d, d)] += (model['kr'] * np.outer(model['radial'][i], model['radial'][i])
                            + model['kt'] * np.outer(model['tangential'][i], model['tangential'][i]))
    u = np.linalg.solve(K, model['F'])
    outward = u[0:3 * N_ELEMENTS:3] * model['radial'][:, 0] + u[1:3 * N_ELEMENTS:3] * model['radial'][:, 1]
    return u, outward


def violations(in_set, outward):
    """Each node's violation of its sign condition relative to the largest radial displacement."""
    scale = max(np.abs(outward).max(), 1e-300)
    return np.where(in_set, -outward, outward) / scale


def engineers_loop(model, rounds=100):
    """The loop of the bedded-ring programs from every node in contact: the set it settles on, or None."""
    in_set = np.ones(N_ELEMENTS, bool)
    for _ in range(rounds):
        _, outward = solve(model, in_set)
        new = outward > 0.0
        if (new == in_set).all() and violations(in_set, outward).max() <= SIGN_TOLERANCE:
            return in_set
        in_set = new
    return None


def single_changes(model, in_set, limit=1000):
    """Change the node of largest violation until none is left (the set) or a set comes back (None)."""
    seen = set()
    for _ in range(limit):
        _, outward = solve(model, in_set)
        v = violations(in_set, outward)
        if v.max() <= SIGN_TOLERANCE:
            return in_set
        key = in_set.tobytes()
        if key in seen:
            return None
        seen.add(key)
        in_set = in_set.copy()
        in_set[np.argmax(v)] = not in_set[np.argmax(v)]
    return None


def uniarc_set(path):
    """The radial candidates in contact in uniarc's contact file (reaction > 0), by node (0-based)."""
    with open(path) as handle:
        lines = [line for line in handle.read().splitlines() if line.strip() and not line.startswith('#')]
    names = lines[0].split()
    in_set = np.zeros(N_ELEMENTS, bool)
    for line in lines[1:]:
        row = dict(zip(names, line.split()))
        if float(row['reaction']) > 0.0:
            in_set[int(row['node']) - 1] = True
    return in_set


def last_row(path):
    with open(path) as handle:
        lines = [line for line in handle.read().splitlines() if line.strip() and not line.startswith('#')]
    return dict(zip(lines[0].split(), (float(x) for x in lines[-1].split())))


def text(in_set):
    return ''.join('1' if x else '0' for x in in_set)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--expect', choices=['solved', 'no-set'], required=True)
    parser.add_argument('--expect-loop-cycles', action='store_true')
    args = parser.parse_args()
    parameters, releases = deck_cards(args.deck, args.define)
    model = ring_model(parameters, releases)
    failures = []
    loop = engineers_loop(model)
    print('engineers\' loop:', 'cycles' if loop is None else f'settles on {loop.sum()} nodes {text(loop)}')
    command, run = run_uniarc(args.uniarc, args.deck, args.out, args.define)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    if args.expect == 'solved':
        if run.returncode != 0:
            raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}, expected 0')
        if args.expect_loop_cycles and loop is not None:
            failures.append('the engineers\' loop settles: the case does not need the search')
        in_set = uniarc_set(os.path.join(args.out, stem + '.contact'))
        u, outward = solve(model, in_set)
        worst = violations(in_set, outward).max()
        print(f'uniarc\'s set: {in_set.sum()} nodes {text(in_set)}; its largest violation here {worst:.3g}')
        if worst > SIGN_TOLERANCE:
            failures.append(f'uniarc\'s set is not consistent in this model (violation {worst:.3g})')
        row = last_row(os.path.join(args.out, stem + '.path'))
        scale = np.abs(np.c_[u[0:3 * N_ELEMENTS:3], u[1:3 * N_ELEMENTS:3]]).max()
        for name, (node, component) in TRACKS.items():
            mine = u[3 * (node - 1) + component]
            difference = abs(row[name] - mine) / scale
            print(f'{name}: uniarc {row[name]!r}, this model {mine!r} (difference {difference:.3g} of the largest)')
            if difference > DISPLACEMENT_TOLERANCE:
                failures.append(f'{name} differs by {difference:.3g} of the largest displacement')
        if int(row['n_contact']) != int(in_set.sum()):
            failures.append(f'n_contact {row["n_contact"]} against {in_set.sum()} reactions > 0')
    else:
        if run.returncode != 1 or 'no consistent contact set' not in run.stderr:
            raise SystemExit(f'FAIL: {" ".join(command)} exited {run.returncode}, expected 1 with '
                             '"no consistent contact set"')
        if loop is not None:
            failures.append(f'the engineers\' loop settles on {text(loop)}')
        found = single_changes(model, np.ones(N_ELEMENTS, bool))
        if found is not None:
            failures.append(f'the search from every node in contact finds {text(found)}')
        for start in range(N_ELEMENTS):
            for length in range(1, N_ELEMENTS):
                in_set = np.zeros(N_ELEMENTS, bool)
                in_set[[(start + k) % N_ELEMENTS for k in range(length)]] = True
                _, outward = solve(model, in_set)
                if violations(in_set, outward).max() <= SIGN_TOLERANCE:
                    failures.append(f'the arc {text(in_set)} is consistent')
        generator = np.random.default_rng(16)
        for _ in range(200):
            found = single_changes(model, generator.random(N_ELEMENTS) < 0.7)
            if found is not None:
                failures.append(f'a random start finds the consistent set {text(found)}')
                break
        print('no consistent set: the loop and the searches cycle, no arc of nodes is one' if not failures else '')
    for failure in failures:
        print('FAIL:', failure)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
