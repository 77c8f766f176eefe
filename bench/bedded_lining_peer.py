#!/usr/bin/env python3
"""A segmental lining on a bedded ring: uniarc's contact LCP against OpenSees with the engineers' loop.

A verification peer of the tangential springs of `*FOUNDATION` (docs/theory.md §3.8), not a test
dependency: it needs openseespy (PyPI; `pip install openseespy`). The ring of
bench/segmental_lining_peer.py (48 Timoshenko elements, five rotational-spring joints and a hinge), with
the realistic lining and ground of the field deck input/segmental_lining_bedded.inp (0.35 m concrete
segments on R = 3 m, Janssen joints, E_s = 60 MPa, H = 15 m, K0 = 0.5), is bedded in the ground, without
supports:

- radial springs of modulus K_R on the outer side, acting in compression only, and tangential springs
  of modulus K_T acting only where the radial one is in contact (`TANGENTIAL=CONTACT`, the default),
  both lumped to the nodes as uniarc lumps them: k = K × (the chord length of a node's two half
  elements);
- the ground pressure of a lining at depth: p = GAMMA (H − y)(K0 + (1 − K0) sin²θ) normal to the ring,
  given at the nodes as forces p × chord toward the centre (the same nodal loads in both programs).

uniarc solves it with `*STATIC` (its contact LCP with Lemke's method). OpenSees solves the linear ring
with the springs of a contact set, and the set is found by the loop of bedded-ring design programs:
drop the radial (and with it the tangential) spring of every node that pulls, put back every node that
moves into the ground, and solve again until the set stops changing. Two different algorithms for the
same complementarity problem: they must find the same set and the same displacements.

It prints the sets' sizes and the largest difference of the nodal displacements and rotations,
relative to the largest of each kind, and exits 1 if the sets differ or a difference exceeds
TOLERANCE (round-off and the 13 digits of uniarc's shape file).

    python3 bench/bedded_lining_peer.py --uniarc build/uniarc

`--dload` gives the ground pressure as uniarc's own `*DLOAD, P` with the depth expression (consistent
loads on every element, also on the hinged and jointed ones: their fixed-end forces are those of the
member released through its joints, docs/theory.md §1.10) and OpenSees the same pressure as
`beamUniform` element loads at each element's midpoint value, and compares the element end forces
N, V, M (`*OUTPUT, FORCES` against OpenSees' `localForce`). uniarc evaluates the expression at each
element's midpoint and takes it uniform there (docs/input.md, `*DLOAD`), so both programs carry the
same loads. uniarc's forces file gives each element of the bed its share of the bed's distributed
reaction as a load on its span (docs/contracts.md, STEM.forces; docs/theory.md §3.1), where OpenSees'
elements see the springs at their nodes only: the script adds that share to OpenSees' forces, computed
here from OpenSees' own spring forces (bed_share_loads) and released through the joints by OpenSees'
own elements (released_end_forces), so both sides give the same quantity and must agree to round-off.

    python3 bench/bedded_lining_peer.py --uniarc build/uniarc --dload

With `--dload` uniarc runs the deck file input/segmental_lining_bedded.inp (the same model written as
an engineer writes it: parameters, the ground pressure as an expression) after checking that it gives
the same element forces as the deck generated here from the constants below (to FILE_TOLERANCE), so
the file is the model that OpenSees is compared with; `--deck FILE` runs another such file.
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

# The ring of segmental_lining_peer.py (its 48 elements, joints and hinge), bedded here with the
# values of the field deck input/segmental_lining_bedded.inp (kN, m; its header gives their sources):
# 0.35 m concrete segments (E = 30 GPa, nu = 0.2) on R = 3 m, Janssen joints over l_t = 0.2 m.
from segmental_lining_peer import N_ELEMENTS, JOINT_NODES, HINGE_NODE  # noqa: E402
R = 3.0
E = 3e7
NU = 0.2
THICKNESS = 0.35
EA = E * THICKNESS
EI = E * THICKNESS ** 3 / 12
GAS = E / (2 * (1 + NU)) * 5 / 6 * THICKNESS
K_JOINT = E * 0.2 ** 2 / 12   # Janssen: E b l_t^2 / 12
K_R = 6e4 / R        # radial subgrade modulus E_s/R (force per length per length)
K_T = K_R / 3.0      # tangential subgrade modulus
GAMMA = 20.0
H = 15.0             # depth of the ring's centre below the surface (y = H at the surface)
K0 = 0.5
TOLERANCE = 1e-9
# --dload: the same loads in both programs (midpoint values) and the same bed's share on the spans
# (bed_share_forces), so round-off: measured 1.6e-13, 6.8e-13, 4.0e-13 of the largest N, V, M (without
# the share on OpenSees' side 5.29e-4, 0.141, 7.59e-3): 1e-9 as for the displacements.
FORCE_TOLERANCE = 1e-9
# the deck file against the generated deck: the same numbers and expressions, so the same arithmetic;
# 1e-12 of the largest of each force leaves only the 13 digits of the forces file.
FILE_TOLERANCE = 1e-12
DECK_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, 'input',
                         'segmental_lining_bedded.inp')

CHORD = 2.0 * R * math.sin(math.pi / N_ELEMENTS)


def angle(i):
    return 2.0 * math.pi * (i - 1) / N_ELEMENTS


def nodal_loads():
    """Inward nodal forces (fx, fy) by node: p(theta) times the chord length a node carries."""
    loads = {}
    for i in range(1, N_ELEMENTS + 1):
        t = angle(i)
        y = R * math.sin(t)
        p = GAMMA * (H - y) * (K0 + (1.0 - K0) * math.sin(t) ** 2)
        loads[i] = (-p * CHORD * math.cos(t), -p * CHORD * math.sin(t))
    return loads


def pressure(t, y):
    """The ground pressure at angle t and height y (force per length, toward the centre)."""
    return GAMMA * (H - y) * (K0 + (1.0 - K0) * math.sin(t) ** 2)


def deck(element_loads=False):
    loads = nodal_loads()
    if element_loads:
        return deck().split('*CLOAD')[0] + (
            f'*DLOAD, XC=0, YC=0\nring, P, {GAMMA!r}*({H!r} - y)*({K0!r} + (1 - {K0!r})*sind(theta)**2)\n'
            '*OUTPUT, FORCES\n*STATIC\n')
    return f"""** Bedded segmental lining (bench/bedded_lining_peer.py)
