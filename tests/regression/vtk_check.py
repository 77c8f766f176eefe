#!/usr/bin/env python3
"""Run uniarc on a deck with `*OUTPUT, VTK` and check the ParaView files it writes.

A snapshot is written twice, as legacy `STEM_NNNN.vtk` and as XML `STEM_NNNN.vtu`; `STEM.pvd` lists
the `.vtu` files (ParaView's pvd reader reads XML files only).

Usage (one CTest per call):
  vtk_check.py --uniarc BIN --deck DECK --out DIR [--define NAME=VALUE]...
               --every N                         # the snapshot interval the deck asks for
               [--timestep lambda|step]          # what the pvd must use as its timestep
               [--expect-cell NAME=VALUE:ATOL]...  # every cell of array NAME equals lambda*VALUE
               [--expect-contact]                # some snapshot has a positive contact reaction
               [--no-vtk]                        # the deck has no *OUTPUT: no .vtk and no .pvd

What is checked, from the files alone:
- the snapshots are those of the shape file's rule with EVERY: the first step, every N-th step, the
  last step of the path file, no more and no fewer, and no `.part` file is left;
- STEM.pvd is well-formed XML (xml.etree): a VTKFile of type Collection whose DataSets reference
  the existing .vtu files, with strictly increasing timesteps that are lambda when lambda increases strictly
  over the snapshots and the step numbers otherwise (and --timestep says which this deck must give);
- every STEM_NNNN.vtk is a legacy ASCII UNSTRUCTURED_GRID: header, POINTS n with 3n finite numbers,
  CELLS m 3m of two-point lines with valid point indices, CELL_TYPES m all 3 (VTK_LINE), POINT_DATA n
  with displacement (3-vector), rotation, contact_reaction, node_label, CELL_DATA m with axial_force,
  bending_moment, bending_moment_start, bending_moment_end, element_label, all finite; its field data
  lambda and step match the path file;
- every STEM_NNNN.vtu is well-formed XML (xml.etree), a VTKFile of type UnstructuredGrid with one
  Piece of the same numbers of points and cells, whose Points, Cells (connectivity, offsets, types),
  FieldData, PointData and CellData arrays hold the same numbers as the legacy file;
- the points are the deformed geometry x0 + u of the shape file's snapshot of the same step (for
  the steps the shape file has: always the first and the last), and the point arrays are the shape file's u_x, u_y, rz and reaction; the sum of contact_reaction is the path
  file's reaction_sum; bending_moment is the mean of the two end moments.
If the `vtk` Python module can be imported, each file is also read with vtkUnstructuredGridReader and
its point count, cell count and arrays compared; the script says whether it did.
"""
import argparse
import glob
import math
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uniarc_check import run_uniarc  # noqa: E402

POINT_ARRAYS = {'displacement': 3, 'rotation': 1, 'contact_reaction': 1, 'node_label': 1}
CELL_ARRAYS = {'axial_force': 1, 'bending_moment': 1, 'bending_moment_start': 1, 'bending_moment_end': 1,
               'element_label': 1}

# Every real is written with 13 significant digits (format es21.12e3), so two numbers that are the
# same quantity written by two files (or a sum of two written numbers) agree to a few units of 1e-12
# of the largest magnitude involved.
ROUND_OFF = 1e-11


class Problems(list):
    def check(self, condition, message):
        if not condition:
            self.append(message)
        return condition


def read_table(path):
    """Column names and rows (lists of floats) of a uniarc table file; blank and comment lines are skipped."""
    with open(path) as handle:
        lines = handle.read().splitlines()
    names = lines[0].split()
    rows = [[float(x) for x in line.split()] for line in lines[1:] if line.strip() and not line.startswith('#')]
    return names, rows


