#!/usr/bin/env python3
"""Run uniarc on a deck with `*OUTPUT, VTK` and read every ParaView file it writes with VTK's own readers.

A snapshot is written twice, as XML PolyData `STEM_NNNN.vtp` and as legacy `STEM_NNNN.vtk` (DATASET
POLYDATA); `STEM.pvd` lists the `.vtp` files with the step number as timestep.

Usage (one CTest per call):
  vtk_check.py --uniarc BIN --deck DECK --out DIR [--define NAME=VALUE]...
               --every N                           # the snapshot interval the deck asks for
               [--linear]                          # a linear analysis (forces on the initial chord)
               [--expect-cell NAME=VALUE:ATOL]...  # every cell of array NAME equals lambda*VALUE
               [--expect-contact]                  # some snapshot has a positive contact reaction
               [--load LABEL:FX,FY,MZ]...          # the deck's reference load on node LABEL (all of
                                                   # it: with --load the nodal equilibrium is checked)
               [--force-tolerance TOL]             # the deck's force_tolerance (default 1e-8)
               [--no-vtk]                          # the deck has no *OUTPUT: no VTK file at all

The `vtk` Python module (Debian: python3-vtk9, installed by scripts/install_deps.sh) is required: without
it the check fails. What is checked:
- the snapshots are those of the shape file's rule with EVERY: the first step, every N-th step, the last
  step of the path file, no more and no fewer, each as .vtp and .vtk; no .vtu and no .part file;
- STEM.pvd is XML (parsed as ParaView's collection reader does: a VTKFile of type Collection whose
  DataSet elements give a timestep and a file): it lists the .vtp snapshots in order, with the step
  number as timestep (strictly increasing);
- every .vtp read by vtkXMLPolyDataReader and every .vtk by vtkPolyDataReader (told to read all scalar,
  vector and field arrays), without an error or warning of VTK: PolyData of n points (the shape file's
  nodes) and m line cells of two distinct points, no verts, polys or strips, every point on a line;
  exactly the arrays of POINT_ARRAYS, CELL_ARRAYS and FIELD_ARRAYS below, of the stated type, number of
  components and of tuples (field data: one tuple), every number finite; the two files hold the same
  numbers;
- field data: `step` is the step of the pvd and the file name, `lambda` the path file's lambda of it;
- point data against the shape file where it has the step (always the first and the last): the points
  are x0 + u (z = 0), `displacement` (u_x, u_y, 0), `rotation` rz, `contact_reaction` the reaction
  column, `node_label` the node column; the sum of contact_reaction is the path file's reaction_sum;
- cell data: `bending_moment` is the mean of the end moments, `shear_force` V = dM/ds times the chord
  length (the current one; the initial one, x - u, for --linear) is bending_moment_end - bending_moment_start,
  `element_label` positive and distinct; --expect-cell closed forms;
- with --load: nodal equilibrium of N, V and M with lambda times the --load values, at every node
  without a contact reaction, in every free direction (see check_equilibrium);
- vtkTubeFilter (ParaView's Tube) applied to every snapshot, .vtp and .vtk, gives one triangle strip per
  side and line, carrying the cell arrays (colouring the tubes by N or M works).
"""
import argparse
import glob
import math
import os
import sys
import xml.etree.ElementTree as ElementTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uniarc_check import read_table, run_uniarc  # noqa: E402

# name: (components, integer type)
POINT_ARRAYS = {'displacement': (3, False), 'rotation': (1, False), 'contact_reaction': (1, False),
                'node_label': (1, True)}
CELL_ARRAYS = {'axial_force': (1, False), 'shear_force': (1, False), 'bending_moment': (1, False),
               'bending_moment_start': (1, False), 'bending_moment_end': (1, False),
               'element_label': (1, True)}
FIELD_ARRAYS = {'lambda': (1, False), 'step': (1, True)}

# Every real is written with 13 significant digits (format es21.12e3), so two numbers that are the
# same quantity written by two files (or a sum or product of written numbers) agree to a few units of
# 1e-12 of the largest magnitude involved.
ROUND_OFF = 1e-11

# Sides of the tubes of the Tube filter check (any number >= 3).
TUBE_SIDES = 6

