#!/usr/bin/env python3
"""The two models of the contact-scale benchmark (bench/contact_scale.py) in OpenSees (openseespy).

This is the OpenSees side of bench/contact_scale.py and a benchmark peer only: no test of uniarc
imports it. It builds, from the same parameters as the uniarc decks in bench/decks/, the same nodes,
elements, springs and reference loads:

- the beam-columns are `elasticBeamColumn` elements with the `Corotational` geometric transformation
  (EA and EI as E = 1, A = EA, Iz = EI);
- every node of the foundation is tied by a `zeroLength` element to a ground node at the same point,
  held by zero prescribed displacements (`sp` in a constant pattern, constraint handler
  `Transformation`; `ops.fix` of n ground nodes costs O(n^2) in OpenSees — `--ground-fixity fix`
  measures that variant),
  with the lumped Winkler stiffness of uniarc's *FOUNDATION (k times half the length of the adjacent
  elements: a whole element at every node of the closed ring, half an element at the two ends of the
  beam), oriented along the direction in which the medium pushes (the inward radius of the ring; up
  for the beam); its material is `ENT` (elastic, no tension) for the tensionless medium, or `Elastic`
  for the bonded one (uniarc's BILATERAL);
- the reference loads are the consistent nodal loads (forces q L / 2 and end moments +-q_n L^2 / 12
  on the initial geometry) that uniarc computes for each element's *DLOAD, PY, so that both programs
  apply the same load vector; lambda = 1 is the full load;
- `integrator LoadControl` with `steps` equal increments of 1/steps, `algorithm Newton`, at most 25
  iterations per step (uniarc's default `max_iterations`), `numberer RCM`, `constraints Transformation` and the
  linear-system solver given by --system (default BandGeneral);
- `test RelativeNormDispIncr 1e-8`: the step has converged when the norm of the Newton correction is
  1e-8 of that of the step's first solve (about the step's increment). This is uniarc's displacement
  test (correction <= 1e-8 of the step's increment). uniarc also asks the force residual to be below
  1e-8 of the force scale, but with a floor at the round-off of the element forces; OpenSees has no
  such floor, and `test NormUnbalance` (--test NormUnbalance: tolerance 1e-8 times the norm of the
  reference load) cannot be met by the fixed-radius ring from about n = 1e3 on (the residual that
  round-off leaves grows like (R/L)^3), which would make OpenSees fail for a reason that is not the
  model's.

Run by itself it prints `step K ITERATIONS` after each converged step (so that a run stopped by a time
limit shows how far it got) and then one JSON object, the last line of stdout (openseespy writes its
banner to stderr):

    python3 bench/opensees_models.py --model ring --n 1000 [--bonded] [--system BandGeneral]
"""

import argparse
import json
import math
import sys
import time

# Parameters of the two models. bench/contact_scale.py passes the same values to the uniarc decks with
# -D NAME=VALUE, so these dictionaries are the single source of the numbers; the defaults written in
# bench/decks/*.inp are the same values (a standalone run of a deck gives the benchmark's model).
RING = {
    'R': 1.0,       # radius of the ring (fixed for every n: the same ring, finer meshes)
    'EI': 1.0,      # bending stiffness
    'EA': 3.0e4,    # axial stiffness: EA/EI = 12/t^2 for a wall of thickness t = R/50
    'k': 500.0,     # Winkler modulus (force per unit length per unit deflection): k R^4/EI = 500
    'p': 5.0,       # downward load per unit (initial) length, the ring's weight: p R^3/EI = 5
}
BEAM = {
    'Le': 1.0,      # element length (fixed for every n: the pipeline gets longer with n)
    'm': 100,       # elements per wave of the sinusoidal load (fixed: the deck has m phase sets)
    'EI': 1.0e4,    # bending stiffness: 1/beta = (4 EI/k)^(1/4) = 14.1 element lengths
    'EA': 1.0e6,    # axial stiffness
    'k': 1.0,       # Winkler modulus of the bed below
    'w': 1.0,       # self-weight per unit length (downward)
    'a': 5.0,       # amplitude of the sinusoidal load relative to w
}
DEFAULTS = {'ring': RING, 'beam': BEAM}


