#!/usr/bin/env python3
"""A segmental lining ring of Timoshenko beams with rotational-spring joints: uniarc against OpenSees.

A verification peer (docs/theory.md §1.10), not a test dependency: it needs openseespy (PyPI; `pip install
openseespy`). The same ring is built in both programs from the parameters below and solved linearly:

- a closed ring of radius R, N_ELEMENTS straight Timoshenko elements (EA, EI, kGA), six segments joined at
  JOINT_NODES by linear rotational springs of stiffness K_JOINT, and one hinge (HINGE_NODE);
- uniarc: `*RING, TYPE=TIMOSHENKO` and `*RELEASE` on the element that starts at each joint node (end 1);
- OpenSees: `ElasticTimoshenkoBeam` elements (E = G = 1, A = EA, Iz = EI, Avy = kGA) on `Linear`
  transformations; at each joint a second node at the same point starts the next segment, tied to the
  ring node by `equalDOF` in x and y and by a `zeroLength` element with an `Elastic` material of
  stiffness K_JOINT in the rotation (a hinge: no rotational element at all);
- the bottom node is clamped; a downward load P at the crown and a horizontal P/2 at the springing
  (theta = 0).

It prints the largest difference of the nodal displacements and rotations, relative to the largest of
each kind, and exits 1 above TOLERANCE. Both element laws are exact for nodal loads, so only round-off
(and the 13 digits of uniarc's shape file) separates them.

A second case gives the five joints a moment limit MY (`*RELEASE, MY=`, docs/theory.md §1.11) and traces
the ring's nonlinear path in both programs: Euler-Bernoulli elements (uniarc `TYPE=BEAM`, OpenSees
`elasticBeamColumn`) on corotational transformations, the joints elastic-perfectly plastic (OpenSees:
`zeroLength` with an `ElasticPP` material, yield rotation MY/k), the same loads raised to P in
PLASTIC_STEPS equal load steps (two joints reach MY) and taken off again (uniarc: a second `*STEP` with
the opposite loads; OpenSees: LoadControl back to 0 in 100 steps, as its Newton iteration from the zero
tangent of a yielded ElasticPP does not converge on larger unloading steps). It compares the loaded
and the unloaded (residual) states: nodal displacements, and the joints' moments (uniarc's STEM.forces,
OpenSees' zeroLength forces); both laws and transformations are the same theory, so the Newton
tolerances (1e-12) and round-off separate them.

    python3 bench/segmental_lining_peer.py --uniarc build/uniarc
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

R = 3.0
EA = 1.0e5
EI = 50.0
GAS = 4.0e3
K_JOINT = 200.0
P = 10.0
N_ELEMENTS = 48
# nodes of the ring (1 at theta = 0, counter-clockwise, 7.5 degrees apart)
JOINT_NODES = [3, 11, 19, 27, 43]   # 15, 75, 135, 195, 315 degrees: springs
HINGE_NODE = 35                     # 255 degrees: a hinge
BOTTOM_NODE = 37                    # 270 degrees: clamped
CROWN_NODE = 13                     # 90 degrees: load -P in y
SIDE_NODE = 1                       # 0 degrees: load P/2 in x
TOLERANCE = 1e-9
# the moment-limited case: P raised in PLASTIC_STEPS equal steps, joints with MY (two of them reach it)
P_PLASTIC = 1.0
MY = 0.72
PLASTIC_STEPS = 20

DECK = f"""** Segmental lining ring: Timoshenko elements, spring joints and a hinge (bench/segmental_lining_peer.py)
*SECTION, NAME=lining, STIFFNESS
{EA!r}, {EI!r}, {GAS!r}
*RING, ELSET=ring, SECTION=lining, TYPE=TIMOSHENKO
0, 0, {R!r}, {N_ELEMENTS}
*RELEASE
{chr(10).join(f'{j}, 1, {K_JOINT!r}' for j in JOINT_NODES)}
{HINGE_NODE}, 1
*BOUNDARY
{BOTTOM_NODE}, FIXED
*CLOAD
{CROWN_NODE}, FY, {-P!r}
{SIDE_NODE}, FX, {P / 2!r}
*STATIC
"""


def uniarc_displacements(uniarc):
    """Nodal (ux, uy, rz) by node label from uniarc's shape file."""
    with tempfile.TemporaryDirectory() as work:
        deck = os.path.join(work, 'lining.inp')
        with open(deck, 'w') as f:
            f.write(DECK)
        subprocess.run([uniarc, deck, '-o', os.path.join(work, 'out'), '-q'], check=True)
        result = {}
        with open(os.path.join(work, 'out', 'lining.shape')) as f:
            for line in f:
                words = line.split()
                if line.startswith('#') or not words or words[0] == 'step':   # provenance, blank, names
                    continue
                result[int(words[2])] = tuple(float(x) for x in words[5:8])
        return result