INSTALL_HINT = 'the vtk Python module is required (Debian: python3-vtk9, installed by scripts/install_deps.sh)'


class Problems(list):
    def check(self, condition, message):
        if not condition:
            self.append(message)
        return condition


class Vtk:
    """The VTK classes the check uses, and VTK's messages captured instead of printed."""

    def __init__(self):
        from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow, VTK_INT, VTK_DOUBLE
        from vtkmodules.vtkCommonDataModel import vtkPolyData, VTK_LINE
        from vtkmodules.vtkIOLegacy import vtkPolyDataReader
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
        from vtkmodules.vtkFiltersCore import vtkTubeFilter
        from vtkmodules.vtkCommonCore import vtkVersion
        self.version = vtkVersion.GetVTKVersion()
        self.messages = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.messages)
        self.seen = 0   # characters of the window's text already taken
        self.int_type, self.double_type, self.line_type = VTK_INT, VTK_DOUBLE, VTK_LINE
        self.PolyData, self.LegacyReader, self.XmlReader, self.Tube = (vtkPolyData, vtkPolyDataReader,
                                                                       vtkXMLPolyDataReader, vtkTubeFilter)

    def take_messages(self):
        text = self.messages.GetOutput()
        new, self.seen = text[self.seen:], len(text)
        return new.strip()


def read_snapshot(vtk, path, problems):
    """Read one .vtp or .vtk file with VTK's reader; return the vtkPolyData, or None."""
    where = os.path.basename(path)
    if path.endswith('.vtp'):
        reader = vtk.XmlReader()
    else:
        reader = vtk.LegacyReader()
        # The legacy reader keeps only the first SCALARS (and VECTORS, ...) array of each attribute
        # set unless told to read them all.
        for switch in ('Scalars', 'Vectors', 'Normals', 'Tensors', 'ColorScalars', 'TCoords', 'Fields'):
            getattr(reader, f'ReadAll{switch}On')()
    reader.SetFileName(path)
    reader.Update()
    messages = vtk.take_messages()
    problems.check(not messages, f'{where}: VTK reports: {messages[:300]}')
    problems.check(reader.GetErrorCode() == 0, f'{where}: reader error code {reader.GetErrorCode()}')
    data = reader.GetOutput()
    if not problems.check(isinstance(data, vtk.PolyData) and data.GetNumberOfPoints() > 0,
                          f'{where}: VTK reads no PolyData with points'):
        return None
    return data


def arrays_of(attributes):
    """{name: (vtk data type, components, [tuples])} of a vtkPointData, vtkCellData or vtkFieldData."""
    arrays = {}
    for k in range(attributes.GetNumberOfArrays()):
        array = attributes.GetAbstractArray(k)
        arrays[array.GetName()] = (array.GetDataType(), array.GetNumberOfComponents(),
                                   [array.GetTuple(i) for i in range(array.GetNumberOfTuples())])
    return arrays


def contents(vtk, data, where, problems):
    """Points, lines and arrays of a snapshot as plain Python values, with their structure checked."""
    n, m = data.GetNumberOfPoints(), data.GetNumberOfCells()
    problems.check(data.GetNumberOfLines() == m and m > 0, f'{where}: {m} cells, of them {data.GetNumberOfLines()} lines')
    problems.check(data.GetNumberOfVerts() == data.GetNumberOfPolys() == data.GetNumberOfStrips() == 0,
                   f'{where}: verts, polys or strips besides the lines')
    points = [data.GetPoint(i) for i in range(n)]
    lines = []
    for c in range(m):
        cell = data.GetCell(c)
        ids = [cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]
        problems.check(cell.GetCellType() == vtk.line_type and len(ids) == 2 and ids[0] != ids[1]
                       and all(0 <= i < n for i in ids), f'{where}: cell {c} is not a line of two distinct points: {ids}')
        lines.append(tuple(ids))
    problems.check({i for line in lines for i in line} == set(range(n)), f'{where}: a point on no line')
    result = {'points': points, 'lines': lines}
    for group, attributes, expected, size in (('point', data.GetPointData(), POINT_ARRAYS, n),
                                              ('cell', data.GetCellData(), CELL_ARRAYS, m),
                                              ('field', data.GetFieldData(), FIELD_ARRAYS, 1)):
        arrays = arrays_of(attributes)
        problems.check(set(arrays) == set(expected), f'{where}: {group} arrays {sorted(arrays)}, expected {sorted(expected)}')
        result[group] = {}
        for name, (components, integer) in expected.items():
            if name not in arrays:
                continue
            kind, got_components, tuples = arrays[name]
            problems.check(kind == (vtk.int_type if integer else vtk.double_type),
                           f'{where}: {group} array {name} of VTK type {kind}')
            problems.check(got_components == components, f'{where}: {name} has {got_components} components, expected {components}')
            problems.check(len(tuples) == size, f'{where}: {group} array {name} has {len(tuples)} tuples, expected {size}')
            result[group][name] = [x[0] for x in tuples] if components == 1 else tuples
    every_number = [x for p in points for x in p] + [
        x for group in ('point', 'cell', 'field') for values in result[group].values()
        for v in values for x in (v if isinstance(v, tuple) else (v,))]
    problems.check(all(math.isfinite(x) for x in every_number), f'{where}: a number is not finite')
    return result