def ring_geometry(n, par):
    """Nodes 1..n counter-clockwise from the bottom (270 degrees), as uniarc's *RING with theta_start
    = 270; element e joins node e to node e+1 (the last closes the ring)."""
    R = par['R']
    angles = [math.radians(270.0 + 360.0 * (i / n)) for i in range(n)]
    coords = [(R * math.cos(t), R * math.sin(t)) for t in angles]
    elements = [(e + 1, e + 1, (e + 1) % n + 1) for e in range(n)]
    qy = [-par['p']] * n
    # Winkler lumping: every node of the closed ring carries a whole element (all of equal length).
    length = 2.0 * R * math.sin(math.pi / n)
    springs = []
    for i, t in enumerate(angles):
        # The medium is outside (uniarc SIDE=OUTER): it pushes along the inward radius. The nodal
        # normal of a regular polygon is exactly radial.
        springs.append((i + 1, (-math.cos(t), -math.sin(t)), par['k'] * length))
    supports = [(1, (1, 0, 0))]      # u_x at the bottom node: removes the rigid rotation
    tracked = ('uy_crown', n // 2 + 1, 2)
    return coords, elements, qy, springs, supports, tracked


def beam_geometry(n, par):
    """Nodes 1..n+1 along y = 0 from x = 0 to n Le; element e joins nodes e and e+1. The load of
    element e is -w - a w cos(2 pi (j - 1/2)/m), j = its phase (1..m), as the deck's phase sets."""
    Le, m = par['Le'], int(par['m'])
    coords = [(i * Le, 0.0) for i in range(n + 1)]
    elements = [(e + 1, e + 1, e + 2) for e in range(n)]
    w, a = par['w'], par['a']
    qy = [-w - a * w * math.cos(2.0 * math.pi * ((e % m) + 1 - 0.5) / m) for e in range(n)]
    springs = []
    for i in range(n + 1):
        share = 0.5 if i in (0, n) else 1.0
        springs.append((i + 1, (0.0, 1.0), par['k'] * Le * share))   # the bed pushes up
    supports = [(1, (1, 0, 0))]      # u_x at the first node: the beam is otherwise free
    tracked = ('uy_lift', m // 2 + 1, 2)   # middle of the first wave: lifted off at the end
    return coords, elements, qy, springs, supports, tracked


def consistent_loads(coords, elements, qy):
    """uniarc's fixed_direction_load_vector (qx = 0) summed over the elements: {node: [fx, fy, mz]}."""
    loads = {}
    for (tag, i, j), q in zip(elements, qy):
        (x1, y1), (x2, y2) = coords[i - 1], coords[j - 1]
        dx, dy = x2 - x1, y2 - y1
        length = math.hypot(dx, dy)
        q_normal = (dx / length) * q          # component of (0, q) along the left normal (-s, c)
        for node, sign in ((i, 1.0), (j, -1.0)):
            f = loads.setdefault(node, [0.0, 0.0, 0.0])
            f[1] += q * length / 2.0
            f[2] += sign * q_normal * length ** 2 / 12.0
    return loads


TESTS = ('RelativeNormDispIncr', 'NormUnbalance')


def run(model, n, bonded=False, system='BandGeneral', steps=30, rel_tol=1e-8, max_iter=25, params=None,
        progress=False, test='RelativeNormDispIncr', ground_fixity='sp'):
    import openseespy.opensees as ops

    t0 = time.perf_counter()
    par = dict(DEFAULTS[model])
    par.update(params or {})
    geometry = ring_geometry if model == 'ring' else beam_geometry
    coords, elements, qy, springs, supports, tracked = geometry(n, par)
    n_nodes = len(coords)

    ops.wipe()
    ops.model('basic', '-ndm', 2, '-ndf', 3)
    for i, (x, y) in enumerate(coords):
        ops.node(i + 1, x, y)
    for node, fixity in supports:
        ops.fix(node, *fixity)
    ops.geomTransf('Corotational', 1)
    for tag, i, j in elements:
        ops.element('elasticBeamColumn', tag, i, j, par['EA'], 1.0, par['EI'], 1)

    # One material per distinct lumped stiffness; ENT = elastic, no tension (stiffness in compression,
    # none in tension; its tangent at zero strain is the compressive one, so that every spring starts
    # active, as uniarc's candidates at zero gap).
    materials = {}
    element_tag = len(elements)
    spring_elements = []
    grounds = []
    for node, (nx, ny), stiffness in springs:
        key = round(stiffness, 12)
        if key not in materials:
            materials[key] = len(materials) + 1
            if bonded:
                ops.uniaxialMaterial('Elastic', materials[key], stiffness)
            else:
                ops.uniaxialMaterial('ENT', materials[key], stiffness)
        ground = n_nodes + node
        x, y = coords[node - 1]
        ops.node(ground, x, y)
        if ground_fixity == 'fix':
            ops.fix(ground, 1, 1, 1)
        else:
            grounds.append(ground)
        element_tag += 1
        # Local x = the direction in which the medium pushes; deformation = x . (u_node - u_ground),
        # negative (compression) when the node moves into the medium.
        ops.element('zeroLength', element_tag, ground, node, '-mat', materials[key], '-dir', 1,
                    '-orient', nx, ny, 0.0, -ny, nx, 0.0)
        spring_elements.append((node, nx, ny))

    loads = consistent_loads(coords, elements, qy)
    ops.timeSeries('Linear', 1)
    ops.pattern('Plain', 1, 1)
    for node in sorted(loads):
        ops.load(node, *loads[node])
    load_norm = math.sqrt(sum(v * v for f in loads.values() for v in f))

    if grounds:
        # The ground nodes held by zero prescribed displacements of a constant pattern: `ops.fix` of
        # n nodes costs O(n^2) in OpenSees (8.7 s for 1e4 nodes, 0.02 s this way), which made its model
        # building, not its analysis, dominate the whole run from n = 1e4 on. Plain handles only
        # `fix`; the Transformation handler eliminates these constraints as Plain eliminates fixes.
        ops.timeSeries('Constant', 2)
        ops.pattern('Plain', 2, 2)
        for ground in grounds:
            for dof in (1, 2, 3):
                ops.sp(ground, dof, 0.0)
        ops.constraints('Transformation')
    else:
        ops.constraints('Plain')
    ops.numberer('RCM')
    ops.system(system)
    if test == 'NormUnbalance':
        ops.test('NormUnbalance', rel_tol * load_norm, max_iter)
    else:
        ops.test(test, rel_tol, max_iter)
    ops.algorithm('Newton')
    ops.integrator('LoadControl', 1.0 / steps)
    ops.analysis('Static')
    t1 = time.perf_counter()

    done, iterations, failed = 0, 0, False
    for _ in range(steps):
        if ops.analyze(1) != 0:
            failed = True
            break
        done += 1
        iterations += ops.testIter()
        if progress:
            sys.stdout.write('step %d %d\n' % (done, ops.testIter()))
            sys.stdout.flush()
    t2 = time.perf_counter()

    # Springs in compression at the last converged step (uniarc: candidates with a reaction r > 0).
    in_contact = 0
    for node, nx, ny in spring_elements:
        ux, uy = ops.nodeDisp(node, 1), ops.nodeDisp(node, 2)
        if nx * ux + ny * uy < 0.0:
            in_contact += 1
    name, node, dof = tracked
    result = {
        'program': 'opensees', 'model': model, 'n': n, 'bonded': bonded, 'system': system, 'test': test,
        'steps': done, 'failed': failed, 'lambda': ops.getTime(), 'iterations': iterations,
        'n_springs': len(springs), 'n_contact': in_contact,
        'track_name': name, 'track': ops.nodeDisp(node, dof),
        'build_s': t1 - t0, 'analysis_s': t2 - t1,
    }
    ops.wipe()
    return result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--model', choices=sorted(DEFAULTS), required=True)
    parser.add_argument('--n', type=int, required=True, help='number of elements')
    parser.add_argument('--bonded', action='store_true', help='linear springs both ways (no contact)')
    parser.add_argument('--system', default='BandGeneral', help='OpenSees system (UmfPack, BandGeneral, ...)')
    parser.add_argument('--steps', type=int, default=30)
    parser.add_argument('--test', choices=TESTS, default=TESTS[0],
                        help='convergence test (default RelativeNormDispIncr, tolerance --rel-tol; '
                             'NormUnbalance: tolerance --rel-tol times the norm of the reference load)')
    parser.add_argument('--rel-tol', type=float, default=1e-8)
    parser.add_argument('--ground-fixity', choices=['sp', 'fix'], default='sp',
                        help='how the ground nodes are held: sp (linear build, Transformation handler; '
                             'default) or fix (quadratic build, Plain handler)')
    parser.add_argument('-D', dest='defines', action='append', default=[], metavar='NAME=VALUE',
                        help='override a model parameter')
    args = parser.parse_args(argv)
    params = {}
    for d in args.defines:
        name, value = d.split('=', 1)
        params[name] = float(value)
    result = run(args.model, args.n, args.bonded, args.system, args.steps, args.rel_tol, params=params,
                 progress=True, test=args.test, ground_fixity=args.ground_fixity)
    sys.stdout.write('\n' + json.dumps(result) + '\n')
    sys.stdout.flush()


if __name__ == '__main__':
    main()