def opensees_displacements():
    """Nodal (ux, uy, rz) by ring node from the OpenSees model."""
    import openseespy.opensees as ops
    ops.wipe()
    ops.model('basic', '-ndm', 2, '-ndf', 3)
    for i in range(1, N_ELEMENTS + 1):
        angle = 2.0 * math.pi * (i - 1) / N_ELEMENTS
        ops.node(i, R * math.cos(angle), R * math.sin(angle))
    ops.geomTransf('Linear', 1)
    ops.uniaxialMaterial('Elastic', 1, K_JOINT)
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
    ops.fix(BOTTOM_NODE, 1, 1, 1)
    ops.timeSeries('Linear', 1)
    ops.pattern('Plain', 1, 1)
    ops.load(CROWN_NODE, 0.0, -P, 0.0)
    ops.load(SIDE_NODE, P / 2, 0.0, 0.0)
    ops.system('FullGeneral')
    ops.numberer('Plain')
    ops.constraints('Transformation')
    ops.integrator('LoadControl', 1.0)
    ops.algorithm('Linear')
    ops.analysis('Static')
    if ops.analyze(1) != 0:
        raise RuntimeError('OpenSees analysis failed')
    return {i: tuple(ops.nodeDisp(i)) for i in range(1, N_ELEMENTS + 1)}


def plastic_deck():
    """The moment-limited case as a uniarc deck: loading, then unloading, two analysis steps."""
    loads = [f'{CROWN_NODE}, FY, {-P_PLASTIC!r}\n{SIDE_NODE}, FX, {P_PLASTIC / 2!r}',
             f'{CROWN_NODE}, FY, {P_PLASTIC!r}\n{SIDE_NODE}, FX, {-P_PLASTIC / 2!r}']
    steps = ''.join(f"""*STEP
*CLOAD
{load}
*PATH, CONTROL=LOAD
increment = {1.0 / PLASTIC_STEPS!r}
max_increment = 1
lambda_max = 1
tolerance = 1e-12
*END STEP
""" for load in loads)
    return f"""** Segmental lining ring with moment-limited joints, loaded and unloaded (bench/segmental_lining_peer.py)
*SECTION, NAME=lining, STIFFNESS
{EA!r}, {EI!r}
*RING, ELSET=ring, SECTION=lining
0, 0, {R!r}, {N_ELEMENTS}
*RELEASE, MY={MY!r}
{chr(10).join(f'{j}, 1, {K_JOINT!r}' for j in JOINT_NODES)}
*RELEASE
{HINGE_NODE}, 1
*BOUNDARY
{BOTTOM_NODE}, FIXED
*OUTPUT, FORCES
{PLASTIC_STEPS}
{steps}"""


def read_blocks(path, columns):
    """The rows of a uniarc table by step: {step: {label: values}}, label the third column."""
    blocks = {}
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words or line.startswith('#') or words[0] == 'step':
                continue
            blocks.setdefault(int(words[0]), {})[int(words[2])] = tuple(float(words[c]) for c in columns)
    return blocks


def uniarc_plastic_states(uniarc):
    """(loaded, unloaded): each ({node: (ux, uy, rz)}, {joint node: moment}) from uniarc's path. The
    joint's moment is M_start of the element starting at the joint node (its released end 1)."""
    with tempfile.TemporaryDirectory() as work:
        deck = os.path.join(work, 'plastic.inp')
        with open(deck, 'w') as f:
            f.write(plastic_deck())
        subprocess.run([uniarc, deck, '-o', os.path.join(work, 'out'), '-q'], check=True)
        shapes = read_blocks(os.path.join(work, 'out', 'plastic.shape'), [5, 6, 7])
        forces = read_blocks(os.path.join(work, 'out', 'plastic.forces'), [7])
    states = []
    for step in (PLASTIC_STEPS, max(shapes)):
        states.append((shapes[step], {j: forces[step][j][0] for j in JOINT_NODES}))
    return states


