#!/usr/bin/env python3
"""Elastic-perfectly plastic soil springs and beds (QU=, docs/theory.md §3.9) against closed forms and
an independent solution of the same piecewise-linear problem.

Usage (one CTest per call):
  plastic_check.py --uniarc BIN --out DIR --mode block   --deck DECK [--define NAME=VALUE]...
  plastic_check.py --uniarc BIN --out DIR --mode limit   --deck DECK [--limit tu]
  plastic_check.py --uniarc BIN --out DIR --mode bed     --deck DECK [--define NAME=VALUE]... --rtol R
  plastic_check.py --uniarc BIN --out DIR --mode elastic --deck DECK
  plastic_check.py --uniarc BIN --out DIR --mode bilateral --deck DECK
  plastic_check.py --uniarc BIN --out DIR --mode plateau --deck DECK --rtol R [--load-node I]
  plastic_check.py --uniarc BIN --out DIR --mode reload  --deck DECK --rtol R [--define NAME=VALUE]...

block:   a block on a guided cantilever (spring kb = 12 EI/L^3) and a plastic soil spring k, limit qu,
         pushed, unloaded and pushed again (tests/regression/decks/plastic_spring_block.inp): every path
         row against the closed form of its load history, and the slip of STEM.contact; with a
         parameter tu and no ku (decks/plastic_spring_shared_slip.inp) one spring with both limits
         (TU=) and one slip shared by them; with a parameter kup too (decks/plastic_spring_two_stiffnesses.inp)
         that spring's uplift branch has the stiffness kup (KU=).
limit:   a stiff beam on a plastic bed under a central load: the limit load is qu x (contact length);
         the deck's own load qu L must be reached to 0.999 and not passed at 1.001: the run ends at
         the collapse with a bearing_collapse row of STEM.crit at lambda = 1 and exit code 0;
         with --limit tu the uplift limit tu L of a bed with TU= under an upward load.
bed:     a beam on a tensionless plastic bed (decks/beam_plastic_bed.inp): the deflections, the
         slips and the yielding candidates of the last step against an independent small-displacement
         solution: Hermite beam elements on a mesh 16 times finer (--refine), the bed lumped to its nodes, the
         piecewise-linear law solved increment by increment by an active-set loop (numpy).
elastic: the bed deck with QU huge (1e300) against the same deck without QU=: the path files are equal.
reload:  the bed deck loaded, unloaded to zero and loaded again in three *STEPs
         (decks/plastic_bed_unload_reload.inp): the state at the end of each step against its closed
         form, the plastic set being history (docs/theory.md §3.9). End of loading: the independent
         solution of `bed` (deflections and slips to --rtol of w0, the same yielding candidates). End of
         unloading: the slips unchanged and the beam straight where it started, w = 0 at every node to
         the touch tolerance 1e-9 L of the contacts it rests on (the springs that did not yield are at
         their unloaded length, the yielded ones open over the hollow of their slip). End of reloading:
         the state of the end of loading (no spring reaches its limit again: each follows its elastic
         branch back), deflections to 1e-8 of w0 and reactions to 1e-8 of the largest (both ends are
         converged to Newton's tolerance 1e-8 of the force scale), the slips the same.
bilateral: the bed deck with QU= and TU= both huge (1e300) against the same deck with BILATERAL in their
         place: the path files are equal.
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import scipy.linalg


def run(uniarc, deck, out, defines):
    shutil.rmtree(out, ignore_errors=True)
    command = [uniarc, deck, '-o', out, '-q']
    for definition in defines:
        command += ['-D', definition]
    finished = subprocess.run(command, capture_output=True, text=True)
    sys.stdout.write(finished.stdout)
    sys.stderr.write(finished.stderr)
    return finished


def table(path):
    """A uniarc table by column name (docs/contracts.md): header line, `#` lines, rows."""
    return np.genfromtxt(path, names=True, dtype=None, encoding=None, comments='#')


def deck_parameters(deck, defines):
    """The *PARAMETER values of a deck (simple `name = expression` lines), -D overrides applied."""
    values = {}
    reading = False
    with open(deck) as handle:
        for line in handle:
            text = line.strip()
            if text.startswith('*') and not text.startswith('**'):
                reading = text.upper().startswith('*PARAMETER')
                continue
            if reading and '=' in text and not text.startswith('**'):
                name, expression = text.split('=', 1)
                values[name.strip()] = eval(expression.replace('^', '**'), {'pi': math.pi}, dict(values))
    for definition in defines:
        name, value = definition.split('=', 1)
        values[name] = float(value)
    return values


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


# ------------------------------------------------------------------------------------------------
# (a) the block: closed form of the load history
# ------------------------------------------------------------------------------------------------

def clamp(value, high):
    return min(max(value, 0.0), high)


def block_response(kb, bearing, uplift, loads, shared=None, k_up=None):
    """Deflection w (down positive) and slips after each of the loads P (down positive) applied in
    order, each from the state the previous one left: a spring kb (elastic) in parallel with a bearing
    spring (k, q) pushing up and, if given, an uplift spring (k_u, t_u) pushing down, both compression
    only and elastic-perfectly plastic, with slips s_b (down) and s_u (up). The resisting force
    kb w + clamp(k (w - s_b), 0, q) - clamp(k_u (-w - s_u), 0, t_u) is continuous and increasing in w,
    so the equilibrium is its unique root, found by bisection to round-off; then each spring beyond its
    limit moves its slip on (s_b = w - q/k, s_u = -w - t_u/k_u).
    shared = t_u instead: ONE spring (k, q) with the uplift limit t_u too (TU=), bonded while elastic,
    force clamp(k (w - s), -t_u, q) with one slip s (down) that either limit moves on (s = w - q/k
    beyond the bearing limit, s = w + t_u/k beyond the uplift one); returned as (w, s, s).
    k_up (with shared): the stiffness of that spring's uplift branch (KU=), the force clamp(f(w - s), -t_u, q)
    with f(d) = k d for d >= 0 and k_up d for d < 0, continuous and increasing, and s = w + t_u/k_up
    beyond the uplift limit."""
    k, q = bearing
    ku, tu = uplift if uplift else (0.0, 0.0)
    k_up = k if k_up is None else k_up
    s_b = s_u = 0.0

    def elastic(d):
        return k*d if d >= 0.0 else k_up*d

    out = []
    for p in loads:
        def resisting(w):
            if shared is not None:
                return kb*w + min(max(elastic(w - s_b), -shared), q) - p
            force = kb*w + clamp(k*(w - s_b), q)
            if ku > 0.0:
                force -= clamp(ku*(-w - s_u), tu)
            return force - p
        low, high = -1.0, 1.0
        while resisting(low) > 0.0:
            low *= 2.0
        while resisting(high) < 0.0:
            high *= 2.0
        for _ in range(200):
            middle = 0.5*(low + high)
            if resisting(middle) > 0.0:
                high = middle
            else:
                low = middle
        w = 0.5*(low + high)
        if shared is not None:
            s_b = min(max(s_b, w - q/k), w + shared/k_up)
            out.append((w, s_b, s_b))
            continue
        s_b = max(s_b, w - q/k)
        if ku > 0.0:
            s_u = max(s_u, -w - tu/ku)
        out.append((w, s_b, s_u))
    return out


def step_loads(deck):
    """The load of each *STEP of the deck on its tracked node, down positive: the FY of its *CLOAD."""
    loads = []
    with open(deck) as handle:
        lines = [line.strip() for line in handle]
    for i, line in enumerate(lines):
        if line.upper().startswith('*CLOAD'):
            loads.append(-float(lines[i + 1].split(',')[2]))
    return loads


def check_block(args):
    finished = run(args.uniarc, args.deck, args.out, args.define)
    if finished.returncode != 0:
        fail(f'exit code {finished.returncode}')
    values = deck_parameters(args.deck, args.define)
    kb = 12*values['EI']/values['L']**3
    uplift = (values['ku'], values['tu']) if 'ku' in values else None
    shared = values['tu'] if 'tu' in values and 'ku' not in values else None
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    path = table(os.path.join(args.out, stem + '.path'))
    # Each analysis step a of the deck: its load F_a times lambda on the loads of the steps before it,
    # held at lambda_max = 1 (docs/input.md, *STEP).
    forces = step_loads(args.deck)
    loads = [sum(forces[:int(a) - 1]) + lam*forces[int(a) - 1]
             for lam, a in zip(path['lambda'], path['analysis_step'])]
    expected = block_response(kb, (values['k'], values['qu']), uplift, loads, shared, values.get('kup'))
    # Tolerance: the path is converged to the displacement tolerance 1e-8 of the deck's default
    # (*PATH), relative to the displacements; the closed form is exact (small displacements: w/L ~ 1e-5,
    # so the corotational terms are 1e-10 of w).
    scale = max(abs(w) for w, _, _ in expected)
    worst = 0.0
    for (w, _, _), got, step in zip(expected, path['w'], path['step']):
        error = abs(got - w)/scale
        worst = max(worst, error)
        if error > 1e-7:
            fail(f'step {step}: w = {got!r}, closed form {w!r}')
    print(f'block: {len(loads)} rows, largest error of w {worst:.2e} of its largest value')
    # hand values of the last row (the deck's comment), beside the closed form: the Newton tolerance
    if args.final_w is not None and abs(path['w'][-1] - args.final_w) > 1e-7*scale:
        fail(f'last row: w = {path["w"][-1]!r}, by hand {args.final_w!r}')
    contact = table(os.path.join(args.out, stem + '.contact'))
    last = contact[contact['step'] == contact['step'].max()]
    _, s_b, s_u = expected[-1]
    for row in last:
        slip = s_b if row['medium'] == 'soil' else s_u
        if abs(row['slip'] - slip) > 1e-7*scale:
            fail(f'last step, {row["medium"]}: slip {row["slip"]!r}, closed form {slip!r}')
        if args.final_slip is not None and row['medium'] == 'soil' and \
                abs(row['slip'] - args.final_slip) > 1e-7*scale:
            fail(f'last step, soil: slip {row["slip"]!r}, by hand {args.final_slip!r}')
        print(f'block: final slip of {row["medium"]} {row["slip"]:.12e} (closed form {slip:.12e}), '
              f'yielding {row["yielding"]}, reaction {row["reaction"]:.12e}')


# ------------------------------------------------------------------------------------------------
# (b) the limit load of a stiff beam
# ------------------------------------------------------------------------------------------------

def check_limit(args):
    below = run(args.uniarc, args.deck, args.out + '/below', ['lmax=0.999'])
    if below.returncode != 0:
        fail(f'0.999 of qu L: exit code {below.returncode}, expected 0')
    above = run(args.uniarc, args.deck, args.out + '/above', ['lmax=1.001'])
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    if above.returncode != 0:
        fail(f'1.001 of qu L: exit code {above.returncode}, expected 0 (the path ends at the bearing collapse, '
             'a result: docs/contracts.md)')
    limit = args.limit
    # The load-controlled path stops where it cannot go on: at the limit load, from below, to the
    # step-length floor (min_increment) times the first increment.
    reached = table(os.path.join(args.out, 'above', stem + '.path'))['lambda'][-1]
    if not 1.0 - 1e-4 <= reached <= 1.0:
        fail(f'1.001 of qu L: the path stopped at lambda = {reached}, not at the limit lambda = 1')
    # ... and says so: one bearing_collapse row, at the last converged step, at its lambda
    crit = np.atleast_1d(table(os.path.join(args.out, 'above', stem + '.crit')))
    collapse = crit[crit['kind'] == 'bearing_collapse']
    if len(collapse) != 1 or collapse['lambda'][0] != reached:
        fail(f'1.001 of qu L: expected one bearing_collapse row at lambda = {reached} in STEM.crit, found {collapse}')
    values = deck_parameters(args.deck, [])
    path = table(os.path.join(args.out, 'below', stem + '.path'))
    # Elastic rows: a rigid beam on the bed, w = P/(K L); the beam's own bending adds
    # P L^3/(EI) ~ 1e-9 of it (EI = 1e6 against K L^4 = 16).
    load = path['lambda']*values[limit]*values['L']
    elastic = load < 0.99*values[limit]*values['L']
    expected = load[elastic]/(values['K']*values['L'])
    got = path['w'][elastic]
    if np.max(np.abs(got - expected)) > 1e-6*np.max(np.abs(expected)):
        fail(f'elastic rows: w {got} against P/(K L) {expected}')
    contact = table(os.path.join(args.out, 'below', stem + '.contact'))
    last = contact[contact['step'] == contact['step'].max()]
    # at 0.999 of the limit load the rigid beam's uniform tension (or pressure) is 0.999 of the limit
    # at every node, below it: nothing yields yet (the yielding column 1 bearing, -1 uplift, 0 elastic)
    if np.any(last['yielding'] != 0):
        fail('candidates yielding below the limit load of a rigid beam')
    print(f'limit ({limit} L): lambda {path["lambda"][-1]} reached, {int(np.sum(last["yielding"] != 0))} of '
          f'{len(last)} candidates yielding; toward 1.001 the path stops at lambda = {reached!r}')


# ------------------------------------------------------------------------------------------------
# (c) a beam on a plastic bed against an independent solution
# ------------------------------------------------------------------------------------------------

def hermite_stiffness(ei, h):
    """Euler-Bernoulli beam element (w1, θ1, w2, θ2), exact for end loads (Przemieniecki 1968, §5.3)."""
    return ei/h**3*np.array([[12, 6*h, -12, 6*h],
                             [6*h, 4*h*h, -6*h, 2*h*h],
                             [-12, -6*h, 12, -6*h],
                             [6*h, 2*h*h, -6*h, 4*h*h]])


def plastic_bed_reference(length, n, ei, modulus, qu, load, increments, uplift=None, history=None,
                          uplift_modulus=None):
    """Deflections w (down positive, n + 1 nodes), slips and yielding flags of a free-free beam on a
    tensionless elastic-perfectly plastic bed lumped to its nodes (k_i = K L_i, q_i = qu L_i), central
    load `load` applied in `increments` equal increments, each solved by an active-set loop over the
    three states of every spring (open, elastic, yielding) from the state the last one left. The
    stiffness is banded (half-bandwidth 3: DOFs w_i, θ_i node by node), solved by scipy's band solver.
    uplift = t_u (per length): the springs are bonded with the uplift limit t_i = t_u L_i too and one
    slip (TU=): states elastic, yielding in bearing (r = q), yielding in uplift (r = -t), never open.
    history: the central loads the increments go through in order (from 0; `load` then unused),
    `increments` equal increments between each two.
    uplift_modulus = k_u (per length, with uplift): the bonded springs' stiffness in tension (KU=), k_i
    pressed and k_u L_i pulled (d = w - s < 0): a fourth state, elastic in tension, the kink at d = 0
    exchanged as the other states are by the sign of the spring's force."""
    h = length/n
    dofs = 2*(n + 1)
    upper = 3
    band = np.zeros((2*upper + 1, dofs))      # scipy.linalg.solve_banded layout: band[u + i - j, j] = A[i, j]
    element = hermite_stiffness(ei, h)
    for e in range(n):
        for a in range(4):
            for b in range(4):
                band[upper + a - b, 2*e + b] += element[a, b]
    tributary = np.full(n + 1, h)
    tributary[[0, -1]] = h/2
    k = modulus*tributary
    q = qu*tributary
    t = (uplift if uplift else 0.0)*tributary
    k_up = (uplift_modulus if uplift_modulus else modulus)*tributary
    slip = np.zeros(n + 1)
    # 0 open, 1 elastic (pressed, k), 2 yielding (3 in uplift), 4 elastic pulled (k_up); all touching
    state = np.ones(n + 1, dtype=int)
    w = np.zeros(n + 1)
    nodes = np.arange(n + 1)
    targets = history if history else [load]
    loads = []
    for a, target in enumerate(targets):
        start = targets[a - 1] if a > 0 else 0.0
        loads += [start + (target - start)*step/increments for step in range(1, increments + 1)]
    for level in loads:
        force = np.zeros(dofs)
        force[2*(n//2)] = level
        committed = slip.copy()
        for _ in range(200):
            matrix = band.copy()
            rhs = force.copy()
            stiffness = np.where(state == 1, k, np.where(state == 4, k_up, 0.0))
            elastic = (state == 1) | (state == 4)
            matrix[upper, 2*nodes[elastic]] += stiffness[elastic]
            rhs[2*nodes[elastic]] += stiffness[elastic]*committed[elastic]
            rhs[2*nodes[state == 2]] -= q[state == 2]
            rhs[2*nodes[state == 3]] += t[state == 3]
            w = scipy.linalg.solve_banded((upper, upper), matrix, rhs)[0::2]
            new = state.copy()
            reaction = np.where(state == 4, k_up, k)*(w - committed)
            if uplift:
                # the kink at d = 0: the branch of an elastic spring is the sign of its force
                new[(state == 1) & (reaction < 0)] = 4
                new[(state == 4) & (reaction > 0)] = 1
                new[(state == 4) & (reaction < -t)] = 3
                new[(state == 1) & (reaction < -t)] = 3
                new[(state == 3) & (w + t/k_up > committed)] = 4
            else:
                new[(state == 1) & (reaction < 0)] = 0
            new[(state == 1) & (reaction > q)] = 2
            new[(state == 0) & (w > committed)] = 1
            new[(state == 2) & (w - q/k < committed)] = 1
            if np.array_equal(new, state):
                break
            state = new
        else:
            fail('reference: the active-set loop did not settle')
        slip = np.where(state == 2, w - q/k, np.where(state == 3, w + t/k_up, committed))
    return w, slip, np.where(state == 2, 1, np.where(state == 3, -1, 0))


def check_bed(args):
    finished = run(args.uniarc, args.deck, args.out, args.define)
    if finished.returncode != 0:
        fail(f'exit code {finished.returncode}')
    values = deck_parameters(args.deck, args.define)
    refine = args.refine
    uplift = values.get('tu')
    # with an uplift limit the deck is a load history: P down, then its *STEP pull to -P/2 (up; the
    # uplift resistance of the whole bed is tu L = 0.8 P)
    history = [values['P'], -0.5*values['P']] if uplift else None
    w_ref, slip_ref, yielding_ref = plastic_bed_reference(values['L'], refine*int(values['n']), 1.0,
                                                          values['k'], values['qu'], values['P'], 20,
                                                          uplift, history, values.get('ku'))
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    shape = table(os.path.join(args.out, stem + '.shape'))
    last = shape[shape['step'] == shape['step'].max()]
    order = np.argsort(last['x0'])
    w = -last['uy'][order]
    contact = table(os.path.join(args.out, stem + '.contact'))
    rows = contact[contact['step'] == contact['step'].max()]
    rows = rows[np.argsort(rows['s'])]
    w0 = np.max(np.abs(w_ref))
    deflection = np.max(np.abs(w - w_ref[::refine]))/w0
    slip = np.max(np.abs(rows['slip'] - slip_ref[::refine]))/w0
    print(f'bed: w0 {w[len(w)//2]:.10e} against {w_ref[len(w_ref)//2]:.10e}; largest deflection error '
          f'{deflection:.2e} of w0, slip error {slip:.2e} of w0; yielding {int(np.sum(rows["yielding"] == 1))} '
          f'in bearing and {int(np.sum(rows["yielding"] == -1))} in uplift, reference '
          f'{int(np.sum(yielding_ref[::refine] == 1))} and {int(np.sum(yielding_ref[::refine] == -1))}')
    if deflection > args.rtol or slip > args.rtol:
        fail(f'deflections or slips beyond {args.rtol} of w0')
    if not np.array_equal(rows['yielding'], yielding_ref[::refine]):
        fail('the yielding candidates differ from the reference')


def minimise_bed_energy(stiffness, k, q, free, u, scale):
    """The deflections u (from the start u, its prescribed entries kept) that minimise the convex
    energy 1/2 u'Ku + sum Phi_i(w_i) of a beam on a tensionless elastic-perfectly plastic bed lumped
    to its nodes (springs k_i, limits q_i; w = u[0::2] down positive) over the entries `free`:
    Newton's method with an exact line search (the slope of a convex energy along a line is
    monotone: bisection). Returns u and the bed's force law and the energy's gradient as functions
    (the residual forces of the prescribed entries are the loads there)."""

    def force(w):
        return np.where(w <= 0.0, 0.0, np.minimum(k*w, q))

    def gradient(u):
        g = stiffness @ u
        g[0::2] += force(u[0::2])
        return g

    for _ in range(500):
        g = gradient(u)
        # 1e-10 of the bed's capacity, or the round-off of K u where that is larger: on a fine mesh
        # the bending terms of a row (EI/h^3 times the deflections: 1.25e5 x 1e-3 at 400 elements)
        # leave g an error of order 100 eps times them, above 1e-10 qu L
        floor = 100.0*np.finfo(float).eps*np.max(np.abs(stiffness) @ np.abs(u))
        if np.max(np.abs(g[free])) <= max(1e-10*scale, floor):
            break
        w = u[0::2]
        hessian = stiffness.copy()
        hessian[0::2, 0::2] += np.diag(np.where((w > 0.0) & (k*w < q), k, 0.0))
        step = np.zeros(len(u))
        step[free] = -np.linalg.solve(hessian[np.ix_(free, free)], g[free])
        t = 1.0
        if gradient(u + step)[free] @ step[free] > 0.0:
            low, high = 0.0, 1.0
            for _ in range(80):
                t = 0.5*(low + high)
                if gradient(u + t*step)[free] @ step[free] > 0.0:
                    high = t
                else:
                    low = t
        u = u + t*step
    else:
        fail('reference: Newton did not converge')
    # The floor above stops Newton where g is of the order of the round-off of K u per entry, but the
    # load is the sum of the bed's forces, where those errors add up (half a beam of 100 elements:
    # 100 x 4e-12 against end forces of 1e-10 just past a plateau). Once the state is on its final
    # piece of the piecewise-linear law (the same nodes open, elastic and yielded), one full Newton
    # step lands on that piece's quadratic minimum to the round-off of the solve: taken while it
    # keeps the piece and lowers the residual (at most 5).
    def piece(w):
        return np.where(w <= 0.0, 0, np.where(k*w < q, 1, 2))

    for _ in range(5):
        g = gradient(u)
        w = u[0::2]
        hessian = stiffness.copy()
        hessian[0::2, 0::2] += np.diag(np.where((w > 0.0) & (k*w < q), k, 0.0))
        trial = u.copy()
        trial[free] -= np.linalg.solve(hessian[np.ix_(free, free)], g[free])
        if not np.array_equal(piece(trial[0::2]), piece(w)):
            break
        if not np.max(np.abs(gradient(trial)[free])) < np.max(np.abs(g[free])):
            break
        u = trial
    return u, force, gradient


def midspan_equilibrium(length, n, ei, modulus, qu, w0):
    """The load (the central force) in equilibrium with a free-free beam on a tensionless
    elastic-perfectly plastic bed lumped to its nodes (k_i = K L_i, q_i = qu L_i) whose midspan is
    pushed down by w0, with the deflections w (down positive, the half from the middle to an end).
    The law is taken holonomic, r_i = min(k_i w_i, q_i) for w_i > 0 and 0 else (the incremental law
    gives the same where no yielded node moves back, which check_plateau verifies along the path):
    the equilibrium then minimises the convex, continuously differentiable energy
    1/2 u'Ku + sum Phi_i(w_i) with w0 prescribed (Maier 1968: piecewise-linear holonomic springs),
    unique and found by Newton's method with an exact line search (the slope of a convex energy
    along a line is monotone: bisection). Half the beam by symmetry (theta = 0 at the middle, the
    middle node's spring and load halved); dense, n/2 Hermite elements."""
    h = length/n
    half = n//2
    dofs = 2*(half + 1)
    stiffness = np.zeros((dofs, dofs))
    element = hermite_stiffness(ei, h)
    for e in range(half):
        stiffness[2*e:2*e + 4, 2*e:2*e + 4] += element
    tributary = np.full(half + 1, h)
    tributary[[0, -1]] = h/2
    k = modulus*tributary
    q = qu*tributary
    free = np.arange(2, dofs)

    u = np.zeros(dofs)
    u[0::2] = w0
    u, force, gradient = minimise_bed_energy(stiffness, k, q, free, u, qu*length)
    w = u[0::2]
    return 2.0*gradient(u)[0], w, force(w) >= q*(1.0 - 1e-12)


def loaded_node_equilibrium(length, n, ei, modulus, qu, node, w_node, w_end):
    """midspan_equilibrium for a load at any node (an eccentric load): the whole beam (no symmetry),
    node `node` (0 at the left end) pushed down by w_node and the right end by w_end (on a plateau the
    beam turns about a touching node at constant load, so the loaded node's deflection alone does not
    fix the state); the forces there (the load, and the end's, which is 0 where the row is an
    equilibrium of the beam loaded at `node` alone) and the deflections w of every node (down
    positive). The same convex energy, minimised by the same Newton iteration."""
    h = length/n
    dofs = 2*(n + 1)
    stiffness = np.zeros((dofs, dofs))
    element = hermite_stiffness(ei, h)
    for e in range(n):
        stiffness[2*e:2*e + 4, 2*e:2*e + 4] += element
    tributary = np.full(n + 1, h)
    tributary[[0, -1]] = h/2
    k = modulus*tributary
    q = qu*tributary
    free = np.array([i for i in range(dofs) if i not in (2*node, 2*n)])

    u = np.zeros(dofs)
    u[0::2] = w_node + (w_end - w_node)*(np.arange(n + 1) - node)/(n - node)
    u, force, gradient = minimise_bed_energy(stiffness, k, q, free, u, qu*length)
    w = u[0::2]
    g = gradient(u)
    return g[2*node], g[2*n], w, force(w) >= q*(1.0 - 1e-12)


def check_plateau(args):
    """A flexible beam on a plastic bed traced to its collapse (decks/bed_qu_flex_plateau*.inp): the
    run ends with exit code 0 and one bearing_collapse row at qu L / P; every path row (its load
    factor and end deflection) against the independent equilibrium at its midspan deflection
    (midspan_equilibrium), within rtol of the collapse load and of the midspan deflection; the path
    has plateaus (rows at one load whose midspan deflection grows) and no yielded node of the
    reference moves back along it (so the holonomic reference is the incremental law's path), and no
    row equals the one before to round-off (a step of no length). With --load-node the load is at that
    node (decks/bed_qu_flex_plateau_eccentric.inp): the collapse load is qu (L - 2e)/P (Meyerhof's
    effective width, e the eccentricity) and each row is checked at its loaded node's deflection
    (column w_load) against loaded_node_equilibrium."""
    finished = run(args.uniarc, args.deck, args.out, args.define)
    if finished.returncode != 0:
        fail(f'exit code {finished.returncode}')
    values = deck_parameters(args.deck, args.define)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    path = table(os.path.join(args.out, stem + '.path'))
    crit = table(os.path.join(args.out, stem + '.crit'))
    crit = np.atleast_1d(crit)
    collapse_load = values['qu']*values['L']/values['P']
    eccentric = args.load_node is not None
    if eccentric:
        # Meyerhof's effective width L - 2e: the bed under the load's eccentricity e from the middle
        # yields over the width centred on the load (the discrete collapse of the lumped bed is the same:
        # the node at the far edge of that width carries half its limit)
        n = int(values['n'])
        eccentricity = abs(args.load_node - n//2)*values['L']/n
        collapse_load = values['qu']*(values['L'] - 2*eccentricity)/values['P']
    rows = crit[crit['kind'] == 'bearing_collapse']
    if len(rows) != 1:
        fail(f'{len(rows)} bearing_collapse rows, expected one')
    error = abs(rows['lambda'][0] - collapse_load)/collapse_load
    print(f'plateau: bearing_collapse at lambda {rows["lambda"][0]:.12e}, expected {collapse_load}, '
          f'relative error {error:.2e}')
    collapse_rtol = args.collapse_rtol if args.collapse_rtol is not None else args.rtol
    if error > collapse_rtol:
        fail(f'the collapse load beyond {collapse_rtol} relative')
    worst_load = worst_end = 0.0
    previous = None
    plateaus = 0
    moved_back = 0
    w_scale = np.max(path['w0'])
    driven = path['w_load'] if eccentric else path['w0']
    same = 0
    for a in range(1, len(path)):
        # consecutive rows equal to round-off (1e-12 of the scales): a step of no length written as a row
        if abs(path['lambda'][a] - path['lambda'][a - 1]) <= 1e-12*collapse_load and \
           abs(driven[a] - driven[a - 1]) <= 1e-12*np.max(np.abs(driven)):
            same += 1
    if same:
        fail(f'{same} rows equal to the one before to round-off (steps of no length)')
    for lam, w0, w_end in zip(path['lambda'], driven, path['w_end']):
        if w0 <= 0.0:
            continue
        if eccentric:
            # the end's force, 0 in the row's equilibrium, is compared as the load is
            load, end_force, w, yielded = loaded_node_equilibrium(values['L'], int(values['n']), values['EI'],
                                                                  values['K'], values['qu'], args.load_node, w0,
                                                                  w_end)
            worst_load = max(worst_load, abs(end_force/values['P'])/collapse_load)
        else:
            load, w, yielded = midspan_equilibrium(values['L'], int(values['n']), values['EI'], values['K'],
                                                   values['qu'], w0)
        worst_load = max(worst_load, abs(lam - load/values['P'])/collapse_load)
        worst_end = max(worst_end, abs(w_end - w[-1])/w_scale)
        if previous is not None:
            last_lambda, last_w0, last_w, last_yielded = previous
            if abs(lam - last_lambda) <= 1e-9*collapse_load and w0 > last_w0*(1.0 + 1e-9):
                plateaus += 1
            moved_back += int(np.sum(last_yielded & (w < last_w - 1e-9*w_scale)))
        previous = (lam, w0, w, yielded)
    print(f'plateau: {len(path)} rows, load factor within {worst_load:.2e} of the collapse load, end '
          f'deflection within {worst_end:.2e} of the largest midspan deflection; {plateaus} rows on a '
          f'plateau; {moved_back} yielded nodes moving back; no row equal to the one before')
    if worst_load > args.rtol or worst_end > args.rtol:
        fail(f'path rows beyond {args.rtol} of the reference')
    if plateaus < args.min_plateau_rows:
        fail(f'{plateaus} rows on a plateau (constant load, growing deflection), expected at least '
             f'{args.min_plateau_rows}')
    if moved_back:
        fail('a yielded node of the reference moves back: the holonomic reference does not apply')


def check_reload(args):
    finished = run(args.uniarc, args.deck, args.out, args.define)
    if finished.returncode != 0:
        fail(f'exit code {finished.returncode}')
    values = deck_parameters(args.deck, args.define)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    path = table(os.path.join(args.out, stem + '.path'))
    shape = table(os.path.join(args.out, stem + '.shape'))
    contact = table(os.path.join(args.out, stem + '.contact'))
    ends = {}
    for analysis_step in (1, 2, 3):
        rows = path[path['analysis_step'] == analysis_step]
        if len(rows) == 0:
            fail(f'no row of analysis step {analysis_step}')
        last = rows[-1]
        if abs(last['lambda'] - 1.0) > 1e-12:
            fail(f'analysis step {analysis_step} ended at lambda = {last["lambda"]!r}, not 1')
        step = int(last['step'])
        nodes = shape[(shape['step'] == step) & (np.abs(shape['lambda'] - 1.0) <= 1e-12)]
        nodes = nodes[np.argsort(nodes['x0'])]
        springs = contact[(contact['step'] == step) & (contact['analysis_step'] == analysis_step)]
        springs = springs[np.argsort(springs['s'])]
        if len(nodes) != int(values['n']) + 1 or len(springs) != int(values['n']) + 1:
            fail(f'the shape or contact rows of step {step} (end of analysis step {analysis_step}) are missing')
        ends[analysis_step] = (-nodes['uy'], springs['slip'], springs['yielding'], springs['reaction'])
    refine = args.refine
    w_ref, slip_ref, yielding_ref = plastic_bed_reference(values['L'], refine*int(values['n']), 1.0, values['k'],
                                                          values['qu'], values['P'], 20)
    w0 = np.max(np.abs(w_ref))
    w_load, slip_load, yielding_load, reaction_load = ends[1]
    deflection = np.max(np.abs(w_load - w_ref[::refine]))/w0
    slip = np.max(np.abs(slip_load - slip_ref[::refine]))/w0
    print(f'end of loading: w0 {w_load[len(w_load)//2]:.10e} against {w_ref[len(w_ref)//2]:.10e}; deflections '
          f'{deflection:.2e} of w0, slips {slip:.2e}; {int(np.sum(yielding_load == 1))} yielding, reference '
          f'{int(np.sum(yielding_ref[::refine] == 1))}')
    if deflection > args.rtol or slip > args.rtol:
        fail(f'end of loading: deflections or slips beyond {args.rtol} of w0')
    if not np.array_equal(yielding_load, yielding_ref[::refine]):
        fail('end of loading: the yielding candidates differ from the reference')
    if not np.any(slip_load > 0.0):
        fail('end of loading: no slip, nothing to unload from')
    w_unload, slip_unload, yielding_unload, reaction_unload = ends[2]
    touch = 1e-9*values['L']
    print(f'end of unloading: largest |w| {np.max(np.abs(w_unload)):.3e} (touch tolerance {touch:.1e}), slips '
          f'changed by {np.max(np.abs(slip_unload - slip_load)):.3e}, {int(np.sum(yielding_unload != 0))} yielding, '
          f'largest reaction {np.max(np.abs(reaction_unload)):.3e}')
    if np.max(np.abs(w_unload)) > touch:
        fail('end of unloading: the beam is not back where it started')
    if np.max(np.abs(slip_unload - slip_load)) > 1e-12*w0 or np.any(yielding_unload != 0):
        fail('end of unloading: the slips changed or a spring still yields')
    # no load: the springs it rests on carry at most their stiffness times the touch tolerance
    if np.max(np.abs(reaction_unload)) > values['k']*values['L']/values['n']*touch:
        fail('end of unloading: a spring carries a force with no load on the beam')
    w_reload, slip_reload, yielding_reload, reaction_reload = ends[3]
    again = np.max(np.abs(w_reload - w_load))/w0
    # back on the elastic branch of every spring: the same reactions (those at the limit reach qu L_i
    # again, whether the set then calls them yielding or elastic at their limit), no new slip
    reaction_change = np.max(np.abs(reaction_reload - reaction_load))/np.max(np.abs(reaction_load))
    print(f'end of reloading: w0 {w_reload[len(w_reload)//2]:.10e}, deflections {again:.2e} of w0 from the end '
          f'of loading, reactions {reaction_change:.2e} of the largest, slips changed by '
          f'{np.max(np.abs(slip_reload - slip_load)):.3e}; {int(np.sum(yielding_reload == 1))} yielding')
    if again > 1e-8 or reaction_change > 1e-8:
        fail('end of reloading: not the state of the end of loading')
    if np.max(np.abs(slip_reload - slip_load)) > 1e-12*w0:
        fail('end of reloading: the slips differ from the end of loading (a spring yielded again)')

def check_elastic(args):
    """The deck with QU huge against the same deck without QU= (written next to the results): the
    plastic law must leave the elastic path untouched, row for row and digit for digit."""
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    elastic_deck = os.path.join(args.out, stem + '.inp')
    with open(args.deck) as source, open(elastic_deck, 'w') as target:
        for line in source:
            target.write(re.sub(r',\s*QU\s*=\s*[^,\s]+', '', line) if line.upper().startswith('*FOUNDATION') else line)
    plastic = run(args.uniarc, args.deck, args.out + '/plastic', ['qu=1e300'])
    elastic = run(args.uniarc, elastic_deck, args.out + '/elastic', [])
    if plastic.returncode != 0 or elastic.returncode != 0:
        fail('a run failed')

    def rows(path):
        with open(path) as handle:
            return [line for line in handle if not line.startswith('#')]

    a = rows(os.path.join(args.out, 'plastic', stem + '.path'))
    b = rows(os.path.join(args.out, 'elastic', stem + '.path'))
    if a != b:
        fail('the path files differ')
    print(f'elastic: {len(a)} lines of the path files equal')


def check_bilateral(args):
    """The deck with QU= and TU= both huge against the same deck with BILATERAL in their place: a
    spring bonded while elastic whose limits are never reached is the bonded (bilateral) bed, row for
    row and digit for digit."""
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    decks = {}
    for kind, replacement in (('uplift', ', QU=1e300, TU=1e300'), ('bonded', ', BILATERAL')):
        decks[kind] = os.path.join(args.out, kind + '.inp')
        with open(args.deck) as source, open(decks[kind], 'w') as target:
            for line in source:
                if line.upper().startswith('*FOUNDATION'):
                    line = re.sub(r',\s*QU\s*=\s*[^,\s]+', replacement, line)
                target.write(line)
    runs = {kind: run(args.uniarc, deck, os.path.join(args.out, kind), []) for kind, deck in decks.items()}
    if any(finished.returncode != 0 for finished in runs.values()):
        fail('a run failed')

    def rows(path):
        with open(path) as handle:
            return [line for line in handle if not line.startswith('#')]

    a = rows(os.path.join(args.out, 'uplift', 'uplift.path'))
    b = rows(os.path.join(args.out, 'bonded', 'bonded.path'))
    if a != b:
        fail('the path files differ')
    print(f'bilateral: {len(a)} lines of the path files equal')


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--mode', required=True,
                        choices=['block', 'limit', 'bed', 'elastic', 'bilateral', 'plateau', 'reload'])
    parser.add_argument('--limit', default='qu', choices=['qu', 'tu'],
                        help='limit mode: the parameter of the limit load per length (qu bearing, tu uplift)')
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--rtol', type=float, default=1e-3)
    # --mode plateau: the rows on a plateau the path must have (0 on a mesh whose elements are
    # shorter than the elastic strip between the yield zone and the lift-off: no staircase)
    parser.add_argument('--min-plateau-rows', type=int, default=1)
    parser.add_argument('--refine', type=int, default=16)
    parser.add_argument('--final-w', type=float, default=None,
                        help='block: the last row\'s w by hand (down positive), beside the closed form')
    parser.add_argument('--final-slip', type=float, default=None,
                        help='block: the final slip of the spring `soil` by hand, beside the closed form')
    parser.add_argument('--collapse-rtol', type=float, default=None,
                        help='plateau: the tolerance of the collapse load (default --rtol)')
    parser.add_argument('--load-node', type=int, default=None,
                        help='plateau: the loaded node (0 at the left end; default the middle), its '
                             'deflection tracked as w_load')
    args = parser.parse_args()
    {'block': check_block, 'limit': check_limit, 'bed': check_bed, 'elastic': check_elastic,
     'bilateral': check_bilateral, 'plateau': check_plateau, 'reload': check_reload}[args.mode](args)
    print('ok')


if __name__ == '__main__':
    main()