*SECTION, NAME=lining, STIFFNESS
{EA!r}, {EI!r}, {GAS!r}
*RING, ELSET=ring, SECTION=lining, TYPE=TIMOSHENKO
0, 0, {R!r}, {N_ELEMENTS}
*RELEASE
{chr(10).join(f'{j}, 1, {K_JOINT!r}' for j in JOINT_NODES)}
{HINGE_NODE}, 1
*FOUNDATION, ELSET=ring, MODULUS={K_R!r}, SIDE=OUTER, KT={K_T!r}, NAME=ground
*CLOAD
{chr(10).join(f'{i}, FX, {fx!r}' + chr(10) + f'{i}, FY, {fy!r}' for i, (fx, fy) in loads.items())}
*STATIC
"""


def uniarc_solution(uniarc):
    """Nodal (ux, uy, rz) and contact reaction by node label from uniarc's shape file."""
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, 'lining.inp')
        with open(path, 'w') as f:
            f.write(deck())
        subprocess.run([uniarc, path, '-o', os.path.join(work, 'out'), '-q'], check=True)
        displacement, reaction = {}, {}
        with open(os.path.join(work, 'out', 'lining.shape')) as f:
            for line in f:
                if line.startswith('#') or not line.strip() or line.startswith('step'):
                    continue
                words = line.split()
                displacement[int(words[2])] = tuple(float(x) for x in words[5:8])
                reaction[int(words[2])] = float(words[10])
        return displacement, reaction


def uniarc_forces(uniarc, deck_file=None):
    """Element end forces (N, V, M at start, N, V, M at end) by element label: the *DLOAD deck
    generated here, or the deck file `deck_file` as it is."""
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, 'lining.inp')
        if deck_file is None:
            with open(path, 'w') as f:
                f.write(deck(element_loads=True))
        else:
            shutil.copyfile(deck_file, path)
        subprocess.run([uniarc, path, '-o', os.path.join(work, 'out'), '-q'], check=True)
        forces = {}
        with open(os.path.join(work, 'out', 'lining.forces')) as f:
            for line in f:
                if line.startswith('#') or not line.strip() or line.startswith('step'):
                    continue
                words = line.split()
                forces[int(words[2])] = [float(x) for x in words[5:11]]
        return forces