def close(a, b, scale):
    return abs(a - b) <= ROUND_OFF * max(scale, 1e-300)


def check_against_tables(where, snapshot, step, path_row, shape_rows, problems):
    """Field data against the path file; points and point data against the shape file's rows of the
    step (None when the shape file does not have it)."""
    problems.check(snapshot['field']['step'] == [step], f'{where}: field step {snapshot["field"]["step"]}, expected {step}')
    got_lambda = snapshot['field']['lambda'][0]
    problems.check(close(got_lambda, path_row['lambda'], max(abs(path_row['lambda']), 1.0)),
                   f'{where}: field lambda {got_lambda!r}, the path file has {path_row["lambda"]!r}')
    point = snapshot['point']
    reactions = point['contact_reaction']
    largest = max([abs(r) for r in reactions] + [abs(path_row['reaction_sum'])])
    problems.check(close(sum(reactions), path_row['reaction_sum'], len(reactions) * largest),
                   f'{where}: sum of contact_reaction {sum(reactions)!r}, path reaction_sum {path_row["reaction_sum"]!r}')
    if shape_rows is None:
        return
    if not problems.check(len(shape_rows) == len(snapshot['points']),
                          f'{where}: {len(snapshot["points"])} points, the shape file has {len(shape_rows)} nodes'):
        return
    scale = max([abs(row[c]) for row in shape_rows for c in ('x0', 'y0', 'ux', 'uy')] + [1.0])
    for i, row in enumerate(shape_rows):
        node = int(row['node'])
        expected_point = (row['x0'] + row['ux'], row['y0'] + row['uy'], 0.0)
        problems.check(all(close(a, b, scale) for a, b in zip(snapshot['points'][i], expected_point)),
                       f'{where}: node {node} at {snapshot["points"][i]}, x0 + u = {expected_point}')
        problems.check(all(close(a, b, scale) for a, b in zip(point['displacement'][i], (row['ux'], row['uy'], 0.0))),
                       f'{where}: node {node} displacement {point["displacement"][i]}, shape ({row["ux"]}, {row["uy"]})')
        problems.check(close(point['rotation'][i], row['rz'], max(abs(row['rz']), 1.0)),
                       f'{where}: node {node} rotation {point["rotation"][i]!r}, shape {row["rz"]!r}')
        problems.check(close(point['contact_reaction'][i], row['reaction'], abs(row['reaction'])),
                       f'{where}: node {node} contact_reaction {point["contact_reaction"][i]!r}, shape {row["reaction"]!r}')
        problems.check(point['node_label'][i] == node, f'{where}: point {i} node_label {point["node_label"][i]}, shape node {node}')


def bedded_cells(snapshot):
    """The cells with an end in contact: on a foundation they carry their share of the bed's distributed
    reaction on the span (docs/contracts.md, STEM.forces), so V is not constant along them and their end
    forces balance the nodes together with that share, not the nodal loads alone."""
    reaction = snapshot['point']['contact_reaction']
    return {c for c, (i, j) in enumerate(snapshot['lines']) if reaction[i] != 0.0 or reaction[j] != 0.0}