def read_legacy_vtk(path, problems):
    """The sections of a legacy ASCII VTK unstructured grid as a dict; structure errors go to problems."""
    with open(path) as handle:
        lines = handle.read().splitlines()
    where = os.path.basename(path)
    data = {'point_data': {}, 'cell_data': {}, 'field': {}}
    if not problems.check(len(lines) >= 5, f'{where}: fewer than 5 lines'):
        return None
    problems.check(re.fullmatch(r'# vtk DataFile Version \d\.\d', lines[0]) is not None,
                   f'{where}: first line {lines[0]!r} is not a legacy VTK header')
    problems.check(0 < len(lines[1]) <= 256, f'{where}: title line empty or longer than 256 characters')
    problems.check(lines[2] == 'ASCII', f'{where}: third line {lines[2]!r}, expected ASCII')
    problems.check(lines[3] == 'DATASET UNSTRUCTURED_GRID', f'{where}: fourth line {lines[3]!r}')
    tokens = ' '.join(lines[4:]).split()
    position = 0

    def take(count, kind=float):
        nonlocal position
        if position + count > len(tokens):
            raise ValueError(f'{where}: file ends inside a section')
        values = [kind(x) for x in tokens[position:position + count]]
        position += count
        return values

    attributes = None   # 'point_data' or 'cell_data' once POINT_DATA / CELL_DATA is seen
    sizes = {}
    try:
        while position < len(tokens):
            keyword = tokens[position]
            position += 1
            if keyword == 'FIELD':
                _, count = tokens[position], int(tokens[position + 1])
                position += 2
                for _ in range(count):
                    name, components, tuples, kind = tokens[position:position + 4]
                    position += 4
                    data['field'][name] = take(int(components) * int(tuples), int if kind == 'int' else float)
            elif keyword == 'POINTS':
                n, kind = int(tokens[position]), tokens[position + 1]
                position += 2
                problems.check(kind == 'double', f'{where}: POINTS of {kind}, expected double')
                data['points'] = take(3 * n)
                sizes['points'] = n
            elif keyword == 'CELLS':
                m, size = int(tokens[position]), int(tokens[position + 1])
                position += 2
                problems.check(size == 3 * m, f'{where}: CELLS {m} {size}, expected size {3 * m} (lines)')
                data['cells'] = take(size, int)
                sizes['cells'] = m
            elif keyword == 'CELL_TYPES':
                m = int(tokens[position])
                position += 1
                data['cell_types'] = take(m, int)
            elif keyword in ('POINT_DATA', 'CELL_DATA'):
                attributes = 'point_data' if keyword == 'POINT_DATA' else 'cell_data'
                data[keyword.lower() + '_size'] = int(tokens[position])
                position += 1
            elif keyword in ('SCALARS', 'VECTORS'):
                if attributes is None:
                    raise ValueError(f'{where}: {keyword} before POINT_DATA or CELL_DATA')
                name, kind = tokens[position], tokens[position + 1]
                position += 2
                components = 3
                if keyword == 'SCALARS':
                    components = int(tokens[position])
                    position += 1
                    if tokens[position] != 'LOOKUP_TABLE':
                        raise ValueError(f'{where}: SCALARS {name} without LOOKUP_TABLE')
                    position += 2
                count = data[attributes + '_size']
                data[attributes][name] = take(components * count, int if kind == 'int' else float)
            else:
                raise ValueError(f'{where}: unexpected keyword {keyword!r}')
    except (ValueError, IndexError) as failure:
        problems.append(str(failure))
        return None
    return data