def opensees_solve(in_contact, element_loads=False):
    """The linear ring with radial and tangential springs at the nodes of `in_contact`; with
    `element_loads` the pressure as beamUniform loads (midpoint value), else the nodal loads."""
    import openseespy.opensees as ops
    ops.wipe()
    ops.model('basic', '-ndm', 2, '-ndf', 3)
    for i in range(1, N_ELEMENTS + 1):
        ops.node(i, R * math.cos(angle(i)), R * math.sin(angle(i)))
    ops.geomTransf('Linear', 1)
    ops.uniaxialMaterial('Elastic', 1, K_JOINT)
    ops.uniaxialMaterial('Elastic', 2, K_R * CHORD)
    ops.uniaxialMaterial('Elastic', 3, K_T * CHORD)
    released = JOINT_NODES + [HINGE_NODE]
    for j in released:
        ops.node(1000 + j, *ops.nodeCoord(j))
        ops.equalDOF(j, 1000 + j, 1, 2)
    for j in JOINT_NODES:
        ops.element('zeroLength', 2000 + j, j, 1000 + j, '-mat', 1, '-dir', 3)
    for i in range(1, N_ELEMENTS + 1):
        start = 1000 + i if i in released else i
        end = i % N_ELEMENTS + 1
        ops.element('ElasticTimoshenkoBeam', i, start, end, 1.0, 1.0, EA, EI, GAS, 1)
    for i in in_contact:
        t = angle(i)
        ops.node(3000 + i, *ops.nodeCoord(i))
        ops.fix(3000 + i, 1, 1, 1)
        # local x radial (outward), local y tangential: springs in both
        ops.element('zeroLength', 4000 + i, 3000 + i, i, '-mat', 2, 3, '-dir', 1, 2,
                    '-orient', math.cos(t), math.sin(t), 0.0, -math.sin(t), math.cos(t), 0.0)
    ops.timeSeries('Linear', 1)
    ops.pattern('Plain', 1, 1)
    if element_loads:
        for i in range(1, N_ELEMENTS + 1):
            # midpoint of element i: angle between its nodes, on the chord (radius R cos(pi/n));
            # beamUniform's transverse load acts along the local y (left normal: toward the centre)
            t = angle(i) + math.pi / N_ELEMENTS
            ops.eleLoad('-ele', i, '-type', '-beamUniform', pressure(t, R * math.cos(math.pi / N_ELEMENTS) * math.sin(t)), 0.0)
    else:
        for i, (fx, fy) in nodal_loads().items():
            ops.load(i, fx, fy, 0.0)
    ops.system('FullGeneral')
    ops.numberer('Plain')
    ops.constraints('Transformation')
    ops.integrator('LoadControl', 1.0)
    ops.algorithm('Linear')
    ops.analysis('Static')
    if ops.analyze(1) != 0:
        raise RuntimeError('OpenSees analysis failed')
    if element_loads:
        # localForce: the forces on the element (axial, shear, moment at each end) in its frame, and
        # the radial springs' forces (basicForce: k times the node's outward displacement; on the node
        # it acts along -x of the spring, toward the centre), for the bed's share (bed_share_forces)
        opensees_solve.local_forces = {i: list(ops.eleResponse(i, 'localForce'))
                                       for i in range(1, N_ELEMENTS + 1)}
        opensees_solve.springs = {i: (ops.eleResponse(4000 + i, 'basicForce')[0],
                                      (math.cos(angle(i)), math.sin(angle(i)))) for i in in_contact}
    return {i: tuple(ops.nodeDisp(i)) for i in range(1, N_ELEMENTS + 1)}