def check_cells(where, snapshot, linear, problems):
    """Relations between the cell arrays: the mean moment, V = dM/ds over the chord (cells without a
    bed's share on the span), the labels."""
    cell = snapshot['cell']
    labels = cell['element_label']
    problems.check(all(label > 0 for label in labels) and len(set(labels)) == len(labels),
                   f'{where}: element labels not positive and distinct')
    bedded = bedded_cells(snapshot)
    for c, (i, j) in enumerate(snapshot['lines']):
        start, end = cell['bending_moment_start'][c], cell['bending_moment_end'][c]
        problems.check(close(cell['bending_moment'][c], 0.5 * (start + end), max(abs(start), abs(end))),
                       f'{where}: cell {c}: bending_moment is not the mean of the end moments')
        if c in bedded:
            continue
        length, _ = chord(snapshot, i, j, linear)
        shear = cell['shear_force'][c]
        problems.check(close(shear * length, end - start, max(abs(start), abs(end), abs(shear * length))),
                       f'{where}: cell {c}: shear_force * L = {shear * length!r}, M_end - M_start = {end - start!r}')


def chord(snapshot, i, j, linear):
    """Length and unit vector of the chord from point i to point j: the deformed one, or for a linear
    analysis the initial one (x - u), on which its forces act."""
    a, b = snapshot['points'][i], snapshot['points'][j]
    if linear:
        ua, ub = snapshot['point']['displacement'][i], snapshot['point']['displacement'][j]
        a, b = [x - u for x, u in zip(a, ua)], [x - u for x, u in zip(b, ub)]
    length = math.dist(a, b)
    return length, ((b[0] - a[0]) / length, (b[1] - a[1]) / length)


def check_equilibrium(where, snapshot, loads, linear, force_tolerance, problems):
    """The written N, V and M are in equilibrium with the load lambda * P at every node without a contact
    reaction, in every direction that is free.

    The end forces of a line element (corotational or linear beam-column, Crisfield 1991, vol. 1,
    ch. 7: f = B^T q) are, with e the unit chord from node 1 to node 2 and n = e turned by +90 degrees:
    node 1 (-N e + V n, -M_start), node 2 (N e - V n, M_end) (uniarc_transformation, V = dM/ds). A
    constrained direction has a displacement of exactly 0 and is left out, as are nodes in contact
    (their reaction's direction is not in the files) and the nodes of cells with an end in contact
    (their share of a bed's distributed reaction is not in the files either; bedded_cells). The run converged with a residual of at most
    force_tolerance times its force scale, max(|P|, |lambda P|, sqrt(sum_e |f_e|^2)) (uniarc_path_newton);
    the written numbers add ROUND_OFF of that scale.
    """
    lambda_ = snapshot['field']['lambda'][0]
    labels = snapshot['point']['node_label']
    residual = [[0.0, 0.0, 0.0] for _ in labels]
    cell = snapshot['cell']
    element_size = 0.0
    for c, (i, j) in enumerate(snapshot['lines']):
        _, (ex, ey) = chord(snapshot, i, j, linear)
        nx, ny = -ey, ex
        axial, shear = cell['axial_force'][c], cell['shear_force'][c]
        fx, fy = axial * ex - shear * nx, axial * ey - shear * ny
        forces = ((i, (-fx, -fy, -cell['bending_moment_start'][c])), (j, (fx, fy, cell['bending_moment_end'][c])))
        for node, force in forces:
            for k in range(3):
                residual[node][k] += force[k]
            element_size += sum(f * f for f in force)
    load_size = 0.0
    for i, label in enumerate(labels):
        for k, value in enumerate(loads.get(label, (0.0, 0.0, 0.0))):
            residual[i][k] -= lambda_ * value
            load_size += value * value
    scale = max(math.sqrt(load_size), abs(lambda_) * math.sqrt(load_size), math.sqrt(element_size))
    free = []
    bedded_nodes = {node for c in bedded_cells(snapshot) for node in snapshot['lines'][c]}
    for i, label in enumerate(labels):
        if snapshot['point']['contact_reaction'][i] != 0.0 or i in bedded_nodes:
            continue
        motion = (*snapshot['point']['displacement'][i][:2], snapshot['point']['rotation'][i])
        free += [residual[i][k] for k in range(3) if motion[k] != 0.0]
    if not free:
        return 0
    norm = math.sqrt(sum(r * r for r in free))
    problems.check(norm <= (force_tolerance + ROUND_OFF) * scale,
                   f'{where}: the element forces leave a nodal residual of {norm:.3e} against lambda*P, more than '
                   f'{force_tolerance + ROUND_OFF:.1e} of the force scale {scale:.3e}')
    return len(free)