def opensees_plastic_states():
    """The same as uniarc_plastic_states from OpenSees (the zeroLength moment has the opposite sign of
    uniarc's M_start: it is the force on the ring node)."""
    import openseespy.opensees as ops
    ops.wipe()
    ops.model('basic', '-ndm', 2, '-ndf', 3)
    for i in range(1, N_ELEMENTS + 1):
        angle = 2.0 * math.pi * (i - 1) / N_ELEMENTS
        ops.node(i, R * math.cos(angle), R * math.sin(angle))
    ops.geomTransf('Corotational', 1)
    ops.uniaxialMaterial('ElasticPP', 1, K_JOINT, MY / K_JOINT)
    released = JOINT_NODES + [HINGE_NODE]
    for j in released:
        ops.node(1000 + j, *ops.nodeCoord(j))
        ops.equalDOF(j, 1000 + j, 1, 2)
    for j in JOINT_NODES:
        ops.element('zeroLength', 2000 + j, j, 1000 + j, '-mat', 1, '-dir', 3)
    for i in range(1, N_ELEMENTS + 1):
        start = 1000 + i if i in released else i
        ops.element('elasticBeamColumn', i, start, i % N_ELEMENTS + 1, EA, 1.0, EI, 1)
    ops.fix(BOTTOM_NODE, 1, 1, 1)
    ops.timeSeries('Linear', 1)
    ops.pattern('Plain', 1, 1)
    ops.load(CROWN_NODE, 0.0, -P_PLASTIC, 0.0)
    ops.load(SIDE_NODE, P_PLASTIC / 2, 0.0, 0.0)
    ops.system('FullGeneral')
    ops.numberer('Plain')
    ops.constraints('Transformation')
    ops.test('NormDispIncr', 1e-12, 100)
    ops.algorithm('Newton')
    ops.integrator('LoadControl', 1.0 / PLASTIC_STEPS)
    ops.analysis('Static')
    states = []
    for increment, steps in ((1.0 / PLASTIC_STEPS, PLASTIC_STEPS), (-0.01, 100)):
        ops.integrator('LoadControl', increment)
        if ops.analyze(steps) != 0:
            raise RuntimeError('OpenSees analysis failed')
        states.append(({i: tuple(ops.nodeDisp(i)) for i in range(1, N_ELEMENTS + 1)},
                       {j: -ops.eleForce(2000 + j)[2] for j in JOINT_NODES}))
    return states


def compare(title, ours, peer):
    """Print the largest relative differences of translations and rotations; return the largest."""
    worst = []
    for k, name in enumerate(['translation', 'rotation']):
        components = [0, 1] if k == 0 else [2]
        scale = max(abs(peer[i][c]) for i in peer for c in components)
        difference = max(abs(ours[i][c] - peer[i][c]) for i in peer for c in components)
        worst.append(difference / scale)
        print(f'{title}: {name}: largest |uniarc - OpenSees| = {difference:.3e}, relative to the largest '
              f'{scale:.6e}: {difference / scale:.2e}')
    return max(worst)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    args = parser.parse_args()
    ours = uniarc_displacements(args.uniarc)
    peer = opensees_displacements()
    worst = []
    for k, name in enumerate(['translation', 'rotation']):
        components = [0, 1] if k == 0 else [2]
        scale = max(abs(peer[i][c]) for i in peer for c in components)
        difference = max(abs(ours[i][c] - peer[i][c]) for i in peer for c in components)
        worst.append(difference / scale)
        print(f'{name}: largest |uniarc - OpenSees| = {difference:.3e}, relative to the largest '
              f'{scale:.6e}: {difference / scale:.2e}')
    crown = ours[CROWN_NODE]
    print(f'crown: uniarc uy = {crown[1]:.12e}, OpenSees uy = {peer[CROWN_NODE][1]:.12e}')
    for title, (our_nodes, our_moments), (peer_nodes, peer_moments) in zip(
            ['loaded (MY)', 'unloaded (MY)'], uniarc_plastic_states(args.uniarc), opensees_plastic_states()):
        worst.append(compare(title, our_nodes, peer_nodes))
        difference = max(abs(our_moments[j] - peer_moments[j]) for j in JOINT_NODES)
        worst.append(difference / MY)
        print(f'{title}: joint moments (uniarc / OpenSees): ' +
              ', '.join(f'{our_moments[j]:.10f} / {peer_moments[j]:.10f}' for j in JOINT_NODES) +
              f'; largest difference {difference:.2e} ({difference / MY:.2e} of MY = {MY})')
    return 0 if max(worst) <= TOLERANCE else 1


if __name__ == '__main__':
    sys.exit(main())