def bed_share_loads(springs):
    """The consistent end loads (Fx1, Fy1, M1, Fx2, Fy2, M2 in the element's local frame, by element)
    of the bed's distributed reaction that each element carries on its span, as uniarc's forces file
    reports it (docs/contracts.md, STEM.forces; docs/theory.md §3.1): at every node the pressure of
    its radial spring, the spring's force over the length it was lumped from (CHORD: k = K_R CHORD),
    acting on the node along the force's direction, varying linearly along the element; the loads of
    a linearly varying load q1 -> q2 on a beam clamped at both ends (Przemieniecki 1968, Theory of
    Matrix Structural Analysis, §5.4):
        axial   F1 = h (2 q1 + q2)/6,     F2 = h (q1 + 2 q2)/6,
        normal  F1 = h (7 q1 + 3 q2)/20,  F2 = h (3 q1 + 7 q2)/20,
                M1 = h^2 (3 q1 + 2 q2)/60,  M2 = -h^2 (2 q1 + 3 q2)/60.
    `springs`: by node in contact, (basic force of the radial spring, its local x (outward)); a node
    without contact carries no pressure. Only the radial springs: the tangential ones are point
    supports in uniarc's forces too (docs/contracts.md)."""
    load = {i: (0.0, 0.0) for i in range(1, N_ELEMENTS + 1)}
    for i, (force, (dx, dy)) in springs.items():
        load[i] = (-force * dx / CHORD, -force * dy / CHORD)
    loads = {}
    for e in range(1, N_ELEMENTS + 1):
        a, b = e, e % N_ELEMENTS + 1
        xa, ya = R * math.cos(angle(a)), R * math.sin(angle(a))
        xb, yb = R * math.cos(angle(b)), R * math.sin(angle(b))
        h = math.hypot(xb - xa, yb - ya)
        t = ((xb - xa) / h, (yb - ya) / h)
        n = (-t[1], t[0])
        qt = [load[k][0] * t[0] + load[k][1] * t[1] for k in (a, b)]
        qn = [load[k][0] * n[0] + load[k][1] * n[1] for k in (a, b)]
        loads[e] = [h * (2 * qt[0] + qt[1]) / 6, h * (7 * qn[0] + 3 * qn[1]) / 20,
                    h * h * (3 * qn[0] + 2 * qn[1]) / 60,
                    h * (qt[0] + 2 * qt[1]) / 6, h * (3 * qn[0] + 7 * qn[1]) / 20,
                    -h * h * (2 * qn[0] + 3 * qn[1]) / 60]
    return loads


def released_end_forces(loads):
    """The end forces (localForce, by element) of each element held at its nodes, through its joints,
    under the clamped member's end loads `loads` (bed_share_loads): OpenSees' own ring, joints and
    hinge as in opensees_solve (the joint nodes at end 1 of the elements that start there, the
    zeroLength rotational springs, none at the hinge) with every ring node fixed and each joint node
    held in translation and free to turn, loaded by the clamped end moment M1 of the element that
    starts there (the loads at held degrees of freedom do nothing).
    The joint node's equilibrium, (K u)_r + k_j theta = M1, is that of the member under its span load
    with its end released through the joint ((K u)_r - M1 + k_j theta = 0), so K u - loads are the
    fixed-end forces of the member with its releases: uniarc's span_release (docs/theory.md §1.10,
    M = Kj F Mf), computed here by OpenSees' element. Zero for the elements without joints."""
    import openseespy.opensees as ops
    ops.wipe()
    ops.model('basic', '-ndm', 2, '-ndf', 3)
    for i in range(1, N_ELEMENTS + 1):
        ops.node(i, R * math.cos(angle(i)), R * math.sin(angle(i)))
        ops.fix(i, 1, 1, 1)
    ops.geomTransf('Linear', 1)
    ops.uniaxialMaterial('Elastic', 1, K_JOINT)
    released = JOINT_NODES + [HINGE_NODE]
    for j in released:
        ops.node(1000 + j, *ops.nodeCoord(j))
        ops.fix(1000 + j, 1, 1, 0)
    for j in JOINT_NODES:
        ops.element('zeroLength', 2000 + j, j, 1000 + j, '-mat', 1, '-dir', 3)
    for i in range(1, N_ELEMENTS + 1):
        start = 1000 + i if i in released else i
        ops.element('ElasticTimoshenkoBeam', i, start, i % N_ELEMENTS + 1, 1.0, 1.0, EA, EI, GAS, 1)
    ops.timeSeries('Linear', 1)
    ops.pattern('Plain', 1, 1)
    for j in released:
        ops.load(1000 + j, 0.0, 0.0, loads[j][2])
    ops.system('FullGeneral')
    ops.numberer('Plain')
    ops.constraints('Transformation')
    ops.integrator('LoadControl', 1.0)
    ops.algorithm('Linear')
    ops.analysis('Static')
    if ops.analyze(1) != 0:
        raise RuntimeError('OpenSees analysis of the released end forces failed')
    return {i: list(ops.eleResponse(i, 'localForce')) for i in range(1, N_ELEMENTS + 1)}


def section_forces(local):
    """uniarc's section forces (N, V, M at start, at end) from OpenSees' localForce (the forces on the
    element at its ends, in its frame): N tension positive, V = dM/ds, M = EI kappa (docs/contracts.md)."""
    return [-local[0], local[1], -local[2], local[3], -local[4], local[5]]