def check_same(where, legacy, xml, problems):
    """The legacy and the XML file of a snapshot hold the same numbers."""
    problems.check(legacy['points'] == xml['points'], f'{where}: .vtk and .vtp points differ')
    problems.check(legacy['lines'] == xml['lines'], f'{where}: .vtk and .vtp lines differ')
    for group in ('point', 'cell', 'field'):
        for name in xml[group]:
            problems.check(legacy[group].get(name) == xml[group][name], f'{where}: {group} array {name} differs between .vtk and .vtp')


def check_tube(vtk, where, data, problems):
    """ParaView's Tube filter (vtkTubeFilter) on the snapshot: a strip per side and line, with the cell
    arrays carried to the tubes."""
    bounds = data.GetBounds()
    diagonal = math.dist(bounds[0::2], bounds[1::2])
    tube = vtk.Tube()
    tube.SetInputData(data)
    tube.SetRadius(0.01 * diagonal)
    tube.SetNumberOfSides(TUBE_SIDES)
    tube.Update()
    messages = vtk.take_messages()
    problems.check(not messages, f'{where}: the Tube filter reports: {messages[:300]}')
    output = tube.GetOutput()
    lines = data.GetNumberOfLines()
    problems.check(output.GetNumberOfStrips() == TUBE_SIDES * lines and output.GetNumberOfCells() == TUBE_SIDES * lines,
                   f'{where}: the Tube filter made {output.GetNumberOfCells()} cells ({output.GetNumberOfStrips()} strips) '
                   f'of {lines} lines, expected {TUBE_SIDES * lines} strips')
    for name in ('axial_force', 'bending_moment'):
        array = output.GetCellData().GetArray(name)
        if problems.check(array is not None, f'{where}: the tubes have no cell array {name}'):
            source = data.GetCellData().GetArray(name)
            problems.check(sorted({array.GetValue(k) for k in range(array.GetNumberOfTuples())}) ==
                           sorted({source.GetValue(k) for k in range(source.GetNumberOfTuples())}),
                           f'{where}: the tubes carry other {name} values than the lines')