def check_snapshot(path, data, n, shape_rows, path_row, path_names, problems):
    """Structure, finiteness and agreement with the shape and path files of one snapshot of n nodes;
    shape_rows is None when the shape file has no snapshot of this step."""
    where = os.path.basename(path)
    points = data.get('points', [])
    cells = data.get('cells', [])
    m = len(data.get('cell_types', []))
    problems.check(len(points) == 3 * n, f'{where}: {len(points) // 3} points, the shape file has {n} nodes')
    problems.check(len(cells) == 3 * m, f'{where}: CELLS and CELL_TYPES disagree on the number of cells')
    problems.check(all(t == 3 for t in data.get('cell_types', [])), f'{where}: a cell type other than 3')
    for c in range(len(cells) // 3):
        count, i, j = cells[3 * c:3 * c + 3]
        problems.check(count == 2 and 0 <= i < n and 0 <= j < n and i != j,
                       f'{where}: cell {c} is not a line of two distinct points: {cells[3 * c:3 * c + 3]}')
    problems.check(data.get('point_data_size') == n, f'{where}: POINT_DATA {data.get("point_data_size")}, expected {n}')
    problems.check(data.get('cell_data_size') == m, f'{where}: CELL_DATA {data.get("cell_data_size")}, expected {m}')
    for arrays, group, size in ((POINT_ARRAYS, 'point_data', n), (CELL_ARRAYS, 'cell_data', m)):
        for name, components in arrays.items():
            values = data[group].get(name)
            if problems.check(values is not None, f'{where}: no {group} array {name}'):
                problems.check(len(values) == components * size, f'{where}: {name} has {len(values)} values')
    every_number = points + [x for group in ('point_data', 'cell_data') for a in data[group].values() for x in a]
    problems.check(all(math.isfinite(x) for x in every_number), f'{where}: a number is not finite')
    if problems:
        return

    # Field data against the path file.
    lambda_ = path_row[path_names.index('lambda')]
    step = int(path_row[path_names.index('step')])
    problems.check(data['field'].get('step') == [step], f'{where}: field step {data["field"].get("step")}, expected {step}')
    got_lambda = data['field'].get('lambda', [math.nan])[0]
    problems.check(abs(got_lambda - lambda_) <= ROUND_OFF * max(abs(lambda_), 1.0),
                   f'{where}: field lambda {got_lambda!r}, path file {lambda_!r}')

    cell = data['cell_data']
    for c in range(m):
        mean = 0.5 * (cell['bending_moment_start'][c] + cell['bending_moment_end'][c])
        size = max(abs(cell['bending_moment_start'][c]), abs(cell['bending_moment_end'][c]), 1e-300)
        problems.check(abs(cell['bending_moment'][c] - mean) <= ROUND_OFF * size,
                       f'{where}: cell {c}: bending_moment is not the mean of the end moments')
    if shape_rows is None:
        return

    # Deformed geometry and point arrays against the shape file (columns: step lambda node x0 y0 ux uy
    # rz x y reaction).
    scale = max(max(abs(v) for row in shape_rows for v in row[3:10]), 1.0)
    displacement = data['point_data']['displacement']
    for i, row in enumerate(shape_rows):
        node, x0, y0, ux, uy, rz, reaction = row[2], row[3], row[4], row[5], row[6], row[7], row[10]
        expected = {'x': x0 + ux, 'y': y0 + uy, 'z': 0.0}
        for k, axis in enumerate('xyz'):
            problems.check(abs(points[3 * i + k] - expected[axis]) <= ROUND_OFF * scale,
                           f'{where}: node {node:g} {axis} = {points[3 * i + k]!r}, x0 + u = {expected[axis]!r}')
        for k, value in enumerate((ux, uy, 0.0)):
            problems.check(abs(displacement[3 * i + k] - value) <= ROUND_OFF * scale,
                           f'{where}: node {node:g} displacement[{k}] = {displacement[3 * i + k]!r}, shape {value!r}')
        problems.check(abs(data['point_data']['rotation'][i] - rz) <= ROUND_OFF * max(abs(rz), 1.0),
                       f'{where}: node {node:g} rotation differs from the shape file')
        problems.check(data['point_data']['node_label'][i] == int(node), f'{where}: node label {i} differs')
        problems.check(abs(data['point_data']['contact_reaction'][i] - reaction) <= ROUND_OFF * max(abs(reaction), 1e-300),
                       f'{where}: node {node:g} contact_reaction differs from the shape file')
    reactions = data['point_data']['contact_reaction']
    reaction_sum = path_row[path_names.index('reaction_sum')]
    largest = max([abs(r) for r in reactions] + [abs(reaction_sum)])
    problems.check(abs(sum(reactions) - reaction_sum) <= ROUND_OFF * n * max(largest, 1e-300),
                   f'{where}: sum of contact_reaction {sum(reactions)!r}, path reaction_sum {reaction_sum!r}')


def check_xml_twin(path, data, problems):
    """The .vtu of a snapshot holds the grid and arrays of its legacy file (`data`)."""
    where = os.path.basename(path)
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError) as failure:
        problems.append(f'{where}: {failure}')
        return
    if not problems.check(root.tag == 'VTKFile' and root.get('type') == 'UnstructuredGrid',
                          f'{where}: root is not an UnstructuredGrid VTKFile'):
        return
    pieces = root.findall('./UnstructuredGrid/Piece')
    if not problems.check(len(pieces) == 1, f'{where}: {len(pieces)} Pieces, expected 1'):
        return
    piece = pieces[0]
    n = len(data['points']) // 3
    m = len(data['cell_types'])
    problems.check(piece.get('NumberOfPoints') == str(n) and piece.get('NumberOfCells') == str(m),
                   f'{where}: Piece of {piece.get("NumberOfPoints")} points and {piece.get("NumberOfCells")} cells, '
                   f'the legacy file has {n} and {m}')

    def array(parent, name, components=1):
        found = [a for a in root.findall(f'./UnstructuredGrid/{parent}/DataArray') if a.get('Name') == name]
        if not problems.check(len(found) == 1, f'{where}: {parent} has {len(found)} arrays {name}'):
            return None
        element = found[0]
        problems.check(element.get('format') == 'ascii', f'{where}: {name} is not ascii')
        problems.check(int(element.get('NumberOfComponents', '1')) == components,
                       f'{where}: {name} has {element.get("NumberOfComponents")} components, expected {components}')
        kind = int if element.get('type', '').startswith(('Int', 'UInt')) else float
        return [kind(x) for x in (element.text or '').split()]

    expected = {('Piece/Points', 'points', 3): data['points'],
                ('FieldData', 'lambda', 1): data['field'].get('lambda'),
                ('FieldData', 'step', 1): data['field'].get('step')}
    for name, components in POINT_ARRAYS.items():
        expected[('Piece/PointData', name, components)] = data['point_data'][name]
    for name, components in CELL_ARRAYS.items():
        expected[('Piece/CellData', name, components)] = data['cell_data'][name]
    legacy_cells = data['cells']
    expected[('Piece/Cells', 'connectivity', 1)] = [x for c in range(m) for x in legacy_cells[3 * c + 1:3 * c + 3]]
    expected[('Piece/Cells', 'offsets', 1)] = [2 * (c + 1) for c in range(m)]
    expected[('Piece/Cells', 'types', 1)] = data['cell_types']
    for (parent, name, components), values in expected.items():
        got = array(parent, name, components)
        if got is not None:
            problems.check(got == values, f'{where}: {parent} {name} differs from the legacy file')