def bed_share_forces():
    """The element forces of the last opensees_solve with element loads, with each element's share of
    the bed's distributed reaction on its span (uniarc's STEM.forces, docs/contracts.md): localForce
    minus the share's consistent loads released through the element's joints (bed_share_loads,
    released_end_forces); and, for comparison, without the share (OpenSees' elements see nodal
    springs only). Both by element, as section forces."""
    local = opensees_solve.local_forces
    loads = bed_share_loads(opensees_solve.springs)
    held = released_end_forces(loads)
    with_share = {i: section_forces([local[i][k] - (loads[i][k] - held[i][k]) for k in range(6)]) for i in local}
    return with_share, {i: section_forces(local[i]) for i in local}


def opensees_solution(element_loads=False):
    """The engineers' loop: start with every node in contact, drop the nodes whose radial spring
    pulls (the ring moved inward there), put back the free nodes that move into the ground."""
    in_contact = set(range(1, N_ELEMENTS + 1))
    for _ in range(100):
        displacement = opensees_solve(sorted(in_contact), element_loads)
        outward = {i: displacement[i][0] * math.cos(angle(i)) + displacement[i][1] * math.sin(angle(i))
                   for i in displacement}
        new = {i for i in outward if outward[i] > 0.0}
        if new == in_contact:
            return displacement, in_contact
        in_contact = new
    raise RuntimeError('the contact set did not settle')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--dload', action='store_true', help='the pressure as element loads; compare N, V, M')
    parser.add_argument('--deck', default=DECK_FILE,
                        help='with --dload: the deck file uniarc runs (default input/segmental_lining_bedded.inp)')
    args = parser.parse_args()
    if args.dload:
        return compare_forces(args.uniarc, args.deck)
    ours, reaction = uniarc_solution(args.uniarc)
    peer, peer_contact = opensees_solution()
    our_contact = {i for i in reaction if reaction[i] > 0.0}
    print(f'nodes in contact: uniarc {len(our_contact)}, OpenSees loop {len(peer_contact)}'
          f' ({"the same" if our_contact == peer_contact else "DIFFERENT"})')
    worst = []
    for k, name in enumerate(['translation', 'rotation']):
        components = [0, 1] if k == 0 else [2]
        scale = max(abs(peer[i][c]) for i in peer for c in components)
        difference = max(abs(ours[i][c] - peer[i][c]) for i in peer for c in components)
        worst.append(difference / scale)
        print(f'{name}: largest |uniarc - OpenSees| = {difference:.3e}, relative to the largest '
              f'{scale:.6e}: {difference / scale:.2e}')
    return 0 if our_contact == peer_contact and max(worst) <= TOLERANCE else 1


def compare_forces(uniarc, deck_file):
    """The --dload case: element end forces of uniarc's *DLOAD (the deck file, once it is checked to
    be the generated model) against OpenSees' beamUniform."""
    generated = uniarc_forces(uniarc)
    ours = uniarc_forces(uniarc, deck_file)
    if sorted(ours) != sorted(generated):
        print(f'{deck_file}: elements {len(ours)}, the generated deck {len(generated)}: not the same model')
        return 1
    for k, name in [(0, 'N'), (1, 'V'), (2, 'M')]:
        scale = max(abs(generated[i][c]) for i in generated for c in (k, k + 3))
        difference = max(abs(ours[i][c] - generated[i][c]) for i in generated for c in (k, k + 3))
        print(f'{name}: deck file against the generated deck: {difference:.3e}, relative {difference / scale:.2e}')
        if difference > FILE_TOLERANCE * scale:
            print(f'{deck_file} is not the model of this script (above {FILE_TOLERANCE:g})')
            return 1
    opensees_solution(element_loads=True)
    peer, nodal = bed_share_forces()
    print(f'radial springs in contact: OpenSees loop {len(opensees_solve.springs)}')
    status = 0
    for k, name in [(0, 'N'), (1, 'V'), (2, 'M')]:
        scale = max(abs(peer[i][c]) for i in peer for c in (k, k + 3))
        difference = max(abs(ours[i][c] - peer[i][c]) for i in peer for c in (k, k + 3))
        share = max(abs(nodal[i][c] - peer[i][c]) for i in peer for c in (k, k + 3))
        print(f'{name}: largest |uniarc - OpenSees| = {difference:.3e}, relative to the largest {scale:.6e}: '
              f'{difference / scale:.2e} (the bed\'s share changes OpenSees\' {name} by {share / scale:.2e})')
        status = status if difference / scale <= FORCE_TOLERANCE else 1
    return status


if __name__ == '__main__':
    sys.exit(main())