def check_collection(pvd_file, stem, wanted, problems):
    """STEM.pvd lists the .vtp snapshots of the wanted steps, the step number as timestep."""
    try:
        root = ElementTree.parse(pvd_file).getroot()
    except (OSError, ElementTree.ParseError) as failure:
        problems.append(f'{stem}.pvd: {failure}')
        return
    problems.check(root.tag == 'VTKFile' and root.get('type') == 'Collection', f'{stem}.pvd: root is not a Collection VTKFile')
    datasets = root.findall('./Collection/DataSet')
    files = [d.get('file') for d in datasets]
    expected_files = [f'{stem}_{s:04d}.vtp' for s in wanted]
    problems.check(files == expected_files, f'{stem}.pvd lists {files}, expected {expected_files}')
    try:
        times = [float(d.get('timestep')) for d in datasets]
    except (TypeError, ValueError):
        problems.append(f'{stem}.pvd: a DataSet without a numeric timestep')
        return
    problems.check(times == [float(s) for s in wanted], f'{stem}.pvd: timesteps {times}, expected the steps {wanted}')
    problems.check(all(b > a for a, b in zip(times, times[1:])), f'{stem}.pvd: timesteps not strictly increasing')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--every', type=int, default=10)
    parser.add_argument('--linear', action='store_true')
    parser.add_argument('--expect-cell', action='append', default=[])
    parser.add_argument('--expect-contact', action='store_true')
    parser.add_argument('--load', action='append', default=[])
    parser.add_argument('--force-tolerance', type=float, default=1e-8)
    parser.add_argument('--no-vtk', action='store_true')
    args = parser.parse_args()

    vtk = None
    if not args.no_vtk:
        try:
            vtk = Vtk()
        except ImportError as failure:
            print(f'FAIL: {INSTALL_HINT}; {sys.executable}: {failure}')
            return 1

    command, run = run_uniarc(args.uniarc, args.deck, args.out, args.define)
    if run.returncode != 0:
        print(f'FAIL: exit code {run.returncode}: {" ".join(command)}')
        return 1
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    found = {extension: sorted(glob.glob(os.path.join(args.out, '*.' + extension)))
             for extension in ('vtk', 'vtp', 'vtu', 'pvd', 'part')}
    problems = Problems()
    problems.check(not found['part'], 'a .part file is left in the output directory')
    problems.check(not found['vtu'], f'.vtu files written: {found["vtu"]}')
    if args.no_vtk:
        problems.check(not any(found.values()), f'VTK files written without *OUTPUT, VTK: {found}')
        return report(problems)

    path_names, path_rows = read_table(os.path.join(args.out, stem + '.path'))
    path_by_step = {int(row[0]): dict(zip(path_names, row)) for row in path_rows}
    shape_names, shape_rows = read_table(os.path.join(args.out, stem + '.shape'))
    shape_by_step = {}
    for row in shape_rows:
        named = dict(zip(shape_names, row))
        shape_by_step.setdefault(int(named['step']), []).append(named)
    steps = sorted(path_by_step)
    wanted = sorted({steps[0], steps[-1]} | {s for s in steps if s % args.every == 0})

    pvd_file = os.path.join(args.out, stem + '.pvd')
    problems.check(found['pvd'] == [pvd_file], f'pvd files {found["pvd"]}, expected {pvd_file}')
    for extension in ('vtp', 'vtk'):
        expected = [os.path.join(args.out, f'{stem}_{s:04d}.{extension}') for s in wanted]
        problems.check(found[extension] == expected, f'.{extension} snapshots {found[extension]}, expected {expected} '
                       f'(every {args.every})')
    check_collection(pvd_file, stem, wanted, problems)
    if problems:
        return report(problems)
    print(f'VTK {vtk.version}: vtkXMLPolyDataReader, vtkPolyDataReader and vtkTubeFilter')

    loads = {}
    for text in args.load:
        label, values = text.split(':')
        loads[int(label)] = tuple(float(x) for x in values.split(','))
    any_contact = False
    compared = 0
    equations = 0
    for step in wanted:
        where = f'{stem}_{step:04d}'
        read = {}
        for extension in ('vtp', 'vtk'):
            data = read_snapshot(vtk, os.path.join(args.out, f'{where}.{extension}'), problems)
            if data is not None:
                read[extension] = (data, contents(vtk, data, f'{where}.{extension}', problems))
        if len(read) < 2 or problems:
            continue
        snapshot = read['vtp'][1]
        check_same(where, read['vtk'][1], snapshot, problems)
        check_against_tables(where + '.vtp', snapshot, step, path_by_step[step], shape_by_step.get(step), problems)
        compared += step in shape_by_step
        check_cells(where + '.vtp', snapshot, args.linear, problems)
        if loads:
            equations += check_equilibrium(where + '.vtp', snapshot, loads, args.linear, args.force_tolerance,
                                           problems)
        for extension, (data, _) in read.items():
            check_tube(vtk, f'{where}.{extension}', data, problems)
        any_contact = any_contact or max(snapshot['point']['contact_reaction']) > 0.0
        lambda_ = snapshot['field']['lambda'][0]
        for expectation in args.expect_cell:
            array, rest = expectation.split('=', 1)
            value, tolerance = (float(x) for x in rest.split(':'))
            worst = max(abs(x - lambda_ * value) for x in snapshot['cell'][array])
            problems.check(worst <= tolerance, f'{where}: {array} differs from lambda*{value!r} = {lambda_ * value!r} '
                           f'by up to {worst:.3e} > {tolerance:.1e}')
    if args.expect_contact:
        problems.check(any_contact, 'no snapshot has a positive contact reaction')
    print(f'{len(wanted)} snapshots (.vtp and .vtk) read, {compared} of them compared with the shape file; '
          f'{equations} nodal equilibrium equations checked; pvd timesteps = steps {wanted}')
    return report(problems)


def report(problems):
    for problem in problems[:40]:
        print('FAIL: ' + problem)
    if len(problems) > 40:
        print(f'... and {len(problems) - 40} more')
    if not problems:
        print('ok')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