def read_with_vtk(vtk_module, path, data, problems):
    """Read one file with VTK's own legacy reader and compare counts and arrays."""
    reader = vtk_module.vtkUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    where = os.path.basename(path)
    problems.check(grid.GetNumberOfPoints() == len(data['points']) // 3, f'{where}: VTK reads another point count')
    problems.check(grid.GetNumberOfCells() == len(data['cell_types']), f'{where}: VTK reads another cell count')
    for name in POINT_ARRAYS:
        problems.check(grid.GetPointData().GetArray(name) is not None, f'{where}: VTK finds no point array {name}')
    for name in CELL_ARRAYS:
        problems.check(grid.GetCellData().GetArray(name) is not None, f'{where}: VTK finds no cell array {name}')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--define', action='append', default=[])
    parser.add_argument('--every', type=int, default=10)
    parser.add_argument('--timestep', choices=('lambda', 'step'))
    parser.add_argument('--expect-cell', action='append', default=[])
    parser.add_argument('--expect-contact', action='store_true')
    parser.add_argument('--no-vtk', action='store_true')
    args = parser.parse_args()

    command, run = run_uniarc(args.uniarc, args.deck, args.out, args.define)
    if run.returncode != 0:
        print(f'FAIL: exit code {run.returncode}: {" ".join(command)}')
        return 1
    stem = os.path.splitext(os.path.basename(args.deck))[0]
    vtk_files = sorted(glob.glob(os.path.join(args.out, '*.vtk')))
    vtu_files = sorted(glob.glob(os.path.join(args.out, '*.vtu')))
    pvd_file = os.path.join(args.out, stem + '.pvd')
    problems = Problems()
    problems.check(not glob.glob(os.path.join(args.out, '*.part')), 'a .part file is left in the output directory')
    if args.no_vtk:
        problems.check(not vtk_files and not vtu_files and not os.path.exists(pvd_file),
                       'VTK files written without *OUTPUT, VTK')
        return report(problems)

    path_names, path_rows = read_table(os.path.join(args.out, stem + '.path'))
    path_by_step = {int(row[0]): row for row in path_rows}
    _, shape_rows = read_table(os.path.join(args.out, stem + '.shape'))
    shape_by_step = {}
    for row in shape_rows:
        shape_by_step.setdefault(int(row[0]), []).append(row)
    steps = [int(row[0]) for row in path_rows]
    wanted = sorted({steps[0], steps[-1]} | {s for s in steps if s % args.every == 0})

    # The collection.
    try:
        root = ElementTree.parse(pvd_file).getroot()
    except (OSError, ElementTree.ParseError) as failure:
        problems.append(f'{stem}.pvd: {failure}')
        return report(problems)
    problems.check(root.tag == 'VTKFile' and root.get('type') == 'Collection', f'{stem}.pvd: root is not a Collection VTKFile')
    datasets = root.findall('./Collection/DataSet')
    files = [d.get('file') for d in datasets]
    times = [float(d.get('timestep')) for d in datasets]
    problems.check(all(b > a for a, b in zip(times, times[1:])), f'{stem}.pvd: timesteps not strictly increasing: {times}')
    referenced = [os.path.join(args.out, f) for f in files]
    problems.check(all(os.path.isfile(f) for f in referenced), f'{stem}.pvd: references missing files')
    problems.check(sorted(referenced) == vtu_files, f'{stem}.pvd lists {files}, the directory has {vtu_files}')
    expected_files = [f'{stem}_{s:04d}.vtu' for s in wanted]
    problems.check(files == expected_files, f'snapshots {files}, expected {expected_files} (every {args.every})')
    legacy = [os.path.join(args.out, f'{stem}_{s:04d}.vtk') for s in wanted]
    problems.check(legacy == vtk_files, f'legacy snapshots {vtk_files}, expected {legacy}')
    if problems:
        return report(problems)
    lambdas = [path_by_step[s][1] for s in wanted]
    by_lambda = all(b > a for a, b in zip(lambdas, lambdas[1:]))
    expected_times = lambdas if by_lambda else [float(s) for s in wanted]
    problems.check(all(abs(t - e) <= ROUND_OFF * max(abs(e), 1.0) for t, e in zip(times, expected_times)),
                   f'{stem}.pvd: timesteps {times}, expected {expected_times}')
    if args.timestep:
        problems.check(args.timestep == ('lambda' if by_lambda else 'step'),
                       f'{stem}.pvd: timestep is the {"lambda" if by_lambda else "step"}, the test expects {args.timestep}')

    try:
        import vtk as vtk_module
    except ImportError:
        vtk_module = None
    print('files parsed by this script' + (' and by vtkUnstructuredGridReader' if vtk_module else
                                           '; the vtk Python module is not available'))

    # The shape file always has the first and the last step; the other snapshots are compared with it
    # where both files have the step (EVERY may differ from the shape file's shape_every).
    n_nodes = len(shape_by_step[steps[0]])
    any_contact = False
    compared = 0
    for step, name, twin in zip(wanted, legacy, referenced):
        data = read_legacy_vtk(name, problems)
        if data is None:
            continue
        check_snapshot(name, data, n_nodes, shape_by_step.get(step), path_by_step[step], path_names, problems)
        compared += step in shape_by_step
        if not problems:
            check_xml_twin(twin, data, problems)
        if problems:
            continue
        any_contact = any_contact or max(data['point_data']['contact_reaction']) > 0.0
        lambda_ = path_by_step[step][1]
        for expectation in args.expect_cell:
            array, rest = expectation.split('=', 1)
            value, tolerance = (float(x) for x in rest.split(':'))
            worst = max(abs(x - lambda_ * value) for x in data['cell_data'][array])
            problems.check(worst <= tolerance, f'{os.path.basename(name)}: {array} differs from '
                           f'lambda*{value!r} = {lambda_ * value!r} by up to {worst:.3e} > {tolerance:.1e}')
        if vtk_module:
            read_with_vtk(vtk_module, name, data, problems)
    if args.expect_contact:
        problems.check(any_contact, 'no snapshot has a positive contact reaction')
    print(f'{len(wanted)} snapshots checked, {compared} of them against the shape file, timestep = {"lambda" if by_lambda else "step"}')
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
